//! `seam transfer SOURCE TARGET -o OUT.vtu`: flags and the report; the
//! pipeline is [`seam_case::transfer`].

use crate::args::TransferArgs;
use crate::assemble::{options, thread_pool};
use crate::Failure;
use seam_case::transfer::{transfer_files, Summary, Transfer, Values};
use seam_case::Expression;
use std::path::Path;

pub fn run(args: &TransferArgs) -> Result<(), Failure> {
    let options = options(&args.coupling)?;
    let values = match (&args.expr, &args.field) {
        (Some(e), _) => Values::Expression(
            Box::new(Expression::parse(e).map_err(|e| Failure::case(&e))?),
            args.name.clone(),
        ),
        (None, Some(field)) => Values::Field(field.clone()),
        (None, None) => unreachable!("clap requires --field or --expr"),
    };
    let pool = thread_pool(args.coupling.threads)?;
    let transfer = Transfer {
        source: args.source.clone(),
        target: args.target.clone(),
        source_group: args.source_group.clone(),
        target_group: args.target_group.clone(),
        values,
        mode: args.mode,
        options,
        output: args.output.clone(),
        force: args.force,
    };
    let summary = pool.install(|| transfer_files(&transfer))?;
    print_summary(&summary, &args.output);
    Ok(())
}

fn print_summary(s: &Summary, out: &Path) {
    println!(
        "seam transfer: {} ({} component{}) {} → {}, {} mode, {} multipliers",
        s.field,
        s.components,
        if s.components == 1 { "" } else { "s" },
        s.source,
        s.target,
        s.mode,
        s.multiplier
    );
    println!(
        "  target covered {:.4} % ({} uncovered nodes), max gap {:.2e}, max overlap {:.2e}",
        100.0 * s.covered_fraction,
        s.uncovered_target_nodes,
        s.max_gap,
        s.max_overlap
    );
    if let (Some(a), Some(b)) = (&s.total_source, &s.total_target) {
        println!("  total load: source {a:?}, target {b:?}");
    }
    if let (Some(e), Some(r)) = (s.l2_error, s.l2_relative_error) {
        println!("  L2 error against the expression on the target: {e:.3e} (relative {r:.3e})");
    }
    println!("  wrote {} and {}", out.display(), out.with_extension("json").display());
}
