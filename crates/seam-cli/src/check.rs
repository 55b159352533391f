//! `seam check MASTER SLAVE`: how the two surfaces meet, for a person at a
//! terminal (and as JSON/VTU for scripts and ParaView).

use crate::args::CheckArgs;
use crate::assemble::{options, thread_pool};
use crate::Failure;
use anyhow::{anyhow, Context};
use seam_case::input::Surface;
use seam_case::output::Staged;
use seam_case::{Check, CheckError, CheckReport};
use seam_io::Field;
use std::path::PathBuf;

pub fn run(args: &CheckArgs) -> Result<(), Failure> {
    let options = options(&args.coupling)?;
    let pool = thread_pool(args.coupling.threads)?;
    let targets: Vec<PathBuf> = args.vtu.iter().chain(&args.json).cloned().collect();
    let inputs = [args.pair.master.clone(), args.pair.slave.clone()];
    let mut out = Staged::prepare(&targets, &inputs, args.force)?;
    let pair = &args.pair;
    let master = Surface::read(&pair.master, pair.master_group.as_deref())?.mesh;
    let slave = Surface::read(&pair.slave, pair.slave_group.as_deref())?.mesh;
    let names = (pair.master.display().to_string(), pair.slave.display().to_string());
    let Check { report, coverage, normal_gaps } = pool
        .install(|| seam_case::check(&master, &slave, &options, (&names.0, &names.1)))
        .map_err(|e| match e {
            CheckError::Assembly(e) => Failure::from_coupling(e, &pair.slave, &pair.master),
            e => Failure::Error(e.into()),
        })?;
    print_report(&report);
    if let Some(path) = &args.vtu {
        let fields = [Field::scalars("coverage", coverage), Field::scalars("normal_gap", normal_gaps)];
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

fn print_report(r: &CheckReport) {
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
