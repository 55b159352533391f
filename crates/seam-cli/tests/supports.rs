//! Patch tests through `seam solve`, with supports and other interfaces
//! touching the slave sides: the CLI versions of seam-fem's `glue_supports.rs`
//! and `mixed.rs`. Every case has an affine exact solution that the
//! discretisation reproduces, so the displacement in the bodies' VTU files
//! (point data) and the stress (cell data) must equal it to 1e-10 relative,
//! and the interface files' `traction` (the force per area the master exerts
//! on the slave) must be σ n_s, n_s the slave's outward normal.
//!
//! Case files allow only constant Dirichlet values, so the supports are
//! rollers (u_x = 0 on x = 0, u_y = 0 on y = 0, u_z = 0 on z = 0) and the
//! stress is diagonal, σ = diag(SX, SY, SZ), u = ε x.
//!
//! - Rollers: a lower block (master) under an upper block (slave) meeting on
//!   the plane z = 1/2 + s (x − 1/2), s = 0 and s = 0.2 (the tilted interface
//!   carries normal and shear traction); both bodies on rollers at x = 0 and
//!   y = 0 (both faces touch the interface), the lower one at z = 0; the
//!   x = 1 and y = 1 faces of both and the top loaded by σ n. Hex|hex,
//!   tet|tet, hex|tet and tet|hex, non-matching, and a 6×6×6 slave over a
//!   2×2×1 master (so that dual multipliers are eliminated: every glue
//!   method of `summary.json` runs); standard and dual multipliers; direct
//!   and PCG solvers.
//! - Crossline: A = [0,1]³, B = [1,2]×[0,1]², C = [0,2]×[0,1]×[1,1.6] glued
//!   A|B (x = 1), A|C and B|C (z = 1, C's bottom split at x = 1 into two
//!   physical surfaces), C slave of both upper interfaces: C's points on the
//!   line x = 1, z = 1 are slave points of two interfaces, B's are slave of
//!   A|B and master of B|C; B and C on rollers that touch their slave sides.
//!   C's crossline points are constrained by A|C (the earlier interface):
//!   the B|C file marks them `constrained` = 0, and its `traction` there is
//!   the modified multiplier's value, still σ n. Standard and dual, direct
//!   and PCG, hex and tet.
//! - Glue and contact: base | contact | block | glue | cap under a uniform
//!   pressure P on the cap's top, rollers at x = 0 and y = 0 on every body,
//!   u_z = 0 under the base: uniaxial σ_zz = −P, the contact pressure P at
//!   every (active) contact point, the glued traction (0, 0, P). Contact
//!   multipliers dual and lumped, glue dual and standard, direct and PCG.
//!
//! PCG runs with `--rtol 1e-13`. Measured (`cargo test -p seam-cli --test
//! supports -- --nocapture`): rollers ≤ 4e-13 (direct ≤ 6e-14), crossline
//! ≤ 1e-12 (direct ≤ 5e-14), stack ≤ 1.2e-12 (the contact pressure; displacement and stress
//! ≤ 6e-13), KKT ≤ 3e-15.

use crate::common;

use common::{json, seam, stderr, vtu_field};
use seam::SurfaceMesh;
use seam_fem::generate::{block, BlockKind, Grid, Side};
use std::path::Path;

const RTOL: f64 = 1e-10;
const E: f64 = 1000.0;
const NU: f64 = 0.3;
/// The diagonal stress of the glue patch tests: σ_xx, σ_yy, σ_zz.
const S: [f64; 3] = [2.0, -1.0, -3.0];

type Point = [f64; 3];
/// A physical surface of a block: its name, its side, and which of the side's
/// faces (by their centroid).
type Surface = (&'static str, Side, fn(Point) -> bool);

/// The six sides of a block under the names the cases use.
const SIDES: [(&str, Side); 6] = [
    ("xmin", Side::XMin),
    ("xmax", Side::XMax),
    ("ymin", Side::YMin),
    ("ymax", Side::YMax),
    ("bottom", Side::ZMin),
    ("top", Side::ZMax),
];

fn all(_: Point) -> bool {
    true
}

/// Writes an n[0] × n[1] × n[2] block of `kind` cells mapped by `map` from the
/// unit cube as a Gmsh file; each surface is (name, side, which of the side's
/// faces by their centroid).
fn write_mesh(
    path: &Path,
    n: [usize; 3],
    kind: BlockKind,
    map: impl Fn(f64, f64, f64) -> Point,
    surfaces: &[Surface],
) {
    let mesh = block(n[0], n[1], n[2], map, kind);
    let grid = Grid::new(n[0], n[1], n[2]);
    let x = mesh.points();
    let surfaces: Vec<(&str, SurfaceMesh)> = surfaces
        .iter()
        .map(|&(name, side, keep)| {
            let faces = grid
                .side_faces(&mesh, side)
                .unwrap()
                .faces()
                .iter()
                .filter(|f| {
                    let nodes = f.nodes();
                    let c: Point = std::array::from_fn(|k| {
                        nodes.iter().map(|&p| x[p][k]).sum::<f64>() / nodes.len() as f64
                    });
                    keep(c)
                })
                .copied()
                .collect();
            (name, SurfaceMesh::new(x.to_vec(), faces).unwrap())
        })
        .collect();
    let refs: Vec<(&str, &SurfaceMesh)> = surfaces.iter().map(|(n, s)| (*n, s)).collect();
    seam_io::write_volume_msh_file(path, &mesh, "body", &refs).unwrap();
}

/// The six sides of a block, each whole.
fn sides() -> Vec<Surface> {
    SIDES.iter().map(|&(name, side)| (name, side, all as fn(Point) -> bool)).collect()
}

/// A case file's text, built up section by section.
#[derive(Default)]
struct Case(String);

impl Case {
    fn body(&mut self, name: &str, young: f64) -> &mut Self {
        self.0 += &format!(
            "[[body]]\nname = \"{name}\"\nmesh = \"{name}.msh\"\nyoung = {young:?}\npoisson = {NU:?}\n\n"
        );
        self
    }

    fn interface(&mut self, master: &str, slave: &str, kind: &str, multiplier: &str) -> &mut Self {
        self.0 += &format!(
            "[[interface]]\nmaster = \"{master}\"\nslave = \"{slave}\"\nkind = \"{kind}\"\n\
             multiplier = \"{multiplier}\"\n\n"
        );
        self
    }

    /// A roller: component `c` (ux, uy, uz) is 0 on `boundary`.
    fn roller(&mut self, boundary: &str, c: &str) -> &mut Self {
        self.0 += &format!("[[dirichlet]]\nboundary = \"{boundary}\"\n{c} = 0.0\n\n");
        self
    }

    fn load(&mut self, boundary: &str, t: Point) -> &mut Self {
        self.0 +=
            &format!("[[traction]]\nboundary = \"{boundary}\"\nt = [{:?}, {:?}, {:?}]\n\n", t[0], t[1], t[2]);
        self
    }

    fn write(&self, dir: &Path) {
        std::fs::write(dir.join("case.toml"), &self.0).unwrap();
    }
}

/// Runs `seam solve case.toml --solver SOLVER --rtol 1e-13` in `dir`; summary.json.
fn solve(dir: &Path, solver: &str) -> serde_json::Value {
    let o = seam(&["solve", "case.toml", "--solver", solver, "--rtol", "1e-13"], dir);
    assert!(o.status.success(), "{}", stderr(&o));
    json(&dir.join("out/summary.json"))
}

/// The strain of the diagonal stress S (E, ν): ε_ii = (S_i − ν (S_j + S_k)) / E.
fn strain() -> Point {
    std::array::from_fn(|i| (S[i] - NU * (S[(i + 1) % 3] + S[(i + 2) % 3])) / E)
}

/// u = ε x for the diagonal stress S.
fn exact(x: Point) -> Point {
    let e = strain();
    std::array::from_fn(|i| e[i] * x[i])
}

/// The diagonal stress in Voigt order (xx yy zz yz xz xy).
fn voigt() -> [f64; 6] {
    [S[0], S[1], S[2], 0.0, 0.0, 0.0]
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The largest relative errors (displacement, cell stress) of the bodies'
/// VTU files in `out` against the exact displacement `u(body, x)` and the
/// stress `sigma(body)`: relative to the largest exact displacement over all
/// bodies' points and the largest stress component.
fn body_errors(
    out: &Path,
    bodies: &[&str],
    u: impl Fn(usize, Point) -> Point,
    sigma: impl Fn(usize) -> [f64; 6],
) -> (f64, f64) {
    let mut fields = Vec::new();
    for (b, name) in bodies.iter().enumerate() {
        let path = out.join(format!("{name}.vtu"));
        let (points, displacement) = vtu_field(&path, "displacement", false);
        let (_, stress) = vtu_field(&path, "stress", true);
        assert_eq!(displacement.len(), 3 * points.len(), "{name}");
        assert!(!stress.is_empty() && stress.len() % 6 == 0, "{name}");
        fields.push((b, points, displacement, stress));
    }
    let u_scale =
        fields.iter().flat_map(|(b, p, _, _)| p.iter().map(|&x| max_abs(&u(*b, x)))).fold(0.0, f64::max);
    let s_scale = (0..bodies.len()).map(|b| max_abs(&sigma(b))).fold(0.0, f64::max);
    assert!(u_scale > 0.0 && s_scale > 0.0);
    let (mut u_error, mut s_error) = (0.0f64, 0.0f64);
    for (b, points, displacement, stress) in &fields {
        for (x, d) in points.iter().zip(displacement.chunks(3)) {
            let e = u(*b, *x);
            u_error = u_error.max((0..3).map(|k| (d[k] - e[k]).abs()).fold(0.0, f64::max) / u_scale);
        }
        let s = sigma(*b);
        for cell in stress.chunks(6) {
            s_error = s_error.max((0..6).map(|k| (cell[k] - s[k]).abs()).fold(0.0, f64::max) / s_scale);
        }
    }
    (u_error, s_error)
}

/// A point field of an interface VTU file, through seam-io's reader.
fn interface_field(path: &Path, name: &str) -> (Vec<Point>, Vec<f64>) {
    let f = seam_io::read_vtu_file(path).unwrap();
    let values = f.point_field(name).unwrap_or_else(|| panic!("{} has no field {name}", path.display()));
    (f.mesh.points().to_vec(), values.values.clone())
}

/// The interface file's `traction` against σ n, n = `normal(x)` the slave's
/// exact outward normal, relative to `scale`: the largest error over its
/// points, and their number. Also checks that the file's `normal` is n and
/// that `constrained` is 1 except at the points `elsewhere` selects (slave
/// points of an earlier interface, where the traction is the modified
/// multiplier's value, still σ n).
fn traction_error(
    path: &Path,
    sigma: [f64; 6],
    normal: impl Fn(Point) -> Point,
    elsewhere: impl Fn(Point) -> bool,
    scale: f64,
) -> (f64, usize) {
    let (points, t) = interface_field(path, "traction");
    let (_, n) = interface_field(path, "normal");
    let (_, constrained) = interface_field(path, "constrained");
    let s = [[sigma[0], sigma[5], sigma[4]], [sigma[5], sigma[1], sigma[3]], [sigma[4], sigma[3], sigma[2]]];
    let mut error = 0.0f64;
    let mut count = 0;
    for (p, x) in points.iter().enumerate() {
        let m = normal(*x);
        for k in 0..3 {
            assert!((n[3 * p + k] - m[k]).abs() <= 1e-12, "{}: normal at {x:?}", path.display());
        }
        let expected = if elsewhere(*x) { 0.0 } else { 1.0 };
        assert_eq!(constrained[p], expected, "{}: constrained at {x:?}", path.display());
        count += 1;
        let exact: Point = std::array::from_fn(|i| s[i][0] * m[0] + s[i][1] * m[1] + s[i][2] * m[2]);
        error = error.max((0..3).map(|k| (t[3 * p + k] - exact[k]).abs()).fold(0.0, f64::max) / scale);
    }
    (error, count)
}

/// Two blocks meeting on z = 1/2 + slope (x − 1/2): "lower" (master,
/// `kinds[0]`, `n[0]` cells) and "upper" (slave, `kinds[1]`, `n[1]` cells, up
/// to z = 1.2), rollers at x = 0 and y = 0 on both and at z = 0 under the
/// lower one, σ n on the other outer faces.
fn rollers_case(dir: &Path, slope: f64, kinds: [BlockKind; 2], n: [[usize; 3]; 2], multiplier: &str) {
    let interface = move |x: f64| 0.5 + slope * (x - 0.5);
    write_mesh(&dir.join("lower.msh"), n[0], kinds[0], |u, v, w| [u, v, w * interface(u)], &sides());
    write_mesh(
        &dir.join("upper.msh"),
        n[1],
        kinds[1],
        |u, v, w| [u, v, interface(u) + w * (1.2 - interface(u))],
        &sides(),
    );
    let mut case = Case::default();
    case.body("lower", E).body("upper", E).interface("lower:top", "upper:bottom", "glue", multiplier);
    for body in ["lower", "upper"] {
        case.roller(&format!("{body}:xmin"), "ux").roller(&format!("{body}:ymin"), "uy");
        case.load(&format!("{body}:xmax"), [S[0], 0.0, 0.0]).load(&format!("{body}:ymax"), [0.0, S[1], 0.0]);
    }
    case.roller("lower:bottom", "uz").load("upper:top", [0.0, 0.0, S[2]]);
    case.write(dir);
}

#[test]
fn rollers_on_both_bodies_touching_a_flat_or_tilted_glued_interface() {
    use BlockKind::{Hex, Tet};
    let mut worst = 0.0f64;
    let mut methods = std::collections::BTreeSet::new();
    for slope in [0.0f64, 0.2] {
        let norm = (1.0 + slope * slope).sqrt();
        // The upper block's outward normal on its bottom.
        let normal = move |_: Point| [slope / norm, 0.0, -1.0 / norm];
        // The last pair, a fine slave over a coarse master, is solved by
        // elimination (reduced Cholesky) for dual multipliers; the others by
        // the saddle point (the elimination would fill in on such small meshes).
        let (usual, coarse, fine) = ([[3, 4, 2], [4, 3, 2]], [2, 2, 1], [6, 6, 6]);
        for (kinds, n) in [
            ([Hex, Hex], usual),
            ([Tet, Tet], usual),
            ([Hex, Tet], usual),
            ([Tet, Hex], usual),
            ([Hex, Hex], [coarse, fine]),
        ] {
            for multiplier in ["standard", "dual"] {
                for solver in ["direct", "pcg"] {
                    let tmp = tempfile::tempdir().unwrap();
                    rollers_case(tmp.path(), slope, kinds, n, multiplier);
                    let s = solve(tmp.path(), solver);
                    let out = tmp.path().join("out");
                    let (u, sigma) = body_errors(&out, &["lower", "upper"], |_, x| exact(x), |_| voigt());
                    let (t, points) = traction_error(
                        &out.join("upper_bottom_interface.vtu"),
                        voigt(),
                        normal,
                        |_| false,
                        max_abs(&S),
                    );
                    assert_eq!(points, (n[1][0] + 1) * (n[1][1] + 1), "the upper block's bottom points");
                    let label = format!("slope {slope} {kinds:?} {:?} {multiplier} {solver}", n[1]);
                    methods.insert(s["method"].as_str().unwrap().to_string());
                    println!(
                        "  {label:<40} u {u:.1e}  σ {sigma:.1e}  t {t:.1e}  ({})",
                        s["method"].as_str().unwrap()
                    );
                    assert!(
                        u <= RTOL && sigma <= RTOL && t <= RTOL,
                        "{label}: u {u:.3e} σ {sigma:.3e} t {t:.3e}"
                    );
                    worst = worst.max(u).max(sigma).max(t);
                }
            }
        }
    }
    println!("  rollers: largest error {worst:.1e}");
    let expected =
        ["reduced Cholesky (u_s = T u_m)", "reduced PCG, matrix-free (u_s = T u_m)", "saddle-point LDLᵀ"];
    assert_eq!(methods, expected.map(String::from).into(), "every glue solver ran");
}

/// Blocks a, b, c meeting along the line x = 1, z = 1 (see the module doc).
fn crossline_case(dir: &Path, kinds: [BlockKind; 3], multiplier: &str) {
    write_mesh(&dir.join("a.msh"), [3, 3, 3], kinds[0], |u, v, w| [u, v, w], &sides());
    write_mesh(&dir.join("b.msh"), [2, 4, 3], kinds[1], |u, v, w| [1.0 + u, v, w], &sides());
    let mut c_sides = sides();
    c_sides.retain(|s| s.0 != "bottom");
    c_sides.push(("bottom_a", Side::ZMin, |c| c[0] < 1.0));
    c_sides.push(("bottom_b", Side::ZMin, |c| c[0] > 1.0));
    write_mesh(&dir.join("c.msh"), [4, 5, 2], kinds[2], |u, v, w| [2.0 * u, v, 1.0 + 0.6 * w], &c_sides);
    let mut case = Case::default();
    case.body("a", E).body("b", E).body("c", E);
    case.interface("a:xmax", "b:xmin", "glue", multiplier)
        .interface("a:top", "c:bottom_a", "glue", multiplier)
        .interface("b:top", "c:bottom_b", "glue", multiplier);
    case.roller("a:xmin", "ux").roller("a:ymin", "uy").roller("a:bottom", "uz");
    case.roller("b:ymin", "uy").roller("b:bottom", "uz");
    case.roller("c:xmin", "ux").roller("c:ymin", "uy");
    for body in ["a", "b", "c"] {
        case.load(&format!("{body}:ymax"), [0.0, S[1], 0.0]);
    }
    case.load("b:xmax", [S[0], 0.0, 0.0]).load("c:xmax", [S[0], 0.0, 0.0]).load("c:top", [0.0, 0.0, S[2]]);
    case.write(dir);
}

#[test]
fn three_blocks_meeting_along_a_crossline() {
    use BlockKind::{Hex, Tet};
    let mut worst = 0.0f64;
    for kinds in [[Hex, Hex, Hex], [Tet, Tet, Tet], [Hex, Tet, Hex], [Tet, Hex, Tet]] {
        for (multiplier, solver) in
            [("standard", "direct"), ("dual", "direct"), ("standard", "pcg"), ("dual", "pcg")]
        {
            let tmp = tempfile::tempdir().unwrap();
            crossline_case(tmp.path(), kinds, multiplier);
            let s = solve(tmp.path(), solver);
            let out = tmp.path().join("out");
            let (u, sigma) = body_errors(&out, &["a", "b", "c"], |_, x| exact(x), |_| voigt());
            let mut t = 0.0f64;
            // c's points on the crossline (x = 1) are slave points of a|c,
            // the earlier interface: b|c does not constrain them.
            let crossline = |x: Point| x[0] == 1.0;
            let nowhere = |_: Point| false;
            for (file, normal, points, elsewhere) in [
                ("b_xmin_interface.vtu", [-1.0, 0.0, 0.0], 5 * 4, &nowhere as &dyn Fn(Point) -> bool),
                ("c_bottom_a_interface.vtu", [0.0, 0.0, -1.0], 3 * 6, &nowhere),
                ("c_bottom_b_interface.vtu", [0.0, 0.0, -1.0], 3 * 6, &crossline),
            ] {
                let (e, n) = traction_error(&out.join(file), voigt(), |_| normal, elsewhere, max_abs(&S));
                assert_eq!(n, points, "{file}");
                t = t.max(e);
            }
            let label = format!("crossline {kinds:?} {multiplier} {solver}");
            println!(
                "  {label:<40} u {u:.1e}  σ {sigma:.1e}  t {t:.1e}  ({})",
                s["method"].as_str().unwrap()
            );
            assert!(u <= RTOL && sigma <= RTOL && t <= RTOL, "{label}: u {u:.3e} σ {sigma:.3e} t {t:.3e}");
            worst = worst.max(u).max(sigma).max(t);
        }
    }
    println!("  crossline: largest error {worst:.1e}");
}

/// The pressure on the cap's top.
const P: f64 = 3.0;
/// Young's moduli of base, block and cap.
const YOUNG: [f64; 3] = [2000.0, 1000.0, 1000.0];

/// base [0,1]² × [0,1] | contact | block [0,1]² × [1,1.5] | glue | cap
/// [0,1]² × [1.5,2.2], meshes 3×4×2, 4×3×2 and 5×2×2 of `kinds`.
fn stack_case(dir: &Path, kinds: [BlockKind; 3], contact: &str, glue: &str) {
    write_mesh(&dir.join("base.msh"), [3, 4, 2], kinds[0], |u, v, w| [u, v, w], &sides());
    write_mesh(&dir.join("block.msh"), [4, 3, 2], kinds[1], |u, v, w| [u, v, 1.0 + 0.5 * w], &sides());
    write_mesh(&dir.join("cap.msh"), [5, 2, 2], kinds[2], |u, v, w| [u, v, 1.5 + 0.7 * w], &sides());
    let mut case = Case::default();
    case.body("base", YOUNG[0]).body("block", YOUNG[1]).body("cap", YOUNG[2]);
    case.interface("base:top", "block:bottom", "contact", contact).interface(
        "block:top",
        "cap:bottom",
        "glue",
        glue,
    );
    for body in ["base", "block", "cap"] {
        case.roller(&format!("{body}:xmin"), "ux").roller(&format!("{body}:ymin"), "uy");
    }
    case.roller("base:bottom", "uz").load("cap:top", [0.0, 0.0, -P]);
    case.write(dir);
}

/// The exact displacement of body `b` of the stack: uniaxial σ_zz = −P, u_z
/// continuous at z = 1 and z = 1.5.
fn stack_exact(b: usize, x: Point) -> Point {
    let strain = |b: usize| P / YOUNG[b];
    let uz = match b {
        0 => -strain(0) * x[2],
        1 => -strain(0) - strain(1) * (x[2] - 1.0),
        _ => -strain(0) - strain(1) * 0.5 - strain(2) * (x[2] - 1.5),
    };
    [NU * strain(b) * x[0], NU * strain(b) * x[1], uz]
}

#[test]
fn glue_and_contact_in_a_stack_carry_the_uniform_pressure() {
    use BlockKind::{Hex, Tet};
    let mut worst = 0.0f64;
    for kinds in [[Hex, Tet, Hex], [Tet, Hex, Tet]] {
        for contact in ["dual", "lumped"] {
            for (glue, solver) in
                [("dual", "direct"), ("dual", "pcg"), ("standard", "direct"), ("standard", "pcg")]
            {
                let tmp = tempfile::tempdir().unwrap();
                stack_case(tmp.path(), kinds, contact, glue);
                let s = solve(tmp.path(), solver);
                let out = tmp.path().join("out");
                let (u, sigma) = body_errors(&out, &["base", "block", "cap"], stack_exact, |_| {
                    [0.0, 0.0, -P, 0.0, 0.0, 0.0]
                });

                let path = out.join("block_bottom_interface.vtu");
                let (points, pressure) = interface_field(&path, "contact_pressure");
                let (_, active) = interface_field(&path, "active");
                let (_, gap) = interface_field(&path, "gap");
                assert_eq!(points.len(), 5 * 4, "the block's bottom points");
                let mut p = 0.0f64;
                for (k, x) in points.iter().enumerate() {
                    assert_eq!(active[k], 1.0, "active at {x:?}");
                    assert!(gap[k].abs() <= 1e-12, "closed at {x:?}: {}", gap[k]);
                    p = p.max((pressure[k] - P).abs() / P);
                }
                let (t, n) = traction_error(
                    &out.join("cap_bottom_interface.vtu"),
                    [0.0, 0.0, -P, 0.0, 0.0, 0.0],
                    |_| [0.0, 0.0, -1.0],
                    |_| false,
                    P,
                );
                assert_eq!(n, 6 * 3, "the cap's bottom points");
                let kkt = s["contact"]["kkt"]["max"].as_f64().unwrap();
                assert_eq!(s["contact"]["active_points"], 20);
                let label = format!("{kinds:?} contact {contact} glue {glue} {solver}");
                println!(
                    "  {label:<44} u {u:.1e}  σ {sigma:.1e}  pressure {p:.1e}  t {t:.1e}  KKT {kkt:.1e}  ({})",
                    s["method"].as_str().unwrap()
                );
                assert!(
                    u <= RTOL && sigma <= RTOL && p <= RTOL && t <= RTOL && kkt <= RTOL,
                    "{label}: u {u:.3e} σ {sigma:.3e} pressure {p:.3e} t {t:.3e} KKT {kkt:.3e}"
                );
                worst = worst.max(u).max(sigma).max(p).max(t);
            }
        }
    }
    println!("  stack: largest error {worst:.1e}");
}
