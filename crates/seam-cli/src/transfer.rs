//! `seam transfer SOURCE TARGET -o OUT.vtu`: move a field across the interface,
//! consistently (T, values) or conservatively (Tᵀ, loads).

use crate::args::{ModeArg, TransferArgs};
use crate::assemble::{options, thread_pool};
use crate::input::{check_finite, Surface};
use crate::Failure;
use anyhow::{bail, Context};
use seam::{assemble, normal_gaps, Mortar, MortarOptions, Multiplier, SurfaceMesh};
use seam_case::output::Staged;
use seam_case::Expression;
use seam_io::Field;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `OUT.json`.
#[derive(Serialize)]
struct Summary {
    source: String,
    target: String,
    field: String,
    components: usize,
    mode: &'static str,
    multiplier: String,
    source_nodes: usize,
    target_nodes: usize,
    target_area: f64,
    covered_area: f64,
    covered_fraction: f64,
    uncovered_target_nodes: usize,
    max_gap: f64,
    max_overlap: f64,
    /// Conservative mode: the totals per component before and after.
    total_source: Option<Vec<f64>>,
    total_target: Option<Vec<f64>>,
    /// With --expr in consistent mode: ‖T f − f‖ on the covered target, in the
    /// target mass-matrix norm, absolute and relative to ‖f‖.
    l2_error: Option<f64>,
    l2_relative_error: Option<f64>,
    seconds: f64,
}

pub fn run(args: &TransferArgs) -> Result<(), Failure> {
    let start = Instant::now();
    let options = options(&args.coupling)?;
    let expression = args.expr.as_deref().map(Expression::parse).transpose()?;
    let pool = thread_pool(args.coupling.threads)?;
    let summary_path = args.output.with_extension("json");
    let inputs = [args.source.clone(), args.target.clone()];
    let mut out = Staged::prepare(&[args.output.clone(), summary_path.clone()], &inputs, args.force)?;

    let (source, target) = pool.install(|| {
        rayon::join(
            || Surface::read(&args.source, args.source_group.as_deref()),
            || Surface::read(&args.target, args.target_group.as_deref()),
        )
    });
    let (source, target) = (source?, target?);
    let (name, k, values) = match (&expression, &args.field) {
        (Some(e), _) => (args.name.clone(), 1, source.sample(e)?),
        (None, Some(field)) => {
            let f = source.field(field)?;
            (f.name.clone(), f.components, f.values.clone())
        }
        (None, None) => unreachable!("clap requires --field or --expr"),
    };

    // The consistent operator (TARGET as slave) gives the field in consistent
    // mode, and the coverage and normal gaps of the target in both modes.
    let couple =
        |master: &SurfaceMesh, slave: &SurfaceMesh, o: &MortarOptions, which: (&PathBuf, &PathBuf)| {
            pool.install(|| assemble(master, slave, o))
                .map_err(|e| Failure::from_coupling(e, which.0, which.1))
        };
    let consistent = couple(&source.mesh, &target.mesh, &options, (&args.target, &args.source))?;
    let t = consistent.transfer().context("the transfer operator")?;
    let (transferred, totals) = match args.mode {
        ModeArg::Consistent => (t.apply(&values, k), None),
        ModeArg::Conservative => {
            let reverse = couple(&target.mesh, &source.mesh, &options, (&args.source, &args.target))?;
            let loads = masked(&values, k, &reverse.covered);
            let moved = reverse.transfer().context("the transfer operator")?.apply_transpose(&loads, k);
            (moved.clone(), Some((totals_of(&values, k), totals_of(&moved, k))))
        }
    };
    let gaps = normal_gaps(&target.mesh, &source.mesh, &t, &consistent.covered);
    let (l2_error, l2_relative) = match (&expression, args.mode) {
        (Some(e), ModeArg::Consistent) => {
            let (err, rel) = l2_error(&consistent, &source, &target, &options, &transferred, e)?;
            (Some(err), Some(rel))
        }
        _ => (None, None),
    };
    // Nothing non-finite is written: the transferred values, the coverage, the
    // gaps where they are defined (NaN marks an uncovered node, documented),
    // and the numbers of the summary.
    check_finite(&transferred, k, &target, "the transferred field")?;
    check_finite(&consistent.node_coverage, 1, &target, "the coverage")?;
    let defined: Vec<f64> =
        gaps.iter().zip(&consistent.covered).map(|(&g, &c)| if c { g } else { 0.0 }).collect();
    check_finite(&defined, 1, &target, "the normal gap")?;
    if let Some((before, after)) = &totals {
        if before.iter().chain(after).any(|t| !t.is_finite()) {
            let e = anyhow::anyhow!(
                "{}: the total load overflows (sum of the field '{name}')",
                args.source.display()
            );
            return Err(e.into());
        }
    }

    let point_data = [
        Field::new(name.clone(), k, transferred),
        Field::scalars("coverage", consistent.node_coverage.clone()),
        Field::scalars("normal_gap", gaps),
    ];
    out.write(&args.output, |p| {
        seam_io::write_vtu_file(p, &target.mesh, &point_data, &[]).map_err(std::io::Error::other)
    })?;
    let s = &consistent.summary;
    let summary = Summary {
        source: args.source.display().to_string(),
        target: args.target.display().to_string(),
        field: name,
        components: k,
        mode: match args.mode {
            ModeArg::Consistent => "consistent",
            ModeArg::Conservative => "conservative",
        },
        multiplier: format!("{:?}", options.multiplier).to_lowercase(),
        source_nodes: s.master_nodes,
        target_nodes: s.slave_nodes,
        target_area: s.slave_area,
        covered_area: s.covered_area,
        covered_fraction: s.covered_area / s.slave_area,
        uncovered_target_nodes: s.uncovered_slave_nodes,
        max_gap: s.max_gap,
        max_overlap: s.max_overlap,
        total_source: totals.as_ref().map(|t| t.0.clone()),
        total_target: totals.as_ref().map(|t| t.1.clone()),
        l2_error,
        l2_relative_error: l2_relative,
        seconds: start.elapsed().as_secs_f64(),
    };
    let json = serde_json::to_string_pretty(&summary).context("summary")?;
    out.write(&summary_path, |p| std::fs::write(p, json + "\n"))?;
    out.commit(&[])?;
    print_summary(&summary, &args.output);
    Ok(())
}

/// The loads on covered nodes only: Tᵀ moves what the covered part carries.
fn masked(values: &[f64], k: usize, covered: &[bool]) -> Vec<f64> {
    values.iter().enumerate().map(|(i, &v)| if covered[i / k] { v } else { 0.0 }).collect()
}

fn totals_of(values: &[f64], k: usize) -> Vec<f64> {
    (0..k).map(|c| values.iter().skip(c).step_by(k).sum()).collect()
}

/// ‖T f − f‖ on the covered target nodes in the target mass-matrix norm (the
/// standard D), absolute and relative to ‖f‖ there.
fn l2_error(
    consistent: &Mortar,
    source: &Surface,
    target: &Surface,
    options: &MortarOptions,
    transferred: &[f64],
    e: &Expression,
) -> anyhow::Result<(f64, f64)> {
    let standard;
    let mass = if consistent.multiplier == Multiplier::Standard {
        &consistent.d
    } else {
        let o = MortarOptions { multiplier: Multiplier::Standard, ..*options };
        standard = assemble(&source.mesh, &target.mesh, &o)?;
        &standard.d
    };
    let exact = target.sample(e)?;
    let covered = |p: usize| if consistent.covered[p] { 1.0 } else { 0.0 };
    let err: Vec<f64> = (0..exact.len()).map(|p| covered(p) * (transferred[p] - exact[p])).collect();
    let f: Vec<f64> = (0..exact.len()).map(|p| covered(p) * exact[p]).collect();
    // vᵀDv ≥ 0 for the mass matrix D; a tiny negative value is round-off, a
    // non-finite one an overflow, reported rather than turned into 0.
    let norm = |v: &[f64], what: &str| -> anyhow::Result<f64> {
        let squared: f64 = v.iter().zip(mass.mul_vec(v, 1)).map(|(a, b)| a * b).sum();
        if !squared.is_finite() {
            bail!("{}: the L2 norm of {what} is not finite (an overflow)", target.path.display());
        }
        Ok(squared.max(0.0).sqrt())
    };
    let (a, b) = (norm(&err, "the error")?, norm(&f, "the expression")?);
    Ok((a, if b > 0.0 { a / b } else { a }))
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
