//! `seam assemble MASTER SLAVE -o DIR`: flags and the progress bar; the
//! pipeline (read, search, assemble, write) is [`seam_case::assemble`].

use crate::args::{AssembleArgs, CouplingArgs, PairArgs};
use crate::Failure;
use anyhow::Context;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use seam::{MaxGap, MortarOptions};
use seam_case::assemble::{assemble_files, Assemble, Pair, Progress};
use std::sync::OnceLock;

/// Slave face count from which a progress bar is shown (on a terminal only).
const PROGRESS_FROM: usize = 20_000;

pub fn run(args: &AssembleArgs) -> Result<(), Failure> {
    let pool = thread_pool(args.coupling.threads)?;
    pool.install(|| assemble_files(&job(args)?, &Bar::default()))?;
    Ok(())
}

/// Rank 0 of `mpirun -np N seam assemble` ([`seam_case::ranks`]): the same files.
/// MPI is called from this (the main) thread only; the work runs on rayon's
/// global pool, sized by `--threads`.
#[cfg(feature = "mpi")]
pub fn run_over_ranks(args: &AssembleArgs, ranks: &seam_case::ranks::Ranks) -> Result<(), Failure> {
    let assembler = ranks.assembler();
    let result = global_pool(args.coupling.threads)
        .map_err(Failure::from)
        .and_then(|()| seam_case::assemble::assemble_files_with(&job(args)?, &Bar::default(), &assembler));
    assembler.release();
    result.map(|_| ())
}

/// Sizes rayon's global pool by `--threads` (all cores without it).
#[cfg(feature = "mpi")]
pub fn global_pool(threads: Option<usize>) -> anyhow::Result<()> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        let n = seam_case::threads::check_threads(n).map_err(|e| anyhow::anyhow!("--threads: {e}"))?;
        builder = builder.num_threads(n);
    }
    builder.build_global().context("cannot start the worker threads")
}

fn job(args: &AssembleArgs) -> anyhow::Result<Assemble> {
    Ok(Assemble {
        pair: pair(&args.pair),
        output: args.output.clone(),
        options: options(&args.coupling)?,
        segments: args.segments.clone(),
        force: args.force,
    })
}

/// The two surfaces of the flags.
pub fn pair(p: &PairArgs) -> Pair {
    Pair {
        master: p.master.clone(),
        slave: p.slave.clone(),
        master_group: p.master_group.clone(),
        slave_group: p.slave_group.clone(),
    }
}

pub fn options(args: &CouplingArgs) -> anyhow::Result<MortarOptions> {
    let max_gap = match args.max_gap {
        Some(g) if !(g.is_finite() && g >= 0.0) => {
            anyhow::bail!("--max-gap must be a non-negative length, got {g}")
        }
        Some(g) => MaxGap::Absolute(g),
        None => MaxGap::DEFAULT,
    };
    Ok(MortarOptions {
        multiplier: args.multiplier,
        facing: args.facing,
        max_gap,
        max_angle_degrees: args.max_angle,
        warped_quad_degree: args.quad_order,
        ..MortarOptions::default()
    })
}

/// The worker threads of a run: `--threads` checked against the cores
/// ([`seam_case::threads`]), or all cores.
pub fn thread_pool(threads: Option<usize>) -> anyhow::Result<rayon::ThreadPool> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        let n = seam_case::threads::check_threads(n).map_err(|e| anyhow::anyhow!("--threads: {e}"))?;
        builder = builder.num_threads(n);
    }
    builder.build().context("cannot start the worker threads")
}

/// A progress bar on stderr from [`PROGRESS_FROM`] slave faces on (indicatif
/// draws it on a terminal only).
#[derive(Default)]
struct Bar(OnceLock<ProgressBar>);

impl Progress for Bar {
    fn start(&self, faces: usize) {
        let bar = if faces < PROGRESS_FROM {
            ProgressBar::hidden()
        } else {
            let bar = ProgressBar::with_draw_target(Some(faces as u64), ProgressDrawTarget::stderr());
            bar.set_style(
                ProgressStyle::with_template("{bar:40} {pos}/{len} slave faces, {per_sec}, {eta} left")
                    .expect("valid template"),
            );
            bar
        };
        let _ = self.0.set(bar);
    }

    fn advance(&self, faces: usize) {
        if let Some(bar) = self.0.get() {
            bar.inc(faces as u64);
        }
    }

    fn finish(&self) {
        if let Some(bar) = self.0.get() {
            bar.finish_and_clear();
        }
    }
}
