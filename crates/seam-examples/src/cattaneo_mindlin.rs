//! `seam example cattaneo-mindlin -o DIR`: partial slip against Cattaneo and
//! Mindlin's solution. A half model ([`seam_fem::scene::cattaneo_mindlin`],
//! symmetry plane y = 0) of the Hertz example's indenter (R = 1) and block,
//! both E = 1000, ν = 0.3 (equal materials: the normal and tangential
//! problems decouple), Coulomb friction μ = 0.3: the indenter's top is
//! pressed by P (the force of the contact radius a = 0.04) in one load step,
//! then pushed along x by Q = 0.5 μP in [`SHEAR_STEPS`] steps, the moment of
//! Q about the contact balanced on the top as a rigid holder would. The
//! centre sticks within c = a (1 − Q/μP)^{1/3}, the annulus c < r < a slips.
//! Both bodies are meshed with hexahedra on rings about the pole, refined
//! radially across the band [0.55a, 1.1a] that holds both circles; dual
//! multipliers on the block's top.
//!
//! It writes the meshes and `case.toml`, solves the problem in memory
//! exactly as `seam solve` solves that case (every load step in `steps/`),
//! and compares with Cattaneo–Mindlin:
//!
//! - `cattaneo-mindlin.csv`: per slave node on the symmetry line y = 0 of
//!   the block's top within 2a: x, the contact pressure, seam's tangential
//!   traction along Q, q(|x|) and whether it sticks;
//! - `cattaneo-mindlin.md`: the table "analytic vs seam" of the stick radius
//!   and the contact radius (seam: the radius of the half disc with the area
//!   of the sticking, or active, nodes' weights) and the L2 error of the
//!   tangential traction over the contact nodes; also printed;
//! - `cattaneo-mindlin.png`: the tangential traction along the line, seam's
//!   sticking and slipping nodes over q(r) and the bound μp(r).

use crate::case::{solve_example, Report};
use crate::hertz::{percent, sig};
use crate::picture::{viridis, Chart, Image, Series};
use crate::{Failure, Options};
use anyhow::{anyhow, Context};
use seam_case::report::report;
use seam_case::solve::Solved;
use seam_fem::scene::{cattaneo_mindlin, CattaneoMindlin, Hertz, Layout, PartialSlip};
use std::fmt::Write as _;
use std::path::Path;

/// Slave cells radially across the band [0.55a, 1.1a] of the rings on the
/// block's top ([`seam_fem::scene::Layout::Rings`]).
pub const FINE_CELLS: usize = 8;

/// Load steps of the shear (after the one that presses).
pub const SHEAR_STEPS: usize = 4;

/// Writes the meshes and case, solves, compares with Cattaneo–Mindlin
/// (module doc); returns the report.
///
/// # Errors
/// As [`crate::run`].
pub fn run(args: &Options) -> Result<Vec<String>, Failure> {
    let defaults = CattaneoMindlin::default();
    let params = CattaneoMindlin {
        hertz: Hertz { fine_cells: args.slave_cells.unwrap_or(FINE_CELLS), ..defaults.hertz },
        shear_steps: SHEAR_STEPS,
        ..defaults
    };
    if params.hertz.fine_cells == 0 {
        return Err(anyhow!("--slave-cells must be at least 1").into());
    }
    let dir = &args.output;
    let report = Report::new(dir, "cattaneo-mindlin");
    let problem = cattaneo_mindlin(&params).context("the example's meshes")?;
    let about = [
        "seam example cattaneo-mindlin: a half model of an indenter with a spherical face (R = 1)".to_string(),
        format!(
            "pressed on a block by P/2 = {}, then pushed sideways by Q/2 = {} (mu = {}); Cattaneo-Mindlin: stick radius {}.",
            sig(params.hertz.force() / 2.0),
            sig(params.shear_force() / 2.0),
            params.friction,
            sig(params.stick_radius())
        ),
    ];
    let solved = solve_example(problem, args, &about, &report.paths())?;

    let clock = std::time::Instant::now();
    let reading = params.measure(&solved.problem, &solved.solution);
    let table = table(&params, &reading);
    let text = markdown(&solved, &params, &reading, &table);
    let image = draw(&params, &reading);
    report.write(text, csv_text(&reading), &image, args.force)?;
    let seconds = clock.elapsed().as_secs_f64();
    Ok(report_lines(dir, &params, &solved, &table, seconds))
}

/// The markdown table "analytic vs seam".
fn table(p: &CattaneoMindlin, m: &PartialSlip) -> Vec<String> {
    let h = p.hertz.slave_size();
    let mut lines = vec![
        "| quantity | analytic | seam | error | seam value |".to_string(),
        "|---|---:|---:|---:|---|".to_string(),
    ];
    for (name, analytic, seam, note) in [
        ("stick radius c", p.stick_radius(), m.stick_radius, "√(2 A/π), A the weights of the sticking nodes"),
        (
            "contact radius a",
            p.hertz.contact_radius,
            m.contact_radius,
            "√(2 A/π), A the weights of the active nodes",
        ),
    ] {
        lines.push(format!(
            "| {name} | {} | {} | {} ({:+.2} h) | {note} |",
            sig(analytic),
            sig(seam),
            percent(seam, analytic),
            (seam - analytic) / h
        ));
    }
    lines.push(format!(
        "| tangential traction q | CM | | {:.2} % | ‖t_x − q‖ / ‖q‖ (L2 over the contact nodes) |",
        100.0 * m.traction_error
    ));
    lines
}

/// The slave's mesh in words.
fn meshes(p: &Hertz) -> String {
    let (n, z, h) = (p.fine_cells, p.fine_zone, sig(p.slave_size()));
    match p.layout {
        Layout::Tensor => format!("hexahedra, {n} slave cells across {z}a (h = {h})"),
        Layout::Rings => format!(
            "hexahedra on rings about the pole, {n} slave cells radially across [{}a, {z}a] (h = {h}, a midway \
             between two rings)",
            z / 2.0
        ),
    }
}

/// `cattaneo-mindlin.md`.
fn markdown(s: &Solved, p: &CattaneoMindlin, m: &PartialSlip, table: &[String]) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "# Cattaneo–Mindlin partial slip: analytic vs seam\n");
    let _ = writeln!(
        t,
        "A half model (symmetry plane y = 0): an indenter with a spherical face (R = {}) pressed on a block, both \
         E = {}, ν = {}, by P/2 = {} in one load step, then pushed along x by Q/2 = {} (Q = {} μP, μ = {}) in {} \
         steps; {} multipliers on the block's top (slave); {}; {} dofs. At the end {} contact nodes stick and {} \
         slip.\n",
        p.hertz.radius,
        p.hertz.block.young(),
        p.hertz.block.poisson(),
        sig(p.hertz.force() / 2.0),
        sig(p.shear_force() / 2.0),
        p.shear_ratio,
        p.friction,
        p.shear_steps,
        s.summary.multiplier,
        meshes(&p.hertz),
        s.summary.dofs,
        m.stick,
        m.slip
    );
    for line in table {
        let _ = writeln!(t, "{line}");
    }
    let _ = writeln!(
        t,
        "\nc = a (1 − Q/μP)^(1/3); q(r) = μp₀/a √(a² − r²) for c ≤ r ≤ a and μp₀/a [√(a² − r²) − √(c² − r²)] \
         inside c (Johnson, Contact Mechanics, §7.1)."
    );
    t
}

/// `cattaneo-mindlin.csv`.
fn csv_text(m: &PartialSlip) -> String {
    let mut t = String::from("x,contact_pressure,tangential_traction_x,cattaneo_mindlin,stick\n");
    for a in &m.axis {
        let _ = writeln!(t, "{},{},{},{},{}", a.x, a.pressure, a.traction, a.analytic, u8::from(a.stick));
    }
    t
}

/// q / (μp₀) against x / a on y = 0: Cattaneo–Mindlin's q and the bound μp,
/// seam's sticking and slipping nodes.
fn draw(p: &CattaneoMindlin, m: &PartialSlip) -> Image {
    let (a, scale) = (p.hertz.contact_radius, p.friction * p.hertz.peak_pressure());
    let samples = 800;
    let along = |f: &dyn Fn(f64) -> f64| -> Vec<[f64; 2]> {
        (0..=samples)
            .map(|i| -2.0 + 4.0 * i as f64 / samples as f64)
            .map(|s| [s, f((s * a).abs()) / scale])
            .collect()
    };
    let nodes = |stick: bool| {
        m.axis.iter().filter(|n| n.stick == stick).map(|n| [n.x / a, n.traction / scale]).collect()
    };
    let chart = Chart {
        title: vec![
            "seam example cattaneo-mindlin: tangential traction on y = 0".into(),
            format!(
                "c: Cattaneo-Mindlin {}, seam {} ({}); q: L2 error {:.2} %",
                sig(p.stick_radius()),
                sig(m.stick_radius),
                percent(m.stick_radius, p.stick_radius()),
                100.0 * m.traction_error
            ),
            format!("Q = {} mu P, mu = {}, h = {}", p.shear_ratio, p.friction, sig(p.hertz.slave_size())),
        ],
        x: ("x / a".into(), -2.0, 2.0),
        y: ("q / (mu p0)".into(), 0.0, 1.2),
        curves: vec![
            Series {
                label: "Cattaneo-Mindlin q(r)".into(),
                color: [20, 20, 20],
                points: along(&|r| p.traction(r)),
            },
            Series {
                label: "mu p(r) (Hertz)".into(),
                color: [160, 160, 160],
                points: along(&|r| p.friction * p.hertz.pressure(r)),
            },
        ],
        markers: vec![
            Series { label: "seam, sticking nodes".into(), color: viridis(0.35), points: nodes(true) },
            Series {
                label: "seam, slipping or free nodes".into(),
                color: [240, 140, 20],
                points: nodes(false),
            },
        ],
    };
    let mut image = Image::new(1000, 680, [255, 255, 255]);
    image.chart(0, 0, 1000, 680, &chart);
    image
}

fn report_lines(
    dir: &Path,
    p: &CattaneoMindlin,
    s: &Solved,
    table: &[String],
    picture_seconds: f64,
) -> Vec<String> {
    let mut lines = vec![format!("seam example cattaneo-mindlin → {}", dir.display())];
    lines.push(format!(
        "  model      half: indenter (sphere R = {}) on a block, E = {}, ν = {}, μ = {}; P/2 = {}, then Q/2 = {} in {} steps",
        p.hertz.radius,
        p.hertz.block.young(),
        p.hertz.block.poisson(),
        p.friction,
        sig(p.hertz.force() / 2.0),
        sig(p.shear_force() / 2.0),
        p.shear_steps
    ));
    lines.push(format!(
        "  meshes     indenter.msh, block.msh: {}, master {}× finer",
        meshes(&p.hertz),
        p.hertz.master_ratio
    ));
    lines.extend(report(s).into_iter().map(|line| format!("  {line}")));
    lines.push("  Cattaneo–Mindlin analytic vs seam (cattaneo-mindlin.md):".to_string());
    lines.extend(table.iter().map(|line| format!("    {line}")));
    lines.push(format!(
        "  wrote      cattaneo-mindlin.csv cattaneo-mindlin.md cattaneo-mindlin.png ({picture_seconds:.2} s)"
    ));
    lines.push(format!("  rerun      seam solve {} --force", dir.join("case.toml").display()));
    lines
}
