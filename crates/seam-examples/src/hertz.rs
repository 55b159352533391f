//! `seam example hertz -o DIR`: contact against Hertz's analytic solution. A
//! quarter model ([`seam_fem::scene::hertz`]) of an indenter with a spherical
//! face (R = 1; E = 2000, ν = 0.3) pressed on a block (E = 1000, ν = 0.25) by
//! the force F that gives the contact radius a = 0.08: symmetry rollers on the
//! planes x = 0 and y = 0 of both bodies, the block's bottom clamped, the load
//! a uniform traction on the indenter's top (force control). The block's top
//! is the slave side, with lumped multipliers.
//!
//! It writes the meshes and `case.toml`, solves the problem in memory
//! exactly as `seam solve` solves that case, and compares with Hertz:
//!
//! - `hertz.csv`: per slave node on the symmetry axes of the block's top
//!   (axis "x": the nodes on y = 0, axis "y": those on x = 0; the pole on
//!   both): its position, r, seam's contact pressure, Hertz's
//!   p(r) = p₀ √(1 − r²/a²) and whether it is active;
//! - `hertz.md`: the table "analytic vs seam" of the contact radius (seam: the
//!   outermost active node on the axes; the edge lies within one slave element
//!   h of it), the peak pressure p₀ (seam: the pressure at the pole node) and
//!   the force on the quarter F/4 (seam: the contact force of the summary),
//!   with the errors; also printed;
//! - `hertz.png`: seam's pressures along both axes as dots over Hertz's curve.

use crate::case::{solve_example, Report};
use crate::picture::{viridis, Chart, Image, Series};
use crate::{Failure, Options};
use anyhow::{anyhow, Context};
use seam_case::report::report;
use seam_case::solve::Solved;
use seam_fem::scene::{hertz, Hertz};
use std::fmt::Write as _;
use std::path::Path;

/// Slave cells across the uniform zone [0, 1.5a] of each symmetry axis.
pub const FINE_CELLS: usize = 8;

/// A slave node on a symmetry axis of the block's top.
struct AxisNode {
    /// "x" (on y = 0) or "y" (on x = 0).
    axis: &'static str,
    x: f64,
    y: f64,
    r: f64,
    pressure: f64,
    hertz: f64,
    active: bool,
}

/// Analytic and computed values of one quantity.
struct Row {
    name: &'static str,
    analytic: f64,
    seam: f64,
    /// What the seam value is.
    note: String,
}

/// Writes the meshes and case, solves, compares with Hertz (module doc);
/// returns the report.
///
/// # Errors
/// As [`crate::run`].
pub fn run(args: &Options) -> Result<Vec<String>, Failure> {
    let params = Hertz { fine_cells: args.slave_cells.unwrap_or(FINE_CELLS), ..Hertz::default() };
    if params.fine_cells == 0 {
        return Err(anyhow!("--slave-cells must be at least 1").into());
    }
    let dir = &args.output;
    let report = Report::new(dir, "hertz");
    let problem = hertz(&params).context("the example's meshes")?;
    let about = [
        "seam example hertz: a quarter model of an indenter with a spherical face (R = 1) pressed"
            .to_string(),
        format!(
            "on an elastic block by F/4 = {}; Hertz: contact radius {}, peak pressure {}.",
            sig(params.force() / 4.0),
            params.contact_radius,
            sig(params.peak_pressure())
        ),
    ];
    let solved = solve_example(problem, args, &about, &report.paths())?;

    let clock = std::time::Instant::now();
    let nodes = axis_nodes(&solved, &params)?;
    let rows = compare(&solved, &params, &nodes)?;
    let table = table(&rows, params.slave_size());
    let text = markdown(&solved, &params, &table);
    let image = draw(&params, &nodes, &rows);
    report.write(text, csv_text(&nodes), &image, args.force)?;
    let seconds = clock.elapsed().as_secs_f64();

    Ok(report_lines(dir, &params, &solved, &table, seconds))
}

/// The slave nodes on the symmetry axes, sorted by axis and r.
fn axis_nodes(s: &Solved, p: &Hertz) -> anyhow::Result<Vec<AxisNode>> {
    let f = s.interfaces().first().ok_or_else(|| anyhow!("the example has an interface"))?;
    let contact =
        |name| f.field(name).ok_or_else(|| anyhow!("the example's interface is a contact interface"));
    let (pressure, active) = (contact("contact_pressure")?, contact("active")?);
    let tol = 1e-9 * p.block_size();
    let mut nodes = Vec::new();
    for (axis, along, across) in [("x", 0, 1), ("y", 1, 0)] {
        let mut on: Vec<AxisNode> = (0..f.mesh.n_points())
            .filter(|&q| f.mesh.points()[q][across].abs() <= tol)
            .map(|q| {
                let [x, y, _] = f.mesh.points()[q];
                let r = f.mesh.points()[q][along];
                AxisNode {
                    axis,
                    x,
                    y,
                    r,
                    pressure: pressure[q],
                    hertz: p.pressure(r),
                    active: active[q] > 0.0,
                }
            })
            .collect();
        on.sort_by(|a, b| a.r.total_cmp(&b.r));
        nodes.extend(on);
    }
    Ok(nodes)
}

/// Contact radius, peak pressure and force: Hertz's and seam's.
fn compare(s: &Solved, p: &Hertz, nodes: &[AxisNode]) -> anyhow::Result<Vec<Row>> {
    let outermost = nodes.iter().filter(|n| n.active).map(|n| n.r).fold(f64::NAN, f64::max);
    let pole = nodes
        .iter()
        .find(|n| n.r == 0.0)
        .ok_or_else(|| anyhow!("the block's top has no node at the pole"))?;
    let contact = s.summary.contact.as_ref().ok_or_else(|| anyhow!("the summary has no contact results"))?;
    let force = -contact.interfaces[0].force[2];
    Ok(vec![
        Row {
            name: "contact radius a",
            analytic: p.contact_radius,
            seam: outermost,
            note: "outermost active node on the axes".into(),
        },
        Row {
            name: "peak pressure p0",
            analytic: p.peak_pressure(),
            seam: pole.pressure,
            note: "contact pressure at the pole node".into(),
        },
        Row {
            name: "force on the quarter F/4",
            analytic: p.force() / 4.0,
            seam: force,
            note: "contact force (summary.json)".into(),
        },
    ])
}

/// `v` with 5 significant digits, without trailing zeros.
pub(crate) fn sig(v: f64) -> String {
    let digits = if v == 0.0 { 0 } else { (4 - v.abs().log10().floor() as i64).max(0) as usize };
    let text = format!("{v:.digits$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// A relative error in percent: "+0.17 %", or "-9.1e-14 %" when tiny.
pub(crate) fn percent(seam: f64, analytic: f64) -> String {
    let e = 100.0 * (seam / analytic - 1.0);
    if e.abs() < 0.005 {
        format!("{e:+.1e} %")
    } else {
        format!("{e:+.2} %")
    }
}

/// The markdown table "analytic vs seam"; `h` is the slave element size.
fn table(rows: &[Row], h: f64) -> Vec<String> {
    let mut lines = vec![
        "| quantity | analytic (Hertz) | seam | error | seam value |".to_string(),
        "|---|---:|---:|---:|---|".to_string(),
    ];
    for (k, r) in rows.iter().enumerate() {
        let error = percent(r.seam, r.analytic);
        let (seam, error) = if k == 0 {
            // The edge lies between the outermost active node and the next one.
            (
                format!("{} ± {}", sig(r.seam), sig(h)),
                format!("{error} ({:+.2} h)", (r.seam - r.analytic) / h),
            )
        } else {
            (sig(r.seam), error)
        };
        lines.push(format!("| {} | {} | {seam} | {error} | {} |", r.name, sig(r.analytic), r.note));
    }
    lines
}

/// `hertz.md`.
fn markdown(s: &Solved, p: &Hertz, table: &[String]) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "# Hertz contact: analytic vs seam\n");
    let _ = writeln!(
        t,
        "A quarter model: an indenter with a spherical face (R = {}, E = {}, ν = {}) pressed on a block \
         (E = {}, ν = {}) by the force F/4 = {} on the quarter, E* = {}; frictionless contact, {} multipliers \
         on the block's top (slave), {} slave cells across 1.5a (h = {}), {} dofs.\n",
        p.radius,
        p.indenter.young(),
        p.indenter.poisson(),
        p.block.young(),
        p.block.poisson(),
        sig(p.force() / 4.0),
        sig(p.effective_modulus()),
        s.summary.multiplier,
        p.fine_cells,
        sig(p.slave_size()),
        s.summary.dofs
    );
    for line in table {
        let _ = writeln!(t, "{line}");
    }
    let _ = writeln!(
        t,
        "\nThe contact edge lies between the outermost active node and the next node out: within one slave element h."
    );
    t
}

/// `hertz.csv`.
fn csv_text(nodes: &[AxisNode]) -> String {
    let mut t = String::from("axis,x,y,r,contact_pressure,hertz_pressure,active\n");
    for n in nodes {
        let _ = writeln!(
            t,
            "{},{},{},{},{},{},{}",
            n.axis,
            n.x,
            n.y,
            n.r,
            n.pressure,
            n.hertz,
            u8::from(n.active)
        );
    }
    t
}

/// p/p₀ against r/a: seam's nodes on both axes as dots, Hertz's curve.
fn draw(p: &Hertz, nodes: &[AxisNode], rows: &[Row]) -> Image {
    let (a, p0) = (p.contact_radius, p.peak_pressure());
    let samples = 400;
    let curve =
        (0..=samples).map(|i| 2.0 * i as f64 / samples as f64).map(|t| [t, p.pressure(t * a) / p0]).collect();
    let along =
        |axis: &str| nodes.iter().filter(|n| n.axis == axis).map(|n| [n.r / a, n.pressure / p0]).collect();
    let chart = Chart {
        title: vec![
            "seam example hertz: contact pressure along the symmetry axes".into(),
            format!("p0: Hertz {}, seam {} ({})", sig(p0), sig(rows[1].seam), percent(rows[1].seam, p0)),
            format!("a: Hertz {}, seam {} ± h, h = {}", sig(a), sig(rows[0].seam), sig(p.slave_size())),
        ],
        x: ("r / a".into(), 0.0, 2.0),
        y: ("p / p0".into(), 0.0, 1.2),
        curves: vec![Series {
            label: "Hertz: p0 sqrt(1 - (r/a)^2)".into(),
            color: [20, 20, 20],
            points: curve,
        }],
        markers: vec![
            Series { label: "seam, nodes on y = 0".into(), color: viridis(0.35), points: along("x") },
            Series { label: "seam, nodes on x = 0".into(), color: [240, 140, 20], points: along("y") },
        ],
    };
    let mut image = Image::new(1000, 680, [255, 255, 255]);
    image.chart(0, 0, 1000, 680, &chart);
    image
}

fn report_lines(dir: &Path, p: &Hertz, s: &Solved, table: &[String], picture_seconds: f64) -> Vec<String> {
    let mut lines = vec![format!("seam example hertz → {}", dir.display())];
    lines.push(format!(
        "  model      quarter: indenter (sphere R = {}, E = {}, ν = {}) on a block (E = {}, ν = {}), force F/4 = {}",
        p.radius,
        p.indenter.young(),
        p.indenter.poisson(),
        p.block.young(),
        p.block.poisson(),
        sig(p.force() / 4.0)
    ));
    lines.push(format!(
        "  meshes     indenter.msh, block.msh: hexahedra, {} slave cells across 1.5a (h = {}), master {}× finer",
        p.fine_cells,
        sig(p.slave_size()),
        p.master_ratio
    ));
    lines.extend(report(s).into_iter().map(|line| format!("  {line}")));
    lines.push("  Hertz      analytic vs seam (hertz.md):".to_string());
    lines.extend(table.iter().map(|line| format!("    {line}")));
    lines.push(format!("  wrote      hertz.csv hertz.md hertz.png ({picture_seconds:.2} s)"));
    lines.push(format!("  rerun      seam solve {} --force", dir.join("case.toml").display()));
    lines
}
