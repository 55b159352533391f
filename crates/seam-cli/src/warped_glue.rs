//! `seam example warped-glue -o DIR`: the paper's first example (Fig. 2). Two
//! hexahedral blocks meet at the warped surface z = 1/2 + 0.1 sin 2πx sin πy;
//! the upper one (slave) is 8× coarser than the lower one (master). The lower
//! block is clamped at z = 0, the upper one loaded at z = 1 by the traction
//! (0.2, 0, −1); E = 1000, ν = 0.3 for both.
//!
//! It writes the two meshes (Gmsh MSH 4.1, physical surfaces "bottom" and
//! "top") and `case.toml`, solves that case exactly as `seam solve` does
//! (so `seam solve DIR/case.toml --force` reruns it), and draws
//! `warped-glue.png`: a cut y = 1/2 through the deformed bodies coloured by
//! u₁ and by u₃, and the slave interface seen from above coloured by the
//! normal traction and by its tangential x component.

use crate::args::{ExampleArgs, SolveArgs, SolverArg};
use crate::output::Staged;
use crate::render::{Image, Plot, P2};
use crate::solve::{self, Solved};
use crate::Failure;
use anyhow::{anyhow, bail, Context};
use seam::{Multiplier, VolumeMesh};
use seam_fem::scene::{warped_glue, WarpedGlue};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Slave cells across x and y: (n + 1)² = 81 slave interface nodes.
pub const SLAVE_CELLS: usize = 8;
/// h_s / h_m: the master side has `RATIO · SLAVE_CELLS` cells across.
pub const RATIO: usize = 8;

/// The plane of the cut: y = 1/2 (a grid plane of both blocks, whose cell
/// counts across y are even).
const CUT_Y: f64 = 0.5;

pub fn run(args: &ExampleArgs) -> Result<(), Failure> {
    let params = WarpedGlue {
        slave_cells: args.slave_cells.unwrap_or(SLAVE_CELLS),
        ratio: args.ratio.unwrap_or(RATIO),
        ..WarpedGlue::default()
    };
    if params.ratio == 0 || params.slave_cells == 0 || params.slave_cells % 2 != 0 {
        return Err(anyhow!("--ratio must be at least 1 and --slave-cells even and at least 2").into());
    }
    let dir = &args.output;
    let case_path = dir.join("case.toml");
    let picture = dir.join("warped-glue.png");
    let inputs = [dir.join("lower.msh"), dir.join("upper.msh"), case_path.clone()];
    let results = ["lower.vtu", "upper.vtu", "upper_bottom_interface.vtu", "summary.json"]
        .map(|f| dir.join("out").join(f));
    for path in inputs.iter().chain(&results).chain([&picture]) {
        if path.exists() && !args.force {
            return Err(anyhow!("{} already exists; pass --force to overwrite it", path.display()).into());
        }
    }
    let problem = warped_glue(&params).context("the example's meshes")?;

    // The meshes and the case file, then the case solved as `seam solve` does.
    let mut staged = Staged::prepare(&inputs, args.force)?;
    for (path, body) in inputs.iter().zip(&problem.bodies) {
        let surfaces: Vec<(&str, &seam::SurfaceMesh)> =
            body.surfaces.iter().map(|(n, s)| (n.as_str(), s)).collect();
        staged.write(path, |p| seam_io::write_volume_msh_file(p, &body.mesh, &body.name, &surfaces))?;
    }
    staged.write(&case_path, |p| std::fs::write(p, case_toml(&params)))?;
    staged.commit(&[])?;
    let solved = solve::solve(&SolveArgs {
        case: case_path.clone(),
        solver: SolverArg::Direct,
        rtol: 1e-10,
        force: args.force,
        threads: args.threads,
    })?;

    let clock = std::time::Instant::now();
    let (image, magnification) = draw(&solved, &params)?;
    let mut staged = Staged::prepare(std::slice::from_ref(&picture), args.force)?;
    staged.write(&picture, |p| image.write_png(std::io::BufWriter::new(std::fs::File::create(p)?)))?;
    staged.commit(&[])?;
    let seconds = clock.elapsed().as_secs_f64();

    print_report(dir, &params, &solved, magnification, seconds);
    Ok(())
}

/// The case file of the example.
fn case_toml(p: &WarpedGlue) -> String {
    let multiplier = match p.multiplier {
        Multiplier::Standard => "standard",
        Multiplier::Dual => "dual",
        Multiplier::Lumped => "lumped",
    };
    let [tx, ty, tz] = p.traction;
    let body = |name: &str, role: &str| {
        format!("[[body]]          # {role}\nname = \"{name}\"\nmesh = \"{name}.msh\"\nyoung = 1000.0\npoisson = 0.3\n")
    };
    format!(
        "# seam example warped-glue: two blocks glued at z = 1/2 + {a} sin 2πx sin πy,\n\
         # the upper one (slave) {r}× coarser than the lower one (master).\n\
         # Rerun with: seam solve case.toml --force\n\n\
         {lower}\n{upper}\n\
         [[interface]]\nmaster = \"lower:top\"\nslave = \"upper:bottom\"\nkind = \"glue\"\nmultiplier = \"{multiplier}\"\n\n\
         [[dirichlet]]     # clamped\nboundary = \"lower:bottom\"\nux = 0.0\nuy = 0.0\nuz = 0.0\n\n\
         [[traction]]\nboundary = \"upper:top\"\nt = [{tx:?}, {ty:?}, {tz:?}]\n\n\
         [output]\ndir = \"out\"\n",
        a = p.amplitude,
        r = p.ratio,
        lower = body("lower", "master side"),
        upper = body("upper", "slave side"),
    )
}

/// The faces of `mesh`'s cells that lie in the plane y = `y` (every corner
/// within `tol`), each once.
fn faces_in_plane(mesh: &VolumeMesh, y: f64, tol: f64) -> Vec<Vec<usize>> {
    let on = |p: usize| (mesh.points()[p][1] - y).abs() <= tol;
    let mut seen = BTreeSet::new();
    let mut faces = Vec::new();
    for cell in mesh.cells() {
        for face in cell.faces() {
            if face.nodes().iter().all(|&p| on(p)) {
                let mut key = face.nodes().to_vec();
                key.sort_unstable();
                if seen.insert(key) {
                    faces.push(face.nodes().to_vec());
                }
            }
        }
    }
    faces
}

/// Adds a face (a triangle or a quad with nodal values) and its edges: a quad
/// as four triangles around its centre, which carries the mean value (no
/// diagonal stands out).
fn add_polygon(plot: &mut Plot, corners: &[P2], values: &[f64]) {
    if corners.len() == 3 {
        plot.triangles.push(([corners[0], corners[1], corners[2]], [values[0], values[1], values[2]]));
    } else {
        let n = corners.len() as f64;
        let centre = [0, 1].map(|k| corners.iter().map(|c| c[k]).sum::<f64>() / n);
        let mean = values.iter().sum::<f64>() / n;
        for k in 0..corners.len() {
            let l = (k + 1) % corners.len();
            plot.triangles.push(([corners[k], corners[l], centre], [values[k], values[l], mean]));
        }
    }
    for k in 0..corners.len() {
        plot.edges.push((corners[k], corners[(k + 1) % corners.len()]));
    }
}

/// 1, 2 or 5 times a power of ten, the largest not above `x`.
fn nice_below(x: f64) -> f64 {
    let p = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0].into_iter().map(|m| m * p).find(|&v| v <= x).unwrap_or(p)
}

/// The four panels (module doc); returns the picture and the displacement
/// magnification of the cut panels.
fn draw(s: &Solved, params: &WarpedGlue) -> anyhow::Result<(Image, f64)> {
    let max_u = s.summary.bodies.iter().map(|b| b.max_displacement).fold(0.0, f64::max);
    let magnification = if max_u > 0.0 { nice_below(0.08 / max_u) } else { 1.0 };
    let (mut u1, mut u3) = (Plot::default(), Plot::default());
    for (b, body) in s.problem.bodies.iter().enumerate() {
        let u = &s.solution.displacement[b];
        let faces = faces_in_plane(&body.mesh, CUT_Y, 1e-9);
        if faces.is_empty() {
            bail!("body \"{}\" has no cell faces on the plane y = {CUT_Y}", body.name);
        }
        for face in faces {
            let moved: Vec<P2> = face
                .iter()
                .map(|&p| {
                    let x = body.mesh.points()[p];
                    [x[0] + magnification * u[3 * p], x[2] + magnification * u[3 * p + 2]]
                })
                .collect();
            let v1: Vec<f64> = face.iter().map(|&p| u[3 * p]).collect();
            let v3: Vec<f64> = face.iter().map(|&p| u[3 * p + 2]).collect();
            add_polygon(&mut u1, &moved, &v1);
            add_polygon(&mut u3, &moved, &v3);
        }
    }
    let h = format!("h_s/h_m = {}, deformation ×{}", params.ratio, label_factor(magnification));
    u1.title = vec!["u_1 on the cut y = 1/2".into(), h.clone()];
    u3.title = vec!["u_3 on the cut y = 1/2".into(), h];
    let f = s.interfaces.first().ok_or_else(|| anyhow!("the example has an interface"))?;
    let (mut normal, mut tangential) = (Plot::default(), Plot::default());
    for face in f.mesh.faces() {
        let corners: Vec<P2> =
            face.nodes().iter().map(|&p| [f.mesh.points()[p][0], f.mesh.points()[p][1]]).collect();
        let tn: Vec<f64> = face.nodes().iter().map(|&p| f.normal_traction[p]).collect();
        let tt: Vec<f64> = face.nodes().iter().map(|&p| f.tangential_traction[p][0]).collect();
        add_polygon(&mut normal, &corners, &tn);
        add_polygon(&mut tangential, &corners, &tt);
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

/// A magnification for a title: "50", "2000", "0.5".
fn label_factor(m: f64) -> String {
    if m >= 1.0 {
        format!("{m:.0}")
    } else {
        format!("{m}")
    }
}

fn print_report(dir: &Path, p: &WarpedGlue, s: &Solved, magnification: f64, picture_seconds: f64) {
    let (nm, ns) = (p.slave_cells * p.ratio, p.slave_cells);
    println!("seam example warped-glue → {}", dir.display());
    println!(
        "  meshes     lower.msh {nm}×{nm}×{} hexahedra (master), upper.msh {ns}×{ns}×{} hexahedra (slave), h_s/h_m = {}",
        p.master_layers, p.slave_layers, p.ratio
    );
    println!(
        "  interface  z = 1/2 + {} sin 2πx sin πy; clamped at z = 0, traction {} at z = 1; E = 1000, ν = 0.3",
        p.amplitude,
        solve::vector(p.traction)
    );
    for line in solve::report(s) {
        println!("  {line}");
    }
    println!(
        "  picture    warped-glue.png: u_1 and u_3 on the cut y = 1/2 (deformation ×{}), interface tractions; {picture_seconds:.2} s",
        label_factor(magnification)
    );
    let case = dir.join("case.toml");
    println!("  rerun      seam solve {} --force", PathBuf::from(&case).display());
}
