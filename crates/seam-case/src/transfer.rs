//! The pipeline of `seam transfer SOURCE TARGET -o OUT.vtu`: move a field
//! across the interface, consistently (T, values) or conservatively (Tᵀ,
//! loads), and write the target with the field, `coverage` and `normal_gap`
//! as VTU and a summary as `OUT.json`, all-or-nothing.

use crate::input::{check_finite, Surface};
use crate::output::Staged;
use crate::{Expression, Failure};
use anyhow::{bail, Context};
use seam::{assemble, normal_gaps_from, Mortar, MortarOptions, Multiplier, Named};
use seam_io::Field;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::time::Instant;

/// Values (consistent) or loads (conservative).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Mode {
    /// Values (temperatures, displacements): TARGET is the slave side and gets
    /// T·(source values); constants stay constants.
    #[default]
    Consistent,
    /// Nodal loads (forces, fluxes): SOURCE is the slave side and the loads are
    /// mapped with Tᵀ, so the total is kept exactly.
    Conservative,
}

seam::named!(Mode, "mode", { Consistent => "consistent", Conservative => "conservative" });

/// What is moved.
pub enum Values {
    /// A point field of the source file, by name.
    Field(String),
    /// An expression in x, y, z sampled at the source nodes, and the name of
    /// the field it gives; the summary reports the L2 error against it.
    Expression(Box<Expression>, String),
}

/// A transfer: the two files, what to move, how, and where to write it.
pub struct Transfer {
    /// The surface that carries the field (MSH or VTU).
    pub source: PathBuf,
    /// The surface that receives it (MSH or VTU).
    pub target: PathBuf,
    /// The source's physical surface (MSH only).
    pub source_group: Option<String>,
    /// The target's physical surface (MSH only).
    pub target_group: Option<String>,
    /// What is moved.
    pub values: Values,
    /// Consistent or conservative.
    pub mode: Mode,
    /// The mortar options.
    pub options: MortarOptions,
    /// The VTU output; the summary goes beside it with the extension `.json`.
    pub output: PathBuf,
    /// Replace existing outputs.
    pub force: bool,
}

/// `OUT.json`: what was moved, how well the target is covered, totals and
/// errors. In conservative mode the target is the operator's master: its
/// coverage and gaps are read from B ([`seam::master_side`]), its covered area
/// measured on the source side.
#[derive(Serialize)]
pub struct Summary {
    /// The source file.
    pub source: String,
    /// The target file.
    pub target: String,
    /// The field's name.
    pub field: String,
    /// Its components per node.
    pub components: usize,
    /// "consistent" or "conservative".
    pub mode: &'static str,
    /// The multiplier space.
    pub multiplier: String,
    /// Nodes of the source.
    pub source_nodes: usize,
    /// Nodes of the target.
    pub target_nodes: usize,
    /// Area of the target.
    pub target_area: f64,
    /// Its area covered by the source.
    pub covered_area: f64,
    /// Covered area over target area.
    pub covered_fraction: f64,
    /// Target nodes the source does not cover.
    pub uncovered_target_nodes: usize,
    /// Largest normal gap.
    pub max_gap: f64,
    /// Largest normal overlap.
    pub max_overlap: f64,
    /// Conservative mode: the totals per component before.
    pub total_source: Option<Vec<f64>>,
    /// Conservative mode: the totals per component after.
    pub total_target: Option<Vec<f64>>,
    /// With --expr in consistent mode: ‖T f − f‖ on the covered target, in the
    /// target mass-matrix norm, absolute and relative to ‖f‖.
    pub l2_error: Option<f64>,
    /// The L2 error relative to ‖f‖.
    pub l2_relative_error: Option<f64>,
    /// Wall-clock seconds of the run.
    pub seconds: f64,
    /// Wall-clock seconds per phase.
    pub phases: Phases,
}

/// Seconds per phase of a transfer (they add up to `seconds`, but for the
/// checks of the output paths before reading).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize)]
pub struct Phases {
    /// Reading both files and the values to move.
    pub read: f64,
    /// Search and assembly of B and D (one operator).
    pub assemble: f64,
    /// T = D⁻¹B (explicit when D is diagonal; for standard multipliers D
    /// restricted to the covered points, to solve with).
    pub operator: f64,
    /// T f or Tᵀ f.
    pub apply: f64,
    /// Coverage, normal gaps, the L2 error and the finiteness checks.
    pub diagnostics: f64,
    /// Writing the VTU (the summary follows).
    pub write: f64,
}

/// Laps of the wall clock.
struct Clock(Instant);

impl Clock {
    fn start() -> Clock {
        Clock(Instant::now())
    }

    /// Seconds since the last lap.
    fn lap(&mut self) -> f64 {
        let now = Instant::now();
        let seconds = (now - self.0).as_secs_f64();
        self.0 = now;
        seconds
    }
}

/// What the target's VTU and the summary report of the coupling.
struct TargetView {
    coverage: Vec<f64>,
    /// NaN where not covered.
    gaps: Vec<f64>,
    area: f64,
    covered_area: f64,
    uncovered: usize,
    max_gap: f64,
    max_overlap: f64,
    source_nodes: usize,
    target_nodes: usize,
}

impl TargetView {
    /// The target as the operator's slave: its own coverage, the mortar gaps
    /// n_p·((T x_m)_p − x_p) from `transferred_points` = T x_m, the largest
    /// gap and overlap of the point pairs of the assembly.
    fn of_slave(mortar: &Mortar, target: &Surface, transferred_points: &[f64]) -> TargetView {
        let s = &mortar.summary;
        TargetView {
            coverage: mortar.node_coverage.clone(),
            gaps: normal_gaps_from(&target.mesh, transferred_points, &mortar.covered),
            area: s.slave_area,
            covered_area: s.covered_area,
            uncovered: s.uncovered_slave_nodes,
            max_gap: s.max_gap,
            max_overlap: s.max_overlap,
            source_nodes: s.master_nodes,
            target_nodes: s.slave_nodes,
        }
    }

    /// The target as the operator's master ([`seam::master_side`]): coverage
    /// and gaps from the columns of B, the largest gap and overlap over its
    /// covered nodes.
    fn of_master(mortar: &Mortar, source: &Surface, target: &Surface) -> TargetView {
        let side = seam::master_side(mortar, &source.mesh, &target.mesh);
        let used = target.mesh.used_points();
        let gaps = side.normal_gaps.iter().filter(|g| !g.is_nan());
        let (max_gap, max_overlap) = gaps.fold((0.0f64, 0.0f64), |(a, b), &g| (a.max(g), b.max(-g)));
        TargetView {
            uncovered: (0..used.len()).filter(|&q| used[q] && !side.covered[q]).count(),
            coverage: side.coverage,
            gaps: side.normal_gaps,
            area: side.area,
            covered_area: side.covered_area,
            max_gap,
            max_overlap,
            source_nodes: mortar.summary.slave_nodes,
            target_nodes: mortar.summary.master_nodes,
        }
    }
}

/// Reads, moves, checks and writes (module doc) on the current rayon pool;
/// returns the summary written.
///
/// # Errors
/// [`Failure::NoCoupling`] when the surfaces do not overlap; anything else
/// (unreadable input, a missing field, a non-finite value, an existing output
/// without `force`) is a [`Failure::Error`] naming the file.
pub fn transfer_files(args: &Transfer) -> Result<Summary, Failure> {
    let start = Instant::now();
    let options = args.options;
    let expression = match &args.values {
        Values::Expression(e, _) => Some(&**e),
        Values::Field(_) => None,
    };
    let mut clock = Clock::start();
    let mut phases = Phases::default();
    let summary_path = args.output.with_extension("json");
    let inputs = [args.source.clone(), args.target.clone()];
    let mut out = Staged::prepare(&[args.output.clone(), summary_path.clone()], &inputs, args.force)?;

    let (source, target) = rayon::join(
        || Surface::read(&args.source, args.source_group.as_deref()),
        || Surface::read(&args.target, args.target_group.as_deref()),
    );
    let (source, target) = (source?, target?);
    let (name, k, values) = match &args.values {
        Values::Expression(e, name) => (name.clone(), 1, source.sample(e)?),
        Values::Field(field) => {
            let f = source.field(field)?;
            (f.name.clone(), f.components, f.values.clone())
        }
    };

    phases.read = clock.lap();

    // One operator: TARGET as slave for values (T), SOURCE as slave for loads
    // (Tᵀ moves them onto the target, its master). The target's coverage and
    // normal gaps come from the same operator: its slave side in consistent
    // mode, `master_side` of B in conservative mode.
    let (slave, master, files) = match args.mode {
        Mode::Consistent => (&target, &source, (&args.target, &args.source)),
        Mode::Conservative => (&source, &target, (&args.source, &args.target)),
    };
    let mortar = assemble(&master.mesh, &slave.mesh, &options)
        .map_err(|e| Failure::from_coupling(e, files.0, files.1))?;
    phases.assemble = clock.lap();
    let t = mortar.transfer().context("the transfer operator")?;
    phases.operator = clock.lap();
    // Consistent: the field and the source's points in one application (the
    // points give the target's normal gaps); conservative: no points.
    let (transferred, totals, points) = match args.mode {
        Mode::Consistent => {
            let xs = source.mesh.points();
            let both: Vec<f64> = (0..xs.len())
                .flat_map(|p| values[p * k..(p + 1) * k].iter().chain(&xs[p]))
                .copied()
                .collect();
            let moved = t.apply(&both, k + 3);
            let (field, at): (Vec<_>, Vec<_>) = moved.chunks_exact(k + 3).map(|c| c.split_at(k)).unzip();
            (field.concat(), None, at.concat())
        }
        Mode::Conservative => {
            let moved = t.apply_transpose(&masked(&values, k, &mortar.covered), k);
            let totals = (totals_of(&values, k), totals_of(&moved, k));
            (moved, Some(totals), Vec::new())
        }
    };
    phases.apply = clock.lap();
    let view = match args.mode {
        Mode::Consistent => TargetView::of_slave(&mortar, &target, &points),
        Mode::Conservative => TargetView::of_master(&mortar, &source, &target),
    };
    let (l2_error, l2_relative) = match (&expression, args.mode) {
        (Some(e), Mode::Consistent) => {
            let (err, rel) = l2_error(&mortar, &source, &target, &options, &transferred, e)?;
            (Some(err), Some(rel))
        }
        _ => (None, None),
    };
    // Nothing non-finite is written: the transferred values, the coverage, the
    // gaps where they are defined (NaN marks an uncovered node, documented),
    // and the numbers of the summary.
    check_finite(&transferred, k, &target, "the transferred field")?;
    check_finite(&view.coverage, 1, &target, "the coverage")?;
    let defined: Vec<f64> = view.gaps.iter().map(|&g| if g.is_nan() { 0.0 } else { g }).collect();
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
    phases.diagnostics = clock.lap();

    let point_data = [
        Field::new(name.clone(), k, transferred),
        Field::scalars("coverage", view.coverage),
        Field::scalars("normal_gap", view.gaps),
    ];
    out.write(&args.output, |p| {
        seam_io::write_vtu_file(p, &target.mesh, &point_data, &[]).map_err(std::io::Error::other)
    })?;
    phases.write = clock.lap();
    let summary = Summary {
        source: args.source.display().to_string(),
        target: args.target.display().to_string(),
        field: name,
        components: k,
        mode: args.mode.name(),
        multiplier: options.multiplier.name().to_string(),
        source_nodes: view.source_nodes,
        target_nodes: view.target_nodes,
        target_area: view.area,
        covered_area: view.covered_area,
        covered_fraction: view.covered_area / view.area,
        uncovered_target_nodes: view.uncovered,
        max_gap: view.max_gap,
        max_overlap: view.max_overlap,
        total_source: totals.as_ref().map(|t| t.0.clone()),
        total_target: totals.as_ref().map(|t| t.1.clone()),
        l2_error,
        l2_relative_error: l2_relative,
        seconds: start.elapsed().as_secs_f64(),
        phases,
    };
    let json = serde_json::to_string_pretty(&summary).context("summary")?;
    out.write(&summary_path, |p| std::fs::write(p, json + "\n"))?;
    out.commit(&[])?;
    Ok(summary)
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
