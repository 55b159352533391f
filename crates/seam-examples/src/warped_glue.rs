//! `seam example warped-glue -o DIR`: the paper's first example (Fig. 2). Two
//! hexahedral blocks meet at the warped surface z = 1/2 + 0.1 sin 2πx sin πy;
//! the upper one (slave) is 8× coarser than the lower one (master). The lower
//! block is clamped at z = 0, the upper one loaded at z = 1 by the traction
//! (0.2, 0, −1); E = 1000, ν = 0.3 for both.
//!
//! With `--order 2` the bodies are Hex27 cells (half as many, so the same
//! numbers of nodes) whose nodes all lie on the blocks' maps: the interface
//! is made of curved Quad9 faces of the true warped surface.
//!
//! It writes the two meshes (Gmsh MSH 4.1, physical surfaces "bottom" and
//! "top") and `case.toml`, solves the problem in memory exactly as `seam
//! solve` solves that case (so `seam solve DIR/case.toml --force` reruns
//! it), and draws
//! `warped-glue.png`: a cut y = 1/2 through the deformed bodies coloured by
//! u₁ and by u₃, and the slave interface seen from above coloured by the
//! normal traction and by its tangential x component.

use crate::case::solve_example;
use crate::picture::{add_cut, label_factor, nice_below, Image, Plot, P2};
use crate::{Failure, Options};
use anyhow::{anyhow, bail, Context};
use seam_case::report::{report, vector};
use seam_case::solve::Solved;
use seam_case::write::write_files;
use seam_fem::scene::{warped_glue, WarpedGlue};
use std::path::{Path, PathBuf};

/// Slave cells across x and y: (n + 1)² = 81 slave interface nodes.
pub const SLAVE_CELLS: usize = 8;
/// h_s / h_m: the master side has `RATIO · SLAVE_CELLS` cells across.
pub const RATIO: usize = 8;

/// The plane of the cut: y = 1/2 (a grid plane of both blocks, whose cell
/// counts across y are even).
const CUT_Y: f64 = 0.5;

/// Writes the meshes and case, solves, draws `warped-glue.png` (module doc);
/// returns the report.
///
/// # Errors
/// As [`crate::run`].
pub fn run(args: &Options) -> Result<Vec<String>, Failure> {
    let order = args.order.unwrap_or(1);
    if !(1..=2).contains(&order) {
        return Err(anyhow!("--order must be 1 or 2, got {order}").into());
    }
    // Order 2: Hex27 cells, half as many across and in z, so the numbers of
    // nodes are those of order 1.
    let defaults = WarpedGlue::default();
    let params = WarpedGlue {
        slave_cells: args.slave_cells.unwrap_or(SLAVE_CELLS / order),
        ratio: args.ratio.unwrap_or(RATIO),
        slave_layers: defaults.slave_layers / order,
        master_layers: defaults.master_layers / order,
        order,
        ..defaults
    };
    if params.ratio == 0 || params.slave_cells == 0 || params.slave_cells % 2 != 0 {
        return Err(anyhow!("--ratio must be at least 1 and --slave-cells even and at least 2").into());
    }
    let picture = args.output.join("warped-glue.png");
    let problem = warped_glue(&params).context("the example's meshes")?;
    let about = [
        format!(
            "seam example warped-glue: two blocks glued at z = 1/2 + {} sin 2πx sin πy,",
            params.amplitude
        ),
        format!("the upper one (slave) {}× coarser than the lower one (master).", params.ratio),
    ];
    let solved = solve_example(problem, args, &about, std::slice::from_ref(&picture))?;

    let clock = std::time::Instant::now();
    let (image, magnification) = draw(&solved, &params)?;
    write_files(&[(picture, image.png().map_err(|e| Failure::error(&e))?)], args.force)?;
    let seconds = clock.elapsed().as_secs_f64();

    Ok(report_lines(&args.output, &params, &solved, magnification, seconds))
}

/// The four panels (module doc); returns the picture and the displacement
/// magnification of the cut panels.
fn draw(s: &Solved, params: &WarpedGlue) -> anyhow::Result<(Image, f64)> {
    let max_u = s.summary.bodies.iter().map(|b| b.max_displacement).fold(0.0, f64::max);
    let magnification = if max_u > 0.0 { nice_below(0.08 / max_u) } else { 1.0 };
    let (mut u1, mut u3) = (Plot::default(), Plot::default());
    for (b, body) in s.problem.bodies.iter().enumerate() {
        let u = &s.solution.displacement[b];
        let x = body.mesh.points();
        let moved = |p: usize| [x[p][0] + magnification * u[3 * p], x[p][2] + magnification * u[3 * p + 2]];
        if add_cut(&mut u1, &body.mesh, 1, CUT_Y, moved, |p| u[3 * p]) == 0 {
            bail!("body \"{}\" has no cell faces on the plane y = {CUT_Y}", body.name);
        }
        add_cut(&mut u3, &body.mesh, 1, CUT_Y, moved, |p| u[3 * p + 2]);
    }
    let h = format!("h_s/h_m = {}, deformation ×{}", params.ratio, label_factor(magnification));
    u1.title = vec!["u_1 on the cut y = 1/2".into(), h.clone()];
    u3.title = vec!["u_3 on the cut y = 1/2".into(), h];
    let f = s.interfaces().first().ok_or_else(|| anyhow!("the example has an interface"))?;
    let traction = |name| f.field(name).ok_or_else(|| anyhow!("the interface has no field {name}"));
    let (normal_traction, tangential_traction) =
        (traction("normal_traction")?, traction("tangential_traction")?);
    let (mut normal, mut tangential) = (Plot::default(), Plot::default());
    for piece in f.mesh.faces().iter().flat_map(|face| face.linear_pieces()) {
        let corners: Vec<P2> =
            piece.iter().map(|&p| [f.mesh.points()[p][0], f.mesh.points()[p][1]]).collect();
        let tn: Vec<f64> = piece.iter().map(|&p| normal_traction[p]).collect();
        let tt: Vec<f64> = piece.iter().map(|&p| tangential_traction[3 * p]).collect();
        normal.add_polygon(&corners, &tn);
        tangential.add_polygon(&corners, &tt);
    }
    let nodes = f.mesh.n_points();
    let seen = format!("interface from above, {nodes} nodes");
    normal.title = vec!["normal traction t·n".into(), seen.clone()];
    tangential.title = vec!["tangential traction, x".into(), seen];
    let (w, h) = (520, 560);
    let header = 44;
    let mut image = Image::new(2 * w as usize, (2 * h + header) as usize, [255, 255, 255]);
    image.text(
        10,
        12,
        &format!("seam example warped-glue: {} multipliers, {} dofs", s.summary.multiplier, s.summary.dofs),
        2,
        [20, 20, 20],
    );
    image.plot(0, header, w, h, &u1);
    image.plot(w, header, w, h, &u3);
    image.plot(0, header + h, w, h, &normal);
    image.plot(w, header + h, w, h, &tangential);
    Ok((image, magnification))
}

fn report_lines(
    dir: &Path,
    p: &WarpedGlue,
    s: &Solved,
    magnification: f64,
    picture_seconds: f64,
) -> Vec<String> {
    let mut lines = Vec::new();
    let (nm, ns) = (p.slave_cells * p.ratio, p.slave_cells);
    let cells = if p.order == 2 { "Hex27 cells" } else { "hexahedra" };
    lines.push(format!("seam example warped-glue → {}", dir.display()));
    lines.push(format!(
        "  meshes     lower.msh {nm}×{nm}×{} {cells} (master), upper.msh {ns}×{ns}×{} {cells} (slave), h_s/h_m = {}",
        p.master_layers, p.slave_layers, p.ratio
    ));
    lines.push(format!(
        "  interface  z = 1/2 + {} sin 2πx sin πy; clamped at z = 0, traction {} at z = 1; E = 1000, ν = 0.3",
        p.amplitude,
        vector(p.traction)
    ));
    lines.extend(report(s).into_iter().map(|line| format!("  {line}")));
    lines.push(format!(
        "  picture    warped-glue.png: u_1 and u_3 on the cut y = 1/2 (deformation ×{}), interface tractions; {picture_seconds:.2} s",
        label_factor(magnification)
    ));
    let case = dir.join("case.toml");
    lines.push(format!("  rerun      seam solve {} --force", PathBuf::from(&case).display()));
    lines
}
