//! Shared helpers of the integration tests.
#![allow(dead_code)]

use seam::{nodal_normals, Cell, Face, Facing, MortarOptions, Multiplier, Point3, SurfaceMesh, VolumeMesh};
use seam_fem::assembly::{geometry, map_point};
use seam_fem::generate::{block, BlockKind, Grid, Side};
use seam_fem::{recover_stresses, traction, CellKind, Dirichlet, Material};
use seam_fem::{solve_coupled, Body, Coupling, Interface, Solution, SolveOptions, Solver};

/// A smooth, non-affine map of the unit cube (positive Jacobian).
pub fn warp(u: f64, v: f64, w: f64) -> Point3 {
    use std::f64::consts::PI;
    [
        1.2 * u + 0.1 * (PI * v).sin() * w,
        0.9 * v + 0.15 * u * u + 0.05 * w,
        0.8 * w + 0.1 * (PI * u).sin() * v + 0.05 * u,
    ]
}

/// SplitMix64 in [-1, 1).
pub struct Rng(pub u64);

impl Rng {
    pub fn symmetric(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        2.0 * ((z >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    }
}

/// An n³ block of `kind` on the warped cube with interior points (and pyramid
/// centres) moved at random by up to `jitter` cell sizes: general, non-affine cells.
pub fn distorted(kind: BlockKind, n: usize, jitter: f64) -> (VolumeMesh, Grid) {
    let grid = Grid::new(n, n, n);
    let mesh = block(n, n, n, warp, kind);
    let mut rng = Rng(n as u64 * 31 + kind as u64);
    let h = 1.0 / n as f64;
    let points: Vec<Point3> = mesh
        .points()
        .iter()
        .enumerate()
        .map(|(p, x)| {
            if grid.on_boundary(p) {
                *x
            } else {
                let d = [rng.symmetric(), rng.symmetric(), rng.symmetric()];
                [x[0] + jitter * h * d[0], x[1] + jitter * h * d[1], x[2] + jitter * h * d[2]]
            }
        })
        .collect();
    (VolumeMesh::new(points, mesh.cells().to_vec()).unwrap(), grid)
}

/// The affine field u = A x + c of the patch tests.
pub const A: [[f64; 3]; 3] = [[1e-3, 2e-4, -3e-4], [-1e-4, -5e-4, 4e-4], [3e-4, 1e-4, 7e-4]];
/// Its translation.
pub const C: [f64; 3] = [1e-3, -2e-3, 5e-4];

pub fn affine(x: Point3) -> [f64; 3] {
    Affine::PATCH.at(x)
}

/// The constant stress of the affine field (Voigt xx yy zz yz xz xy).
pub fn affine_stress(m: &Material) -> [f64; 6] {
    Affine::PATCH.stress(m)
}

/// An affine displacement u = a x + c: constant strain and stress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine {
    /// The gradient ∇u.
    pub a: [[f64; 3]; 3],
    /// The translation.
    pub c: [f64; 3],
}

impl Affine {
    /// The field of the patch tests, u = A x + C.
    pub const PATCH: Affine = Affine { a: A, c: C };

    /// u(x).
    pub fn at(&self, x: Point3) -> [f64; 3] {
        let (a, c) = (&self.a, &self.c);
        std::array::from_fn(|i| c[i] + a[i][0] * x[0] + a[i][1] * x[1] + a[i][2] * x[2])
    }

    /// Its constant stress (Voigt xx yy zz yz xz xy).
    pub fn stress(&self, m: &Material) -> [f64; 6] {
        let a = &self.a;
        m.stress([a[0][0], a[1][1], a[2][2], a[1][2] + a[2][1], a[0][2] + a[2][0], a[0][1] + a[1][0]])
    }
}

/// The traction σ n of a Voigt stress.
pub fn stress_vector(s: &[f64; 6], n: Point3) -> [f64; 3] {
    let t = tensor(s);
    std::array::from_fn(|i| t[i][0] * n[0] + t[i][1] * n[1] + t[i][2] * n[2])
}

/// σ as a 3×3 tensor from Voigt.
pub fn tensor(s: &[f64; 6]) -> [[f64; 3]; 3] {
    [[s[0], s[5], s[4]], [s[5], s[1], s[3]], [s[4], s[3], s[2]]]
}

pub fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The kind name of a cell.
pub fn kind_name(c: &Cell) -> &'static str {
    match c {
        Cell::Tet4(_) => "tet",
        Cell::Hex8(_) => "hex",
        Cell::Prism6(_) => "prism",
        Cell::Pyramid5(_) => "pyramid",
        Cell::Tet10(_) => "tet10",
        Cell::Hex20(_) => "hex20",
        Cell::Hex27(_) => "hex27",
        Cell::Prism15(_) => "prism15",
        Cell::Prism18(_) => "prism18",
        Cell::Pyramid13(_) => "pyramid13",
        Cell::Pyramid14(_) => "pyramid14",
        Cell::Tet14(_) => "tet14",
    }
}

pub const KINDS: [BlockKind; 4] = [BlockKind::Hex, BlockKind::Tet, BlockKind::Prism, BlockKind::Pyramid];

/// The mixed Gmsh mesh (tets, hexes, pyramids) from seam-io's fixtures.
pub fn hybrid() -> VolumeMesh {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../seam-io/tests/data/hybrid_pyramid.v41.ascii.msh");
    seam_io::read_volume_file(path, None).unwrap()
}

/// The manufactured smooth solution of the convergence tests
///
/// ```text
/// u = s (sin x, z cos y, x y z),   b = −div σ(u) = −s [μ Δu + (λ+μ) ∇(div u)]
/// div u = s (cos x − z sin y + x y),   Δu = s (−sin x, −z cos y, 0)
/// ```
pub mod manufactured {
    use seam::Point3;
    use seam_fem::Material;

    /// The scale s.
    pub const S: f64 = 1e-2;

    /// u(x).
    pub fn exact(x: Point3) -> [f64; 3] {
        [S * x[0].sin(), S * x[2] * x[1].cos(), S * x[0] * x[1] * x[2]]
    }

    /// ∇u: g[a][k] = ∂u_a/∂x_k.
    pub fn gradient(x: Point3) -> [[f64; 3]; 3] {
        let [a, b, c] = x;
        [[S * a.cos(), 0.0, 0.0], [0.0, -S * c * b.sin(), S * b.cos()], [S * b * c, S * a * c, S * a * b]]
    }

    /// σ(u) at x (Voigt xx yy zz yz xz xy).
    pub fn stress(m: &Material, x: Point3) -> [f64; 6] {
        let g = gradient(x);
        m.stress([g[0][0], g[1][1], g[2][2], g[1][2] + g[2][1], g[0][2] + g[2][0], g[0][1] + g[1][0]])
    }

    /// The body force b = −div σ(u).
    pub fn load(m: &Material) -> impl Fn(Point3) -> [f64; 3] + Sync {
        let (l, mu) = m.lame();
        move |x| {
            let [a, b, c] = x;
            let grad_div = [-a.sin() + b, -c * b.cos() + a, -b.sin()];
            let lap = [-a.sin(), -c * b.cos(), 0.0];
            std::array::from_fn(|i| -S * (mu * lap[i] + (l + mu) * grad_div[i]))
        }
    }
}

/// Squared errors and squared norms of a discrete field against an exact one,
/// summed over cells (of one or several meshes): L2, H1 seminorm, energy.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorSums {
    /// ∫ |u − u_h|² and ∫ |u|².
    pub l2: [f64; 2],
    /// ∫ |∇(u − u_h)|² and ∫ |∇u|².
    pub h1: [f64; 2],
    /// ∫ ε(u − u_h):C:ε(u − u_h) and ∫ ε(u):C:ε(u).
    pub energy: [f64; 2],
}

/// Relative errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Errors {
    /// ‖u − u_h‖_L2 / ‖u‖_L2.
    pub l2: f64,
    /// |u − u_h|_H1 / |u|_H1.
    pub h1: f64,
    /// ‖u − u_h‖_energy / ‖u‖_energy.
    pub energy: f64,
}

impl ErrorSums {
    /// The sums of both.
    pub fn plus(self, o: ErrorSums) -> ErrorSums {
        let add = |a: [f64; 2], b: [f64; 2]| [a[0] + b[0], a[1] + b[1]];
        ErrorSums { l2: add(self.l2, o.l2), h1: add(self.h1, o.h1), energy: add(self.energy, o.energy) }
    }

    /// The relative errors.
    pub fn relative(&self) -> Errors {
        let r = |a: [f64; 2]| (a[0] / a[1]).sqrt();
        Errors { l2: r(self.l2), h1: r(self.h1), energy: r(self.energy) }
    }
}

/// [`ErrorSums`] of u_h (3 dofs per point of `mesh`) against `exact` with
/// gradient `gradient`, by the volume rules of degree 5.
pub fn error_sums(
    mesh: &VolumeMesh,
    m: &Material,
    u: &[f64],
    exact: impl Fn(Point3) -> [f64; 3],
    gradient: impl Fn(Point3) -> [[f64; 3]; 3],
) -> ErrorSums {
    let (l, mu) = m.lame();
    let rules = CellKind::ALL.map(|k| k.rule(5));
    let mut s = ErrorSums::default();
    let energy = |g: &[[f64; 3]; 3]| {
        let eps: [[f64; 3]; 3] = std::array::from_fn(|a| std::array::from_fn(|k| 0.5 * (g[a][k] + g[k][a])));
        let tr = eps[0][0] + eps[1][1] + eps[2][2];
        let dd: f64 =
            (0..3).flat_map(|a| (0..3).map(move |k| (a, k))).map(|(a, k)| eps[a][k] * eps[a][k]).sum();
        l * tr * tr + 2.0 * mu * dd
    };
    for cell in mesh.cells() {
        let kind = CellKind::of(cell);
        let x: Vec<Point3> = cell.nodes().iter().map(|&p| mesh.points()[p]).collect();
        let rule = &rules[kind as usize];
        for (xi, w) in rule.iter() {
            let geo = geometry(kind, &x, xi).unwrap();
            let wd = w * geo.det.abs();
            let n = kind.shape(xi);
            let y = map_point(kind, &x, xi);
            let (ue, ge) = (exact(y), gradient(y));
            let mut uh = [0.0; 3];
            let mut gh = [[0.0; 3]; 3];
            for (i, &p) in cell.nodes().iter().enumerate() {
                for a in 0..3 {
                    uh[a] += n[i] * u[3 * p + a];
                    for k in 0..3 {
                        gh[a][k] += geo.grads[i][k] * u[3 * p + a];
                    }
                }
            }
            let ge_minus: [[f64; 3]; 3] =
                std::array::from_fn(|a| std::array::from_fn(|k| ge[a][k] - gh[a][k]));
            for a in 0..3 {
                s.l2[0] += wd * (ue[a] - uh[a]).powi(2);
                s.l2[1] += wd * ue[a].powi(2);
                for k in 0..3 {
                    s.h1[0] += wd * ge_minus[a][k].powi(2);
                    s.h1[1] += wd * ge[a][k].powi(2);
                }
            }
            s.energy[0] += wd * energy(&ge_minus);
            s.energy[1] += wd * energy(&ge);
        }
    }
    s
}

/// The least-squares slope of log e against log h: the fitted convergence rate.
pub fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    assert!(h.len() == e.len() && h.len() >= 2, "a rate needs two or more (h, e) pairs");
    let (x, y): (Vec<f64>, Vec<f64>) = h.iter().zip(e).map(|(h, e)| (h.ln(), e.ln())).unzip();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

/// Solves two glued bodies, master `bodies[0]` and slave `bodies[1]`, on one
/// interface of facing surfaces, with the direct solver.
pub fn solve_two(
    bodies: &[Body],
    master_surface: &SurfaceMesh,
    slave_surface: &SurfaceMesh,
    multiplier: Multiplier,
) -> Solution {
    solve_two_with(bodies, master_surface, slave_surface, multiplier, Solver::Direct)
}

/// [`solve_two`] by `solver`.
pub fn solve_two_with(
    bodies: &[Body],
    master_surface: &SurfaceMesh,
    slave_surface: &SurfaceMesh,
    multiplier: Multiplier,
    solver: Solver,
) -> Solution {
    let options = MortarOptions { multiplier, facing: Facing::Opposite, ..MortarOptions::default() };
    let interfaces = [Interface {
        master: 0,
        master_surface,
        slave: 1,
        slave_surface,
        options,
        kind: Coupling::Glue,
        friction: 0.0,
    }];
    solve_coupled(bodies, &interfaces, &SolveOptions { solver, ..SolveOptions::default() }).unwrap()
}

/// (master body, master surface, slave body, slave surface).
pub type Glue = (usize, SurfaceMesh, usize, SurfaceMesh);

/// The glued patch tests (`tests/glue_supports.rs`): solves and returns the
/// largest relative error of displacement, cell stress and slave traction
/// against the affine `field`, and the method that solved.
pub fn glued_patch_error(
    label: &str,
    parts: &[&Part],
    loads: Vec<Vec<f64>>,
    dirichlet: Vec<Dirichlet>,
    glues: &[Glue],
    field: &Affine,
    (multiplier, solver): (Multiplier, Solver),
) -> (f64, &'static str) {
    let material = Material::new(1000.0, 0.3).unwrap();
    let sigma = field.stress(&material);
    let bodies: Vec<Body> = parts
        .iter()
        .zip(loads)
        .zip(dirichlet)
        .map(|((part, load), dirichlet)| Body {
            mesh: &part.mesh,
            material,
            load,
            dirichlet,
            ties: Vec::new(),
        })
        .collect();
    let options = MortarOptions { multiplier, facing: Facing::Opposite, ..MortarOptions::default() };
    let interfaces: Vec<Interface> = glues
        .iter()
        .map(|(master, master_surface, slave, slave_surface)| Interface {
            master: *master,
            master_surface,
            slave: *slave,
            slave_surface,
            options,
            kind: Coupling::Glue,
            friction: 0.0,
        })
        .collect();
    let sol = solve_coupled(&bodies, &interfaces, &SolveOptions { solver, ..Default::default() }).unwrap();

    let (mut u_error, mut s_error, mut t_error) = (0.0f64, 0.0f64, 0.0f64);
    let u_scale =
        parts.iter().flat_map(|p| p.mesh.points().iter().map(|&x| max_abs(&field.at(x)))).fold(0.0, f64::max);
    let s_scale = max_abs(&sigma);
    for (b, part) in parts.iter().enumerate() {
        for (p, &x) in part.mesh.points().iter().enumerate() {
            let e = field.at(x);
            let diff: Vec<f64> = (0..3).map(|c| sol.displacement[b][3 * p + c] - e[c]).collect();
            u_error = u_error.max(max_abs(&diff) / u_scale);
        }
        let s = recover_stresses(&part.mesh, &material, &sol.displacement[b]).unwrap();
        for cell in &s.cell {
            let diff: Vec<f64> = (0..6).map(|k| cell[k] - sigma[k]).collect();
            s_error = s_error.max(max_abs(&diff) / s_scale);
        }
    }
    for ((_, _, _, slave_surface), glued) in glues.iter().zip(&sol.interfaces) {
        let normals = nodal_normals(slave_surface);
        for p in (0..normals.len()).filter(|&p| glued.mortar.covered[p]) {
            let t = stress_vector(&sigma, normals[p]);
            let diff: Vec<f64> = (0..3).map(|c| glued.traction[p][c] - t[c]).collect();
            t_error = t_error.max(max_abs(&diff) / s_scale);
        }
    }
    let solver_name = match solver {
        Solver::Direct => "direct",
        Solver::Pcg(_) => "PCG",
        Solver::Petsc(_) => "PETSc",
    };
    println!(
        "  {label:<34} {:<9} {solver_name:<7} u {u_error:.1e}  σ {s_error:.1e}  t {t_error:.1e}  ({})",
        format!("{multiplier:?}"),
        sol.report.method
    );
    (u_error.max(s_error).max(t_error), sol.report.method)
}

/// The rollers patch test (`tests/glue_supports.rs`): a master block of
/// `m` = (cells, kind) under a slave block `s` on the plane z = 1 + slope·x,
/// both on a roller u_x = 0 at x = 0 touching the interface, the master
/// clamped to the exact field at z = 0, every other outer face loaded by σ n;
/// biaxial with σ_yz. The error and method of [`glued_patch_error`] and a
/// label.
pub fn rollers_patch_error(
    m: ([usize; 3], BlockKind),
    s: ([usize; 3], BlockKind),
    slope: f64,
    variant: (Multiplier, Solver),
) -> (f64, &'static str, String) {
    let field =
        Affine { a: [[1e-3, 0.0, 0.0], [0.0, -5e-4, 4e-4], [0.0, 1e-4, 7e-4]], c: [0.0, -2e-3, 5e-4] };
    let sigma = field.stress(&Material::new(1000.0, 0.3).unwrap());
    let interface = move |x: f64| 1.0 + slope * x;
    let master = Part::new(m.0, m.1, |u, v, w| [u, v, w * interface(u)]);
    let slave = Part::new(s.0, s.1, |u, v, w| [u, v, interface(u) + w * (1.7 - interface(u))]);
    let mut fixed = [Dirichlet::new(), Dirichlet::new()];
    master.fix(&mut fixed[0], &field, Side::ZMin, [true; 3]);
    for (part, d) in [&master, &slave].into_iter().zip(&mut fixed) {
        part.fix(d, &field, Side::XMin, [true, false, false]);
    }
    use Side::*;
    let loads = vec![master.load(&sigma, &[XMax, YMin, YMax]), slave.load(&sigma, &[XMax, YMin, YMax, ZMax])];
    let glues = [(0, master.side(ZMax), 1, slave.side(ZMin))];
    let label = format!("{:?}|{:?} slope {slope}", m.1, s.1);
    let (e, method) =
        glued_patch_error(&label, &[&master, &slave], loads, fixed.to_vec(), &glues, &field, variant);
    (e, method, label)
}

/// The crossline patch test (`tests/glue_supports.rs`): blocks A = [0,1]³,
/// B = [1,2]×[0,1]² and C = [0,2]×[0,1]×[1,1.6] of `kinds`, glued A|B,
/// A|C and B|C, C's points on the line x = 1, z = 1 slave of two
/// interfaces; the patch field, A clamped at z = 0, all other outer faces
/// loaded. The error and method of [`glued_patch_error`] and a label.
pub fn crossline_patch_error(
    kinds: [BlockKind; 3],
    variant: (Multiplier, Solver),
) -> (f64, &'static str, String) {
    use Side::*;
    let field = Affine::PATCH;
    let sigma = field.stress(&Material::new(1000.0, 0.3).unwrap());
    let a = Part::new([3, 3, 3], kinds[0], |u, v, w| [u, v, w]);
    let b = Part::new([2, 4, 3], kinds[1], |u, v, w| [1.0 + u, v, w]);
    let c = Part::new([4, 5, 2], kinds[2], |u, v, w| [2.0 * u, v, 1.0 + 0.6 * w]);
    let mut fixed = [Dirichlet::new(), Dirichlet::new(), Dirichlet::new()];
    a.fix(&mut fixed[0], &field, ZMin, [true; 3]);
    let loads = vec![
        a.load(&sigma, &[XMin, YMin, YMax]),
        b.load(&sigma, &[XMax, YMin, YMax, ZMin]),
        c.load(&sigma, &[XMin, XMax, YMin, YMax, ZMax]),
    ];
    let glues = [
        (0, a.side(XMax), 1, b.side(XMin)),
        (0, a.side(ZMax), 2, c.side_where(ZMin, |[i, _, _]| i <= 2)),
        (1, b.side(ZMax), 2, c.side_where(ZMin, |[i, _, _]| i >= 2)),
    ];
    let label = format!("crossline {kinds:?}");
    let (e, method) =
        glued_patch_error(&label, &[&a, &b, &c], loads, fixed.to_vec(), &glues, &field, variant);
    (e, method, label)
}

/// A structured block and its grid, with the patch tests' loads and supports.
pub struct Part {
    pub mesh: VolumeMesh,
    pub grid: Grid,
}

impl Part {
    pub fn new(n: [usize; 3], kind: BlockKind, map: impl Fn(f64, f64, f64) -> Point3) -> Part {
        Part { mesh: block(n[0], n[1], n[2], map, kind), grid: Grid::new(n[0], n[1], n[2]) }
    }

    pub fn side(&self, side: Side) -> SurfaceMesh {
        self.grid.side_faces(&self.mesh, side).unwrap()
    }

    /// The faces on `side` whose grid points all satisfy `keep`.
    pub fn side_where(&self, side: Side, keep: impl Fn([usize; 3]) -> bool) -> SurfaceMesh {
        let all = self.side(side);
        let faces: Vec<Face> = all
            .faces()
            .iter()
            .filter(|f| f.nodes().iter().all(|&p| keep(self.grid.ijk(p).unwrap())))
            .copied()
            .collect();
        SurfaceMesh::new(self.mesh.points().to_vec(), faces).unwrap()
    }

    /// The load ∫ N σ n over `sides`.
    pub fn load(&self, sigma: &[f64; 6], sides: &[Side]) -> Vec<f64> {
        let mut f = vec![0.0; 3 * self.mesh.points().len()];
        for &side in sides {
            for (a, b) in f.iter_mut().zip(traction(&self.side(side), |_, n| stress_vector(sigma, n))) {
                *a += b;
            }
        }
        f
    }

    /// The exact values of `field` on `side`, in the components `which`.
    pub fn fix(&self, dirichlet: &mut Dirichlet, field: &Affine, side: Side, which: [bool; 3]) {
        for p in self.grid.side_points(side) {
            let u = field.at(self.mesh.points()[p]);
            dirichlet.fix(p, std::array::from_fn(|c| which[c].then_some(u[c])));
        }
    }
}

/// The material of the patch tests.
pub fn material() -> Material {
    Material::new(210e3, 0.3).unwrap()
}

/// Max nodal error of u against the affine field, relative to max |u_exact|, and
/// max cell and nodal stress errors relative to max |σ|.
pub fn check_affine(mesh: &VolumeMesh, u: &[f64], label: &str) {
    let exact: Vec<f64> = mesh.points().iter().flat_map(|&x| affine(x)).collect();
    let diff: Vec<f64> = u.iter().zip(&exact).map(|(a, b)| a - b).collect();
    let err = max_abs(&diff) / max_abs(&exact);
    assert!(err < 1e-10, "{label}: displacement error {err:e}");
    let s = recover_stresses(mesh, &material(), u).unwrap();
    let sigma = affine_stress(&material());
    let scale = max_abs(&sigma);
    for (c, cs) in s.cell.iter().enumerate() {
        let e = (0..6).map(|k| (cs[k] - sigma[k]).abs()).fold(0.0, f64::max) / scale;
        assert!(e < 1e-10, "{label}: {} cell {c} stress error {e:e}", kind_name(&mesh.cells()[c]));
    }
    for ns in &s.nodal {
        let e = (0..6).map(|k| (ns[k] - sigma[k]).abs()).fold(0.0, f64::max) / scale;
        assert!(e < 1e-10, "{label}: nodal stress error {e:e}");
    }
    let vm = seam_fem::von_mises(&sigma);
    assert!(s.cell_von_mises.iter().all(|v| (v - vm).abs() < 1e-10 * vm));
}
pub mod hertz;
pub mod mixed;
pub mod stack;

/// The thick cylindrical shell sector of the glued convergence studies:
/// θ ∈ [THETA0, THETA0 + L/R], z ∈ [0, L], split at the radius R.
pub mod shell {
    use super::manufactured::{exact, gradient, load, stress};
    use super::{error_sums, solve_two_with, stress_vector, ErrorSums, Errors};
    use seam::{Multiplier, Point3};
    use seam_fem::generate::{block, BlockKind, Grid, Side};
    use seam_fem::{body_force, traction, Body, Dirichlet, Material, Solver};

    /// The radius of the interface.
    pub const R: f64 = 1.5;
    /// The sector's length along z and arc length at R.
    pub const L: f64 = 0.8;
    /// The first angle.
    pub const THETA0: f64 = 0.2;

    /// The polar map of the unit cube (u, v, w) → (θ, z, r) with r ∈ [r0, r1].
    pub fn sector(r0: f64, r1: f64) -> impl Fn(f64, f64, f64) -> Point3 {
        move |u, v, w| {
            let (theta, r) = (THETA0 + L / R * u, r0 + (r1 - r0) * w);
            [r * theta.cos(), r * theta.sin(), L * v]
        }
    }

    /// The boundary conditions on the sides θ = const and z = const (the faces
    /// r = const away from the interface are always prescribed).
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub enum Sides {
        /// Loaded by the exact traction σ(u) n.
        Loaded,
        /// Prescribed u = u_exact, slave interface nodes on them included (their
        /// multipliers are dropped by `solve_coupled`).
        Prescribed,
    }

    /// One level of the glued convergence study (`tests/glue_convergence.rs`):
    /// the manufactured solution on the sector, the slave with n³ cells, the
    /// master `nm` in θ and z and ⌈nm/4⌉ in r, solved by `solver`. Returns the
    /// relative errors and the largest gap or overlap.
    pub fn level(n: usize, nm: usize, multiplier: Multiplier, sides: Sides, solver: Solver) -> (Errors, f64) {
        let material = Material::new(100.0, 0.3).unwrap();
        let nr = nm.div_ceil(4);
        let master = (block(nm, nm, nr, sector(R - L / 4.0, R), BlockKind::Hex), Grid::new(nm, nm, nr));
        let slave = (block(n, n, n, sector(R, R + L), BlockKind::Hex), Grid::new(n, n, n));
        let bodies: Vec<Body> = [(&master, Side::ZMax), (&slave, Side::ZMin)]
            .into_iter()
            .map(|((mesh, grid), interface)| {
                let mut f = body_force(mesh, load(&material)).unwrap();
                let mut dirichlet = Dirichlet::new();
                for side in Side::ALL.into_iter().filter(|&s| s != interface) {
                    if sides == Sides::Loaded && !matches!(side, Side::ZMin | Side::ZMax) {
                        let faces = grid.side_faces(mesh, side).unwrap();
                        let t = traction(&faces, |x, n| stress_vector(&stress(&material, x), n));
                        f.iter_mut().zip(t).for_each(|(a, b)| *a += b);
                        continue;
                    }
                    for p in grid.side_points(side) {
                        dirichlet.fix(p, exact(mesh.points()[p]).map(Some));
                    }
                }
                Body { mesh, material, load: f, dirichlet, ties: Vec::new() }
            })
            .collect();
        let master_surface = master.1.side_faces(&master.0, Side::ZMax).unwrap();
        let slave_surface = slave.1.side_faces(&slave.0, Side::ZMin).unwrap();
        let sol = solve_two_with(&bodies, &master_surface, &slave_surface, multiplier, solver);
        let sums = bodies
            .iter()
            .zip(&sol.displacement)
            .map(|(b, u)| error_sums(b.mesh, &material, u, exact, gradient))
            .fold(ErrorSums::default(), ErrorSums::plus);
        let summary = &sol.interfaces[0].mortar.summary;
        (sums.relative(), summary.max_gap.max(summary.max_overlap))
    }
}
