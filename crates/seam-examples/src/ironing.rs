//! `seam example ironing -o DIR`: finite deformation with large sliding (after
//! Puso & Laursen 2004). A neo-Hookean indenter with a cylindrical face
//! (E = 1000) is pressed 0.1 into a softer neo-Hookean slab (E = 100) over the
//! first fifth of the pseudo-time, then slid 3 along it
//! ([`seam_fem::scene::ironing`]), once frictionless and once with μ = 0.3.
//!
//! It writes each run as a case with its results (`DIR/frictionless/` and
//! `DIR/friction/`, rerun with `seam solve DIR/friction/case.toml --force`) and:
//!
//! - `ironing.csv`: per load step of both runs, t and the contact force the
//!   slab exerts on the indenter (F_x, F_y, F_z: the reaction its top carries,
//!   with the opposite sign);
//! - `ironing.md`: the forces over the steps, Newton's iterations, and the
//!   ratio F_x / F_z while sliding against μ;
//! - `ironing.png`: F_z and F_x / F_z over the pseudo-time for both runs, and
//!   the cut y = 1 through the deformed bodies at the end of the run with
//!   friction, coloured by the von Mises stress (true scale).

use crate::case::{solve_example, Report};
use crate::picture::{add_cut, Chart, Image, Plot, Series};
use crate::{Failure, Options};
use anyhow::{anyhow, bail, Context};
use seam_case::solve::Solved;
use seam_fem::scene::{ironing, Ironing};
use std::fmt::Write as _;
use std::path::Path;

/// Indenter cells across (the slab has 4 per unit length, 24 along it).
pub const INDENTER_CELLS: usize = 8;

/// Coulomb's μ of the run with friction.
pub const FRICTION: f64 = 0.3;

/// The cut through the bodies' middle.
const CUT: f64 = 1.0;

/// One run: its μ, its directory's name and its solution.
struct Run {
    friction: f64,
    name: &'static str,
    solved: Solved,
}

impl Run {
    /// (t, F) per load step.
    fn forces(&self) -> Vec<(f64, [f64; 3])> {
        self.solved.summary.steps.iter().map(|s| (s.time, s.forces[0])).collect()
    }

    /// Newton iterations over all steps.
    fn iterations(&self) -> usize {
        self.solved.summary.steps.iter().map(|s| s.iterations).sum()
    }
}

/// Writes both cases, solves them, writes the comparison (module doc);
/// returns the report.
///
/// # Errors
/// As [`crate::run`].
pub fn run(args: &Options) -> Result<Vec<String>, Failure> {
    let cells = args.slave_cells.unwrap_or(INDENTER_CELLS);
    if cells < 2 || cells % 2 != 0 {
        return Err(
            anyhow!("--slave-cells must be even and at least 2 (the cut y = 1 is a grid plane)").into()
        );
    }
    let dir = &args.output;
    let report = Report::new(dir, "ironing");
    let clock = std::time::Instant::now();
    let mut runs = Vec::new();
    for (friction, name) in [(0.0, "frictionless"), (FRICTION, "friction")] {
        let params =
            Ironing { indenter_cells: cells, cells: (cells / 2).max(2), friction, ..Ironing::default() };
        let problem = ironing(&params).context("the example's meshes")?;
        let about = [
            "seam example ironing: a neo-Hookean indenter (E = 1000) pressed 0.1 into a neo-Hookean slab"
                .to_string(),
            format!("(E = 100), then slid 3 along it; mu = {friction}."),
        ];
        let options = Options { output: dir.join(name), ..args.clone() };
        let extra = if runs.is_empty() { report.paths().to_vec() } else { Vec::new() };
        let solved = solve_example(problem, &options, &about, &extra)?;
        runs.push(Run { friction, name, solved });
    }
    let seconds = clock.elapsed().as_secs_f64();
    let image = draw(&runs)?;
    report.write(markdown(&runs), csv_text(&runs), &image, args.force)?;
    Ok(report_lines(dir, &runs, cells, seconds))
}

/// F_x / F_z over the sliding steps (t > 0.3, the slide well under way):
/// (mean, min, max).
fn sliding_ratio(run: &Run) -> (f64, f64, f64) {
    let ratios: Vec<f64> = run.forces().iter().filter(|(t, _)| *t > 0.3).map(|(_, f)| f[0] / f[2]).collect();
    let mean = ratios.iter().sum::<f64>() / ratios.len().max(1) as f64;
    let (lo, hi) = ratios.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &r| (a.min(r), b.max(r)));
    (mean, lo, hi)
}

/// `ironing.md`.
fn markdown(runs: &[Run]) -> String {
    let mut t = String::from("# seam example ironing\n\n");
    let _ = writeln!(
        t,
        "A neo-Hookean indenter (E = 1000, ν = 0.3, a cylindrical face of radius 1) pressed 0.1 into a \
         neo-Hookean slab (E = 100, ν = 0.3) over t ≤ 0.2, then slid 3 along it (Puso & Laursen 2004). \
         F is the contact force of the slab on the indenter.\n"
    );
    let _ = writeln!(t, "| t | F_x (μ = 0) | F_z (μ = 0) | F_x (μ = {FRICTION}) | F_z (μ = {FRICTION}) |");
    let _ = writeln!(t, "|---|---|---|---|---|");
    let (a, b) = (runs[0].forces(), runs[1].forces());
    for ((t0, f), (_, g)) in a.iter().zip(&b) {
        let _ = writeln!(t, "| {t0:.2} | {:.4} | {:.4} | {:.4} | {:.4} |", f[0], f[2], g[0], g[2]);
    }
    for run in runs {
        let (mean, lo, hi) = sliding_ratio(run);
        let _ = writeln!(
            t,
            "\nμ = {}: F_x / F_z while sliding (t > 0.3) {mean:.4} (from {lo:.4} to {hi:.4}); {} Newton iterations \
             over {} load steps, {} dofs.",
            run.friction,
            run.iterations(),
            run.solved.summary.steps.len(),
            run.solved.summary.dofs
        );
    }
    let _ = writeln!(
        t,
        "\nWith friction F_x / F_z is about −μ, less the ploughing of the slab's bulge ahead of the indenter (the \
         normal traction on the tilted parts of the cylindrical face), which also makes F_x of the frictionless \
         run oscillate about zero as the indenter passes over the slab's cells."
    );
    t
}

/// `ironing.csv`.
fn csv_text(runs: &[Run]) -> String {
    let mut t = String::from("friction,t,force_x,force_y,force_z\n");
    for run in runs {
        for (time, f) in run.forces() {
            let _ = writeln!(t, "{},{time},{},{},{}", run.friction, f[0], f[1], f[2]);
        }
    }
    t
}

/// The three panels (module doc).
fn draw(runs: &[Run]) -> anyhow::Result<Image> {
    let colors = [[40, 90, 200], [200, 60, 40]];
    let series = |f: &dyn Fn(&[f64; 3]) -> f64| -> Vec<Series> {
        runs.iter()
            .zip(colors)
            .map(|(run, color)| Series {
                label: format!("mu = {}", run.friction),
                color,
                points: std::iter::once([0.0, 0.0])
                    .chain(run.forces().iter().map(|(t, g)| [*t, f(g)]))
                    .collect(),
            })
            .collect()
    };
    let largest = runs.iter().flat_map(|r| r.forces()).map(|(_, f)| f[2]).fold(0.0, f64::max);
    let normal = Chart {
        title: vec![
            "contact force F_z of the slab on the indenter".into(),
            "pressed for t < 0.2, then slid".into(),
        ],
        x: ("t".into(), 0.0, 1.0),
        y: ("F_z".into(), 0.0, 1.2 * largest),
        curves: series(&|f| f[2]),
        markers: Vec::new(),
    };
    let ratio = Chart {
        title: vec!["F_x / F_z".into(), format!("against -mu = {}", -FRICTION)],
        x: ("t".into(), 0.0, 1.0),
        y: ("F_x / F_z".into(), -0.6, 0.2),
        curves: series(&|f| if f[2] > 0.0 { f[0] / f[2] } else { 0.0 }),
        markers: vec![Series {
            label: "-mu".into(),
            color: [120, 120, 120],
            points: vec![[0.2, -FRICTION], [1.0, -FRICTION]],
        }],
    };
    let s = &runs[1].solved;
    let mut cut = Plot::default();
    for (b, body) in s.problem.bodies.iter().enumerate() {
        let (x, u) = (body.mesh.points(), &s.solution.displacement[b]);
        let place = |q: usize| [x[q][0] + u[3 * q], x[q][2] + u[3 * q + 2]];
        if add_cut(&mut cut, &body.mesh, 1, CUT, place, |q| s.solution.stresses[b].nodal_von_mises[q]) == 0 {
            bail!("body \"{}\" has no cell faces on the plane y = {CUT}", body.name);
        }
    }
    cut.title =
        vec![format!("von Mises stress, cut y = 1, mu = {FRICTION}"), "deformed at t = 1, true scale".into()];
    let (w, h, header) = (560, 520, 44);
    let mut image = Image::new(3 * w as usize, (h + header) as usize, [255, 255, 255]);
    let title = format!(
        "seam example ironing: {} dofs, {} and {} Newton iterations over {} load steps",
        s.summary.dofs,
        runs[0].iterations(),
        runs[1].iterations(),
        s.summary.steps.len()
    );
    image.text(10, 12, &title, 2, [20, 20, 20]);
    image.chart(0, header, w, h, &normal);
    image.chart(w, header, w, h, &ratio);
    image.plot(2 * w, header, w, h, &cut);
    Ok(image)
}

fn report_lines(dir: &Path, runs: &[Run], cells: usize, seconds: f64) -> Vec<String> {
    let mut lines = vec![format!("seam example ironing → {}", dir.display())];
    let s = &runs[0].solved;
    lines.push(format!(
        "  meshes     slab {} hexahedra, indenter {cells}×{cells}×{} hexahedra with a cylindrical face; {} dofs",
        s.problem.bodies[0].mesh.cells().len(),
        (cells / 2).max(1),
        s.summary.dofs
    ));
    lines.push(
        "  conditions neo-Hookean, slab E = 100, indenter E = 1000, ν = 0.3; pressed 0.1 (t ≤ 0.2), slid 3"
            .to_string(),
    );
    for run in runs {
        let (mean, lo, hi) = sliding_ratio(run);
        let last = run.forces().last().map_or([0.0; 3], |f| f.1);
        lines.push(format!(
            "  μ = {:<4}   {} Newton iterations over {} steps; at t = 1 F = ({:.4}, {:.4}, {:.4}); F_x / F_z sliding {mean:.3} ({lo:.3} to {hi:.3}); {}/",
            run.friction,
            run.iterations(),
            run.solved.summary.steps.len(),
            last[0],
            last[1],
            last[2],
            run.name
        ));
    }
    lines.push(format!("  solved     both runs in {seconds:.1} s"));
    lines.push(
        "  written    ironing.md, ironing.csv, ironing.png (forces over t, the deformed bodies)".to_string(),
    );
    lines.push(format!(
        "  rerun      seam solve {} --force",
        dir.join("friction").join("case.toml").display()
    ));
    lines
}
