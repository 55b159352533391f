//! `seam check MASTER SLAVE`: how the two surfaces meet, for a person at a
//! terminal (and as JSON/VTU for scripts and ParaView).

use crate::args::CheckArgs;
use crate::assemble::{options, thread_pool};
use crate::input::Surface;
use crate::output::Staged;
use crate::Failure;
use anyhow::{anyhow, Context};
use seam::{
    assemble, face_integrals, face_quality, normal_gaps, orientation_conflicts, warped_quad_degree,
    FaceElement, Mortar, SurfaceMesh,
};
use seam_io::Field;
use serde::Serialize;
use std::path::PathBuf;

/// Tolerance of the invariant checks: "exact" in DESIGN.md §2.
const EXACT: f64 = 1e-13;

#[derive(Serialize)]
struct Report {
    master: String,
    slave: String,
    slave_faces: usize,
    master_faces: usize,
    slave_area: f64,
    master_area: f64,
    covered_area: f64,
    covered_fraction: f64,
    uncovered_slave_nodes: usize,
    /// Up to five uncovered slave nodes: (1-based row, coordinates).
    uncovered_examples: Vec<(usize, [f64; 3])>,
    gap_histogram: Vec<Bin>,
    min_normal_gap: f64,
    max_normal_gap: f64,
    slave_orientation_conflicts: usize,
    master_orientation_conflicts: usize,
    slave_quality: Quality,
    master_quality: Quality,
    invariants: Vec<Invariant>,
    ok: bool,
}

#[derive(Serialize)]
struct Bin {
    from: f64,
    to: f64,
    nodes: usize,
}

#[derive(Serialize)]
struct Quality {
    min_angle_degrees: f64,
    max_angle_degrees: f64,
    max_warp: f64,
}

#[derive(Serialize)]
struct Invariant {
    name: &'static str,
    value: f64,
    tolerance: f64,
    ok: bool,
}

pub fn run(args: &CheckArgs) -> Result<(), Failure> {
    let options = options(&args.coupling)?;
    let pool = thread_pool(args.coupling.threads)?;
    let targets: Vec<PathBuf> = args.vtu.iter().chain(&args.json).cloned().collect();
    let inputs = [args.pair.master.clone(), args.pair.slave.clone()];
    let mut out = Staged::prepare(&targets, &inputs, args.force)?;
    let pair = &args.pair;
    let master = Surface::read(&pair.master, pair.master_group.as_deref())?.mesh;
    let slave = Surface::read(&pair.slave, pair.slave_group.as_deref())?.mesh;
    let mortar = pool
        .install(|| assemble(&master, &slave, &options))
        .map_err(|e| Failure::from_coupling(e, &pair.slave, &pair.master))?;
    let transfer = mortar.transfer().context("the transfer operator")?;
    let gaps = normal_gaps(&slave, &master, &transfer, &mortar.covered);
    let report = report(args, &master, &slave, &mortar, &transfer, &gaps);
    print_report(&report);
    if let Some(path) = &args.vtu {
        let fields =
            [Field::scalars("coverage", mortar.node_coverage.clone()), Field::scalars("normal_gap", gaps)];
        out.write(path, |p| seam_io::write_vtu_file(p, &slave, &fields, &[]).map_err(std::io::Error::other))?;
    }
    if let Some(path) = &args.json {
        let json = serde_json::to_string_pretty(&report).context("report")?;
        out.write(path, |p| std::fs::write(p, json + "\n"))?;
    }
    out.commit(&[])?;
    if args.strict && !report.ok {
        return Err(Failure::CheckFailed(anyhow!(
            "{} and {}: incomplete coverage or a violated invariant (--strict)",
            args.pair.slave.display(),
            args.pair.master.display()
        )));
    }
    Ok(())
}

fn report(
    args: &CheckArgs,
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    m: &Mortar,
    t: &seam::Transfer,
    gaps: &[f64],
) -> Report {
    let s = &m.summary;
    let uncovered = m.uncovered_nodes();
    let invariants = invariants(m, t, master);
    let finite: Vec<f64> = gaps.iter().copied().filter(|g| g.is_finite()).collect();
    let (lo, hi) = finite.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &g| (a.min(g), b.max(g)));
    Report {
        master: args.pair.master.display().to_string(),
        slave: args.pair.slave.display().to_string(),
        slave_faces: s.slave_faces,
        master_faces: s.master_faces,
        slave_area: s.slave_area,
        master_area: area(master),
        covered_area: s.covered_area,
        covered_fraction: s.covered_area / s.slave_area,
        uncovered_slave_nodes: uncovered.len(),
        uncovered_examples: uncovered.iter().take(5).map(|&p| (p + 1, slave.points()[p])).collect(),
        gap_histogram: histogram(&finite, lo, hi, 10),
        min_normal_gap: lo,
        max_normal_gap: hi,
        slave_orientation_conflicts: orientation_conflicts(slave),
        master_orientation_conflicts: orientation_conflicts(master),
        slave_quality: quality(slave),
        master_quality: quality(master),
        ok: uncovered.is_empty() && invariants.iter().all(|i| i.ok),
        invariants,
    }
}

/// I1 and I2 measured on the assembled operator.
fn invariants(m: &Mortar, t: &seam::Transfer, master: &SurfaceMesh) -> Vec<Invariant> {
    let (d1, b1) = (m.d.row_sums(), m.b.row_sums());
    let scale = d1.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(f64::MIN_POSITIVE);
    let i1 = d1.iter().zip(&b1).map(|(d, b)| (d - b).abs()).fold(0.0, f64::max) / scale;
    let area = m.summary.covered_area.max(f64::MIN_POSITIVE);
    let i2 = (m.d.sum() - area).abs().max((m.b.sum() - area).abs()) / area;
    let t1 = t.apply(&vec![1.0; master.n_points()], 1);
    let ones = (0..t1.len()).filter(|&p| m.covered[p]).map(|p| (t1[p] - 1.0).abs()).fold(0.0, f64::max);
    let check = |name, value: f64, tolerance| Invariant { name, value, tolerance, ok: value <= tolerance };
    vec![
        check("I1 max |D·1 − B·1| / max D·1", i1, EXACT),
        check("I2 |1ᵀD1 − covered area| / covered area", i2, EXACT),
        check("I1 max |T·1 − 1| on covered nodes", ones, 1e-12),
    ]
}

fn area(mesh: &SurfaceMesh) -> f64 {
    (0..mesh.n_faces())
        .map(|f| {
            let e = FaceElement::of(mesh, f);
            let degree = if e.is_planar() { 5 } else { warped_quad_degree(&e) };
            face_integrals(&e, degree).iter().sum::<f64>()
        })
        .sum()
}

fn quality(mesh: &SurfaceMesh) -> Quality {
    let q = face_quality(mesh);
    Quality {
        min_angle_degrees: q.iter().map(|f| f.min_angle_degrees).fold(f64::INFINITY, f64::min),
        max_angle_degrees: q.iter().map(|f| f.max_angle_degrees).fold(0.0, f64::max),
        max_warp: q.iter().map(|f| f.warp).fold(0.0, f64::max),
    }
}

fn histogram(values: &[f64], lo: f64, hi: f64, bins: usize) -> Vec<Bin> {
    if values.is_empty() {
        return Vec::new();
    }
    let width = if hi > lo { (hi - lo) / bins as f64 } else { 1.0 };
    let mut counts = vec![0usize; bins];
    for &v in values {
        counts[(((v - lo) / width) as usize).min(bins - 1)] += 1;
    }
    counts
        .into_iter()
        .enumerate()
        .map(|(i, n)| Bin { from: lo + i as f64 * width, to: lo + (i + 1) as f64 * width, nodes: n })
        .collect()
}

fn print_report(r: &Report) {
    println!(
        "seam check: slave {} ({} faces) against master {} ({} faces)",
        r.slave, r.slave_faces, r.master, r.master_faces
    );
    println!(
        "  area         slave {:.6}, master {:.6}, covered {:.6} ({:.4} % of the slave)",
        r.slave_area,
        r.master_area,
        r.covered_area,
        100.0 * r.covered_fraction
    );
    print!("  uncovered    {} slave nodes", r.uncovered_slave_nodes);
    for (row, p) in &r.uncovered_examples {
        print!("; node {row} at ({:.4}, {:.4}, {:.4})", p[0], p[1], p[2]);
    }
    println!();
    println!(
        "  normal gap   from {:.3e} to {:.3e} (positive: gap, negative: overlap), per slave node:",
        r.min_normal_gap, r.max_normal_gap
    );
    let most = r.gap_histogram.iter().map(|b| b.nodes).max().unwrap_or(1).max(1);
    for b in &r.gap_histogram {
        let bar = "#".repeat((40 * b.nodes).div_ceil(most));
        println!("      [{:>10.3e}, {:>10.3e})  {:>7}  {bar}", b.from, b.to, b.nodes);
    }
    let orientation = |n: usize| {
        if n == 0 {
            "consistent".to_string()
        } else {
            format!("{n} edges with flipped neighbours")
        }
    };
    println!(
        "  orientation  slave {}; master {}",
        orientation(r.slave_orientation_conflicts),
        orientation(r.master_orientation_conflicts)
    );
    for (name, q) in [("slave", &r.slave_quality), ("master", &r.master_quality)] {
        println!(
            "  quality      {name:<6} angles {:.1}° to {:.1}°, max warp {:.3e}",
            q.min_angle_degrees, q.max_angle_degrees, q.max_warp
        );
    }
    println!("  invariants (measured on the assembled operator):");
    for i in &r.invariants {
        println!(
            "    {:<46} {:9.1e}  (≤ {:.0e}) {}",
            i.name,
            i.value,
            i.tolerance,
            if i.ok { "ok" } else { "VIOLATED" }
        );
    }
    println!("  verdict      {}", if r.ok { "ok" } else { "incomplete coverage or a violated invariant" });
}
