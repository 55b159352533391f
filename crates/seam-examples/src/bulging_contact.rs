//! `seam example bulging-contact -o DIR`: the paper's second example (Fig. 3).
//! Two hexahedral blocks over the unit square whose facing sides bulge towards
//! each other (Gaussian bulges of different shapes, off-centre, touching at
//! one point; [`seam_fem::scene::bulging_contact`]), meshed independently,
//! the lower one (master) 1.5× finer. The lower bottom is clamped, the upper
//! top moved by (0.02, −0.01, −0.08): down and sideways, so the bodies come
//! into contact around the touching point. Frictionless contact with lumped
//! multipliers; E = 1000, ν = 0.3.
//!
//! It writes the two meshes and `case.toml`, solves the problem in memory
//! exactly as `seam solve` solves that case, and draws `bulging-contact.png`: left, the initial
//! geometry (the cut y = 1/2, and the initial gap between the bulges seen from
//! above); centre, the cuts y = 1/2 and x = 1/2 through the deformed bodies
//! coloured by the von Mises stress; right, the contact pressure on the slave
//! side seen from above (zero where inactive, the active zone outlined) and
//! the gap after deformation.

use crate::case::solve_example;
use crate::picture::{add_cut, Image, Plot, P2};
use crate::{Failure, Options};
use anyhow::{anyhow, bail, Context};
use seam_case::report::{report, vector};
use seam_case::solve::{InterfaceResult, Solved};
use seam_case::write::write_files;
use seam_fem::scene::{bulging_contact, BulgingContact};
use std::collections::BTreeMap;
use std::path::Path;

/// Slave cells across x and y (the scene's default is 12); the slave has half
/// as many layers, the master 1.5× as many cells in every direction.
pub const SLAVE_CELLS: usize = 16;

/// The cuts x = 1/2 and y = 1/2: grid planes of both blocks when both cell
/// counts across are even.
const CUT: f64 = 0.5;

/// Writes the meshes and case, solves, draws `bulging-contact.png` (module
/// doc); returns the report.
///
/// # Errors
/// As [`crate::run`].
pub fn run(args: &Options) -> Result<Vec<String>, Failure> {
    let cells = args.slave_cells.unwrap_or(SLAVE_CELLS);
    let params = BulgingContact { cells, layers: (cells / 2).max(1), ..BulgingContact::default() };
    if cells < 2 || cells % 2 != 0 || params.master_cells() % 2 != 0 {
        return Err(anyhow!(
            "--slave-cells must be even, at least 2, and give an even master count (a multiple of 4)"
        )
        .into());
    }
    let picture = args.output.join("bulging-contact.png");
    let problem = bulging_contact(&params).context("the example's meshes")?;
    let about = [
        "seam example bulging-contact: two blocks with bulging facing sides, touching at one point,"
            .to_string(),
        format!(
            "pressed together by the displacement {} of the upper top (the paper's Fig. 3).",
            vector(params.press)
        ),
    ];
    let solved = solve_example(problem, args, &about, std::slice::from_ref(&picture))?;

    let clock = std::time::Instant::now();
    let image = draw(&solved, &params)?;
    write_files(&[(picture, image.png().map_err(|e| Failure::error(&e))?)], args.force)?;
    let seconds = clock.elapsed().as_secs_f64();

    Ok(report_lines(&args.output, &params, &solved, seconds))
}

/// The six panels (module doc).
fn draw(s: &Solved, p: &BulgingContact) -> anyhow::Result<Image> {
    let lift = p.lift();
    // The vertical initial gap s − t above (x, y).
    let gap = |x: f64, y: f64| lift - p.master_bulge.at(x, y) - p.slave_bulge.at(x, y);
    let mut initial = Plot::default();
    let (mut cut_y, mut cut_x) = (Plot::default(), Plot::default());
    for (b, body) in s.problem.bodies.iter().enumerate() {
        let (x, u) = (body.mesh.points(), &s.solution.displacement[b]);
        let von_mises = |q: usize| s.solution.stresses[b].nodal_von_mises[q];
        if add_cut(&mut initial, &body.mesh, 1, CUT, |q| [x[q][0], x[q][2]], |q| gap(x[q][0], x[q][1])) == 0 {
            bail!("body \"{}\" has no cell faces on the plane y = {CUT}", body.name);
        }
        let moved = |q: usize, k: usize| [x[q][k] + u[3 * q + k], x[q][2] + u[3 * q + 2]];
        add_cut(&mut cut_y, &body.mesh, 1, CUT, |q| moved(q, 0), von_mises);
        if add_cut(&mut cut_x, &body.mesh, 0, CUT, |q| moved(q, 1), von_mises) == 0 {
            bail!("body \"{}\" has no cell faces on the plane x = {CUT}", body.name);
        }
    }
    initial.title = vec!["initial geometry, cut y = 1/2".into(), "coloured by the gap s-t".into()];
    cut_y.title = vec!["von Mises stress, cut y = 1/2".into(), "deformed, true scale".into()];
    cut_x.title = vec!["von Mises stress, cut x = 1/2".into(), "deformed, true scale".into()];

    let f = s.interfaces().first().ok_or_else(|| anyhow!("the example has an interface"))?;
    let contact =
        |name| f.field(name).ok_or_else(|| anyhow!("the example's interface is a contact interface"));
    let (pressure_at, gap_at, active_at) =
        (contact("contact_pressure")?, contact("gap")?, contact("active")?);
    let xy = |q: usize| [f.mesh.points()[q][0], f.mesh.points()[q][1]];
    let mut gap0 = from_above(f, |q| gap(xy(q)[0], xy(q)[1]));
    let mut pressure = from_above(f, |q| pressure_at[q]);
    let mut gap1 = from_above(f, |q| if gap_at[q].is_finite() { gap_at[q] } else { 0.0 });
    pressure.lines = outline(f, active_at);
    gap1.lines = pressure.lines.clone();
    let [tx, ty] = p.touching_point();
    gap0.title = vec!["initial gap s-t, from above".into(), format!("touching at ({tx:.3}, {ty:.3})")];
    let active = active_at.iter().filter(|&&a| a > 0.0).count();
    pressure.title =
        vec!["contact pressure, from above".into(), format!("{active} of {} points active", active_at.len())];
    gap1.title = vec!["gap after deformation".into(), "active zone outlined".into()];

    let (w, h, header) = (520, 560, 44);
    let mut image = Image::new(3 * w as usize, (2 * h + header) as usize, [255, 255, 255]);
    let steps = s.summary.contact.as_ref().map_or(0, |c| c.iterations);
    let title = format!(
        "seam example bulging-contact: {} dofs, {} multipliers, {steps} active-set steps",
        s.summary.dofs, s.summary.multiplier
    );
    image.text(10, 12, &title, 2, [20, 20, 20]);
    for (k, plot) in [&initial, &cut_y, &pressure, &gap0, &cut_x, &gap1].into_iter().enumerate() {
        let (col, row) = (k as i64 % 3, k as i64 / 3);
        image.plot(col * w, header + row * h, w, h, plot);
    }
    Ok(image)
}

/// The slave surface of `f` seen from above, coloured by `value` per point.
fn from_above(f: &InterfaceResult, value: impl Fn(usize) -> f64) -> Plot {
    let mut plot = Plot::default();
    for face in f.mesh.faces() {
        let corners: Vec<P2> =
            face.nodes().iter().map(|&q| [f.mesh.points()[q][0], f.mesh.points()[q][1]]).collect();
        let values: Vec<f64> = face.nodes().iter().map(|&q| value(q)).collect();
        plot.add_polygon(&corners, &values);
    }
    plot
}

/// The boundary of the faces of `f` whose points are all active, from above.
fn outline(f: &InterfaceResult, active: &[f64]) -> Vec<(P2, P2)> {
    let mut edges: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    for face in f.mesh.faces().iter().filter(|face| face.nodes().iter().all(|&q| active[q] > 0.0)) {
        let n = face.nodes();
        for k in 0..n.len() {
            let (a, b) = (n[k], n[(k + 1) % n.len()]);
            *edges.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let xy = |q: usize| [f.mesh.points()[q][0], f.mesh.points()[q][1]];
    edges.into_iter().filter(|&(_, count)| count == 1).map(|((a, b), _)| (xy(a), xy(b))).collect()
}

fn report_lines(dir: &Path, p: &BulgingContact, s: &Solved, picture_seconds: f64) -> Vec<String> {
    let mut lines = Vec::new();
    let (nm, lm, ns, ls) = (p.master_cells(), p.master_layers(), p.cells, p.layers);
    let [tx, ty] = p.touching_point();
    lines.push(format!("seam example bulging-contact → {}", dir.display()));
    lines.push(format!(
        "  meshes     lower.msh {nm}×{nm}×{lm} hexahedra (master), upper.msh {ns}×{ns}×{ls} hexahedra (slave), h_s/h_m = {}",
        p.ratio
    ));
    lines.push(format!(
        "  geometry   bulges of height {} (lower top) and {} (upper bottom) touching at ({tx:.4}, {ty:.4}); gap far from them {:.4}",
        p.master_bulge.height,
        p.slave_bulge.height,
        p.lift()
    ));
    lines.push(format!(
        "  conditions lower bottom clamped, upper top moved by {}; E = 1000, ν = 0.3; frictionless contact",
        vector(p.press)
    ));
    lines.extend(report(s).into_iter().map(|line| format!("  {line}")));
    lines.push(format!(
        "  picture    bulging-contact.png: initial geometry, von Mises on the cuts y = 1/2 and x = 1/2, contact pressure and gap; {picture_seconds:.2} s"
    ));
    lines.push(format!("  rerun      seam solve {} --force", dir.join("case.toml").display()));
    lines
}
