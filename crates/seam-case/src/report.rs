//! The human report of a solved case, as `seam solve` and the built-in
//! examples print it: one line per item ([`report`]), numbers as [`label`]
//! and [`vector`] write them.

use crate::solve::Solved;
use std::path::Path;

/// A vector as "(x, y, z)", 4 significant digits.
pub fn vector(v: [f64; 3]) -> String {
    format!("({})", v.map(label).join(", "))
}

/// The human report of a solved case, one line per item (without indent).
pub fn report(s: &Solved) -> Vec<String> {
    let m = &s.summary;
    let mut lines = Vec::new();
    for (b, body) in m.bodies.iter().enumerate() {
        let mesh =
            Path::new(&body.mesh).file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        lines.push(format!(
            "{:<10} {:<8} {mesh}: {} cells, {} points; E = {}, ν = {}",
            if b == 0 { "bodies" } else { "" },
            body.name,
            body.cells,
            body.points,
            body.young,
            body.poisson
        ));
    }
    let mut contact_interfaces = m.contact.iter().flat_map(|c| &c.interfaces);
    for f in &m.interfaces {
        lines.push(format!(
            "interface  {} (slave: {} faces, {} nodes) → {} (master: {} faces, {} nodes)",
            f.slave,
            f.mortar.slave_faces,
            f.mortar.slave_nodes,
            f.master,
            f.mortar.master_faces,
            f.mortar.master_nodes
        ));
        lines.push(format!(
            "           {} multipliers{}, covered {:.3} %, {} segments, max gap {:.1e}, max overlap {:.1e}",
            f.multiplier,
            if f.slave_space == "enriched" { " (enriched slave space)" } else { "" },
            100.0 * f.covered_fraction,
            f.mortar.segments,
            f.mortar.max_gap,
            f.mortar.max_overlap
        ));
        if let Some(c) = (f.kind == "contact").then(|| contact_interfaces.next()).flatten() {
            lines.push(format!(
                "           contact: {} of {} points active, force {}, max pressure {}",
                c.active_points,
                c.contact_points,
                vector(c.force),
                label(c.max_pressure)
            ));
        }
    }
    if let Some(p) = &m.petsc {
        let iterations: Vec<String> = p.iterations.iter().map(|i| i.to_string()).collect();
        lines.push(format!(
            "petsc      {} + {}, iterations {}, last residual {:.1e}; setup {:.2} s, solve {:.2} s",
            p.ksp_type,
            p.pc_type,
            iterations.join(", "),
            p.residual,
            p.seconds.setup,
            p.seconds.solve
        ));
    }
    match m.contact.as_ref() {
        None => {
            let iterative = m.method.contains("CG") || m.petsc.is_some();
            let steps = match (m.method.starts_with("Newton"), iterative) {
                (true, _) => "Newton iterations",
                (false, true) => "iterations",
                (false, false) => "refinement steps",
            };
            lines.push(format!(
                "system     {} dofs, {} constraints; {}, {} {steps}, residual {:.1e}",
                m.dofs, m.constraints, m.method, m.iterations, m.residual
            ));
        }
        Some(c) => {
            let per_step: Vec<String> = c.steps.iter().map(|s| s.active.to_string()).collect();
            lines.push(format!(
                "system     {} dofs, {} contact points; {}",
                m.dofs, c.contact_points, c.method
            ));
            lines.push(format!(
                "contact    {} active-set step{} (active points per step: {}), {} of {} points active, KKT max {:.1e}",
                c.iterations,
                if c.iterations == 1 { "" } else { "s" },
                per_step.join(", "),
                c.active_points,
                c.contact_points,
                c.kkt.max
            ));
        }
    }
    for body in m.bodies.iter().filter(|b| !b.supported && norm3(b.applied_load) > 0.0) {
        let balance: [f64; 3] = std::array::from_fn(|k| body.applied_load[k] + body.interface_force[k]);
        lines.push(format!(
            "balance    {}: applied load {}, interface force {}, |sum| / |load| {:.1e}",
            body.name,
            vector(body.applied_load),
            vector(body.interface_force),
            norm3(balance) / norm3(body.applied_load)
        ));
    }
    let (b, body) = m
        .bodies
        .iter()
        .enumerate()
        .max_by(|x, y| x.1.max_displacement.total_cmp(&y.1.max_displacement))
        .expect("at least one body");
    let vm = m.bodies.iter().map(|b| b.max_von_mises).fold(0.0, f64::max);
    lines.push(format!(
        "results    max |u| {:.4e} (in {}), max von Mises {:.4e}",
        body.max_displacement, s.problem.bodies[b].name, vm
    ));
    let (t, p) = (&m.seconds, &m.seconds.solver);
    lines.push(format!(
        "seconds    read {:.2}, assembly {:.2}, mortar {:.2}, setup {:.2}, factorization {:.2}, solve {:.2}, \
         stresses {:.2}, output {:.2}, total {:.2} on {} threads",
        t.read, p.assembly, p.mortar, p.setup, p.factorization, p.solve, p.stresses, t.output, t.total, m.threads
    ));
    let mut files: Vec<String> = m.bodies.iter().map(|b| b.file.clone()).collect();
    files.extend(m.interfaces.iter().map(|f| f.file.clone()));
    files.push("summary.json".into());
    lines.push(format!("wrote      {}", files.join(" ")));
    lines
}

fn norm3(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// A number for a colour-bar label, 4 significant digits.
pub fn label(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if (1e-2..1e4).contains(&v.abs()) {
        format!("{v:.4}").trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.3e}")
    }
}
