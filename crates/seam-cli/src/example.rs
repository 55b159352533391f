//! `seam example NAME -o DIR`: the built-in examples of [`seam_examples`],
//! run on `--threads` worker threads, their report printed.

use crate::args::{ExampleArgs, ExampleName};
use crate::assemble::thread_pool;
use crate::Failure;
use seam_examples::{Example, Options};

pub fn run(args: &ExampleArgs) -> Result<(), Failure> {
    let example = match args.name {
        ExampleName::Operator => Example::Operator,
        ExampleName::WarpedGlue => Example::WarpedGlue,
        ExampleName::BulgingContact => Example::BulgingContact,
        ExampleName::Hertz => Example::Hertz,
        ExampleName::CattaneoMindlin => Example::CattaneoMindlin,
        ExampleName::Ironing => Example::Ironing,
    };
    let options = Options {
        output: args.output.clone(),
        force: args.force,
        ratio: args.ratio,
        slave_cells: args.slave_cells,
        order: args.order,
    };
    let pool = thread_pool(args.threads)?;
    for line in pool.install(|| seam_examples::run(example, &options))? {
        println!("{line}");
    }
    Ok(())
}
