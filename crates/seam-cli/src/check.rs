//! `seam check MASTER SLAVE`: how the two surfaces meet, for a person at a
//! terminal (and as JSON/VTU for scripts and ParaView). Flags and the
//! printed report; the pipeline is [`seam_case::check::check_files`].

use crate::args::CheckArgs;
use crate::assemble::{options, pair, thread_pool};
use crate::Failure;
use seam_case::check::{check_files, CheckFiles, ELEMENT_FACE_TAGS};
use seam_case::{CheckReport, Invariant};

pub fn run(args: &CheckArgs) -> Result<(), Failure> {
    let options = options(&args.coupling)?;
    let pool = thread_pool(args.coupling.threads)?;
    let files = CheckFiles {
        pair: pair(&args.pair),
        options,
        vtu: args.vtu.clone(),
        json: args.json.clone(),
        force: args.force,
    };
    let checked = pool.install(|| check_files(&files))?;
    print_report(&checked.report);
    let report = checked.write()?;
    if args.strict && !report.ok {
        let (slave, master) = (args.pair.slave.display(), args.pair.master.display());
        let violated: Vec<String> = report
            .invariants
            .iter()
            .filter(|i| !i.ok)
            .map(|i| match offending(&report, i) {
                Some(place) => format!("{} at {place}", i.name),
                None => i.name.to_string(),
            })
            .collect();
        let reason = match (report.uncovered_slave_nodes, violated.is_empty()) {
            (0, _) => format!("violated: {}", violated.join("; ")),
            (n, true) => format!("{n} uncovered slave nodes"),
            (n, false) => format!("{n} uncovered slave nodes; violated: {}", violated.join("; ")),
        };
        return Err(Failure::CheckFailed(format!("{slave} and {master}: {reason} (--strict)")));
    }
    Ok(())
}

/// Where a violated invariant fails, "slave faces (Gmsh element tags) 11,
/// 12; slave nodes (1-based rows) 19, 20" (element faces of an `.inp` or
/// Exodus file: "slave faces element 7 face S2, element 8 face S2"), or
/// `None` when nothing is named.
fn offending(r: &CheckReport, i: &Invariant) -> Option<String> {
    let list = |v: Vec<String>| v.join(", ");
    let mut parts = Vec::new();
    if !i.offending_faces.is_empty() {
        if r.face_ids == ELEMENT_FACE_TAGS {
            let faces = list(i.offending_faces.iter().map(|&t| seam_io::abaqus::element_label(t)).collect());
            parts.push(format!("slave faces {faces}"));
        } else {
            let faces = list(i.offending_faces.iter().map(u64::to_string).collect());
            parts.push(format!("slave faces ({}) {faces}", r.face_ids));
        }
    }
    if !i.offending_nodes.is_empty() {
        let nodes = list(i.offending_nodes.iter().map(usize::to_string).collect());
        parts.push(format!("slave nodes (1-based rows) {nodes}"));
    }
    (!parts.is_empty()).then(|| parts.join("; "))
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
            "    {:<56} {:9.1e}  (≤ {:.0e}) {}",
            i.name,
            i.value,
            i.tolerance,
            if i.ok { "ok" } else { "VIOLATED" }
        );
        if let Some(place) = offending(r, i) {
            println!("        at {place}");
        }
    }
    let violated = r.invariants.iter().any(|i| !i.ok);
    let verdict = match (r.uncovered_slave_nodes > 0, violated) {
        (false, false) => "ok",
        (true, false) => "incomplete coverage",
        (false, true) => "violated invariants",
        (true, true) => "incomplete coverage and violated invariants",
    };
    println!("  verdict      {verdict}");
}
