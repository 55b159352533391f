//! I10 of docs/verification.md: the operator under floating-point noise on the
//! coordinates. Meshes from mesh generators, CAD exports and
//! coordinate transforms put master vertices within round-off of slave edges;
//! the operator must move by O(ε) only.
//!
//! - [`operator_under_noise`]: matching, shifted, twisted, rotated and scaled
//!   grids of triangles, quadrilaterals and both, flat, warped and curved
//!   (cylinder patches), first and second order, standard and dual
//!   multipliers; the coordinates of both meshes perturbed by ε L (L the model
//!   size) with ε ∈ {0, 1e-16, …, 1e-8}, in the surface's tangent plane and
//!   along its normal. Asserted, with tol = 1e-12 + 10 ε: the covered area is
//!   the slave area (the master covers the slave) to tol and never above it;
//!   D's row sums are the nodal areas (standard multipliers; by a reference
//!   rule, or on curved second-order faces, where D's rule is not exact, those
//!   of the noise-free assembly), linear fields are reproduced, D x_s = B x_m,
//!   on flat scenes, and T 1 = 1, each to tol relative to the node's support
//!   (the area of its faces).
//! - [`clipping_against_exact_rationals`] and
//!   [`clipped_pieces_tile_the_slave_polygon`]: the flat clipping (C4) on
//!   random near-degenerate pairs against an exact reference computed in
//!   rational arithmetic (`num-rational`, used only here), to round-off.

use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};
use seam::curved::{shape_and_gradients, CurvedFace};
use seam::FaceKind;
use seam::{
    assemble, clip_polygon_polygon, face_polygon, polygon_area, triangle_rule, Face, Mortar, MortarOptions,
    Multiplier, Point2, Point3, Polygon, SurfaceMesh,
};

/// The noise levels, relative to the model size.
const NOISE: [f64; 10] = [0.0, 1e-16, 1e-15, 1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8];

/// `value <= tolerance`, false for NaN.
fn within(value: f64, tolerance: f64) -> bool {
    value <= tolerance
}

/// The tolerance at noise ε: round-off plus O(ε).
fn tolerance(eps: f64) -> f64 {
    1e-12 + 10.0 * eps
}

/// SplitMix64: a deterministic generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [−1, 1).
    fn symmetric(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The faces of a grid's cells.
#[derive(Clone, Copy, Debug)]
enum Cells {
    Quad4,
    Tri3,
    /// Every third cell as two triangles, the others quads.
    Mixed,
    Quad9,
    Quad8,
    Tri6,
}

impl Cells {
    fn second_order(self) -> bool {
        matches!(self, Cells::Quad9 | Cells::Quad8 | Cells::Tri6)
    }
}

/// The surface on which the grids lie: (u, v) ↦ x, with its unit normal.
#[derive(Clone, Copy, Debug)]
enum Surface {
    /// z = 0.
    Flat,
    /// A cylinder of radius 1 about the z axis, angle u, height v.
    Cylinder,
    /// z = ½ u v: its bilinear quads are warped.
    Saddle,
}

impl Surface {
    fn map(self, [u, v]: [f64; 2]) -> Point3 {
        match self {
            Surface::Flat => [u, v, 0.0],
            Surface::Cylinder => [u.cos(), u.sin(), v],
            Surface::Saddle => [u, v, 0.5 * u * v],
        }
    }

    /// The unit tangents and normal at (u, v).
    fn frame(self, [u, v]: [f64; 2]) -> [Point3; 3] {
        let (a, b) = match self {
            Surface::Flat => ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            Surface::Cylinder => ([-u.sin(), u.cos(), 0.0], [0.0, 0.0, 1.0]),
            Surface::Saddle => ([1.0, 0.0, 0.5 * v], [0.0, 1.0, 0.5 * u]),
        };
        let unit = |x: Point3| {
            let n = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
            [x[0] / n, x[1] / n, x[2] / n]
        };
        let n = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
        [unit(a), unit(b), unit(n)]
    }
}

/// A grid of `cells` of size h over the index box [i0, i1] × [j0, j1] of
/// parameter space, each index point (i, j) at parameter `place(i h, j h)`
/// (second-order nodes at half indices). Points of equal indices and
/// placement are equal bit for bit across grids.
struct Grid {
    cells: Cells,
    h: f64,
    range: [i64; 4],
}

impl Grid {
    /// The mesh and each point's parameters.
    fn mesh(&self, place: &dyn Fn([f64; 2]) -> [f64; 2], surface: Surface) -> (SurfaceMesh, Vec<[f64; 2]>) {
        let [i0, i1, j0, j1] = self.range;
        let k = if self.cells.second_order() { 2 } else { 1 };
        let (ni, nj) = (k * (i1 - i0) + 1, k * (j1 - j0) + 1);
        let mut params = Vec::new();
        for j in 0..nj {
            for i in 0..ni {
                let (a, b) = (i0 as f64 + i as f64 / k as f64, j0 as f64 + j as f64 / k as f64);
                params.push(place([a * self.h, b * self.h]));
            }
        }
        let id = |i: i64, j: i64| (j * ni + i) as usize;
        let mut faces = Vec::new();
        for j in 0..(j1 - j0) {
            for i in 0..(i1 - i0) {
                let (i, j) = (k * i, k * j);
                let c = [id(i, j), id(i + k, j), id(i + k, j + k), id(i, j + k)];
                let triangles = match self.cells {
                    Cells::Tri3 | Cells::Tri6 => true,
                    Cells::Mixed => (i + j) % 3 == 0,
                    _ => false,
                };
                let diagonal = (i / k + j / k) % 2 == 0;
                faces.extend(match (self.cells, triangles) {
                    (Cells::Quad4 | Cells::Mixed, false) => vec![Face::Quad4(c)],
                    (Cells::Tri3 | Cells::Mixed, true) if diagonal => {
                        vec![Face::Tri3([c[0], c[1], c[2]]), Face::Tri3([c[0], c[2], c[3]])]
                    }
                    (Cells::Tri3 | Cells::Mixed, true) => {
                        vec![Face::Tri3([c[0], c[1], c[3]]), Face::Tri3([c[1], c[2], c[3]])]
                    }
                    (cells, _) => {
                        let m = [id(i + 1, j), id(i + 2, j + 1), id(i + 1, j + 2), id(i, j + 1)];
                        let centre = id(i + 1, j + 1);
                        match cells {
                            Cells::Quad9 => {
                                vec![Face::Quad9([c[0], c[1], c[2], c[3], m[0], m[1], m[2], m[3], centre])]
                            }
                            Cells::Quad8 => {
                                vec![Face::Quad8([c[0], c[1], c[2], c[3], m[0], m[1], m[2], m[3]])]
                            }
                            _ if diagonal => vec![
                                Face::Tri6([c[0], c[1], c[2], m[0], m[1], centre]),
                                Face::Tri6([c[0], c[2], c[3], centre, m[2], m[3]]),
                            ],
                            _ => vec![
                                Face::Tri6([c[0], c[1], c[3], m[0], centre, m[3]]),
                                Face::Tri6([c[1], c[2], c[3], m[1], m[2], centre]),
                            ],
                        }
                    }
                });
            }
        }
        let points = params.iter().map(|&p| surface.map(p)).collect();
        (SurfaceMesh::new(points, faces).expect("a valid grid"), params)
    }
}

/// A scene: a slave grid on [0, 1]² and a master grid covering it, on one
/// surface, moved as a whole by a similarity.
#[derive(Clone, Copy, Debug)]
struct Scene {
    name: &'static str,
    surface: Surface,
    slave: (Cells, i64),
    master: (Cells, i64),
    /// The master grid's offset, in its cells, and in-plane rotation about
    /// the centre of [0, 1]², in radians.
    shift: [f64; 2],
    twist: f64,
    /// The similarity x ↦ offset + scale R x (R about the axis (1, 2, 3)).
    scale: f64,
    rotation: f64,
    offset: f64,
}

const SCENE: Scene = Scene {
    name: "",
    surface: Surface::Flat,
    slave: (Cells::Quad4, 6),
    master: (Cells::Quad4, 6),
    shift: [0.0, 0.0],
    twist: 0.0,
    scale: 1.0,
    rotation: 0.0,
    offset: 0.0,
};

impl Scene {
    /// (master, slave) with noise of size `eps` × scale in the tangent plane
    /// (`normal` false) or along the normal.
    fn meshes(&self, eps: f64, normal: bool, rng: &mut Rng) -> (SurfaceMesh, SurfaceMesh) {
        let (cells, n) = self.slave;
        let slave = Grid { cells, h: 1.0 / n as f64, range: [0, n, 0, n] }.mesh(&|p| p, self.surface);
        let (cells, n) = self.master;
        let h = 1.0 / n as f64;
        // Enough cells to cover the slave after the shift and the twist.
        let margin = ((0.75 * self.twist.abs()) / h).ceil() as i64 + 2;
        let range = [-margin, n + margin, -margin, n + margin];
        let (s, c) = self.twist.sin_cos();
        let shift = self.shift;
        let place = move |[u, v]: [f64; 2]| {
            if shift == [0.0, 0.0] && s == 0.0 {
                return [u, v];
            }
            let (x, y) = (u + shift[0] * h - 0.5, v + shift[1] * h - 0.5);
            [0.5 + c * x - s * y, 0.5 + s * x + c * y]
        };
        let master = Grid { cells, h, range }.mesh(&place, self.surface);
        let [master, slave] =
            [master, slave].map(|(mesh, params)| self.place(mesh, &params, eps, normal, rng));
        (master, slave)
    }

    /// The noise the coordinates carry: `eps` plus their representation,
    /// relative to the model size.
    fn noise(&self, eps: f64) -> f64 {
        eps + 2.0 * f64::EPSILON * (self.offset.abs() + 2.0 * self.scale) / self.scale
    }

    /// `mesh` moved by the similarity, each point perturbed.
    fn place(
        &self,
        mesh: SurfaceMesh,
        params: &[[f64; 2]],
        eps: f64,
        normal: bool,
        rng: &mut Rng,
    ) -> SurfaceMesh {
        let (points, faces) = mesh.into_parts();
        let rotate = rotation([1.0, 2.0, 3.0], self.rotation);
        let points = points
            .iter()
            .zip(params)
            .map(|(&x, &p)| {
                let [t1, t2, n] = self.surface.frame(p);
                let d = if normal {
                    let a = rng.symmetric();
                    [a * n[0], a * n[1], a * n[2]]
                } else {
                    let (a, b) = (rng.symmetric(), rng.symmetric());
                    [a * t1[0] + b * t2[0], a * t1[1] + b * t2[1], a * t1[2] + b * t2[2]]
                };
                let x = apply(&rotate, x);
                let d = apply(&rotate, d);
                std::array::from_fn(|k| self.offset + self.scale * x[k] + eps * self.scale * d[k])
            })
            .collect();
        SurfaceMesh::new(points, faces).expect("a valid mesh")
    }
}

/// The rotation by `angle` about `axis` (Rodrigues).
fn rotation(axis: Point3, angle: f64) -> [[f64; 3]; 3] {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let [x, y, z] = axis.map(|a| a / n);
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [c + x * x * t, x * y * t - z * s, x * z * t + y * s],
        [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
        [z * x * t - y * s, z * y * t + x * s, c + z * z * t],
    ]
}

fn apply(r: &[[f64; 3]; 3], x: Point3) -> Point3 {
    std::array::from_fn(|i| r[i][0] * x[0] + r[i][1] * x[1] + r[i][2] * x[2])
}

fn scenes() -> Vec<Scene> {
    use Cells::*;
    let s = SCENE;
    vec![
        Scene { name: "matching quads", ..s },
        Scene { name: "matching triangles", slave: (Tri3, 6), master: (Tri3, 6), ..s },
        Scene { name: "matching mixed", slave: (Mixed, 6), master: (Mixed, 6), ..s },
        Scene { name: "quads on triangles", slave: (Quad4, 6), master: (Tri3, 6), ..s },
        Scene { name: "shifted quads", shift: [0.37, 0.21], ..s },
        Scene { name: "half-cell shift", slave: (Mixed, 6), shift: [0.5, 0.0], ..s },
        Scene { name: "twisted", slave: (Tri3, 5), twist: 0.12, ..s },
        Scene { name: "4:3 quads", slave: (Quad4, 6), master: (Quad4, 8), ..s },
        Scene { name: "3:2 mixed", slave: (Mixed, 4), master: (Quad4, 6), ..s },
        Scene { name: "2:1 triangles", slave: (Tri3, 4), master: (Mixed, 8), ..s },
        Scene { name: "rotated in space", slave: (Mixed, 6), master: (Quad4, 6), rotation: 0.7, ..s },
        Scene { name: "small, far away", scale: 1e-3, offset: 10.0, rotation: 2.1, ..s },
        Scene { name: "large", slave: (Quad4, 6), master: (Quad4, 8), scale: 1e4, offset: -3e4, ..s },
        Scene { name: "saddle, matching", surface: Surface::Saddle, ..s },
        Scene { name: "saddle, 4:3", surface: Surface::Saddle, master: (Quad4, 8), ..s },
        Scene { name: "cylinder, matching quads", surface: Surface::Cylinder, ..s },
        Scene {
            name: "cylinder, 4:3 triangles",
            surface: Surface::Cylinder,
            slave: (Tri3, 6),
            master: (Tri3, 8),
            ..s
        },
        Scene { name: "Quad9, matching", slave: (Quad9, 3), master: (Quad9, 3), ..s },
        Scene { name: "Quad8 on Quad9, 4:3", slave: (Quad8, 3), master: (Quad9, 4), ..s },
        Scene { name: "Tri6 on Quad4, matching grid", slave: (Tri6, 3), master: (Quad4, 6), ..s },
        Scene {
            name: "Quad9 cylinder, matching",
            surface: Surface::Cylinder,
            slave: (Quad9, 3),
            master: (Quad9, 3),
            ..s
        },
        Scene {
            name: "Quad9 cylinder, 4:3",
            surface: Surface::Cylinder,
            slave: (Quad9, 3),
            master: (Quad9, 4),
            ..s
        },
        Scene {
            name: "Tri6 cylinder, matching",
            surface: Surface::Cylinder,
            slave: (Tri6, 3),
            master: (Tri6, 3),
            ..s
        },
    ]
}

/// Per slave point p, ∫ λ_p over the slave surface (the nodal area) and the
/// area of the faces that use p (its support), by the degree-20 rule on each
/// reference triangle cut into 16: a reference independent of the
/// assembly's rules.
fn nodal_and_support_areas(slave: &SurfaceMesh) -> (Vec<f64>, Vec<f64>) {
    let rule = triangle_rule(20).expect("tabulated");
    let (mut nodal, mut support) = (vec![0.0; slave.n_points()], vec![0.0; slave.n_points()]);
    for (f, face) in slave.faces().iter().enumerate() {
        let kind = FaceKind::of(face);
        let curved = CurvedFace::of(slave, f);
        let cell: &[[[f64; 2]; 3]] = if kind.is_triangle() {
            &[[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]]
        } else {
            &[[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]]
        };
        let mut pieces = cell.to_vec();
        for _ in 0..2 {
            pieces = pieces
                .iter()
                .flat_map(|&[a, b, c]| {
                    let m = |p: [f64; 2], q: [f64; 2]| [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])];
                    let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
                    [[a, ab, ca], [ab, b, bc], [ca, bc, c], [bc, ca, ab]]
                })
                .collect();
        }
        let mut area = 0.0;
        for [a, b, c] in pieces {
            let size = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
            for (pt, &w) in rule.points.iter().zip(rule.weights) {
                let l0 = 1.0 - pt[0] - pt[1];
                let xi = [l0 * a[0] + pt[0] * b[0] + pt[1] * c[0], l0 * a[1] + pt[0] * b[1] + pt[1] * c[1]];
                let wj = w * size * curved.jacobian(xi);
                area += wj;
                let shape = shape_and_gradients(kind, xi).0;
                for (&p, l) in face.nodes().iter().zip(shape) {
                    nodal[p] += wj * l;
                }
            }
        }
        for &p in face.nodes() {
            support[p] += area;
        }
    }
    (nodal, support)
}

/// The checks of the module doc on one operator; `what` names the case.
fn check(
    mortar: &Mortar,
    (master, slave): (&SurfaceMesh, &SurfaceMesh),
    (nodal, support): (&[f64], &[f64]),
    noise_free: Option<&[f64]>,
    flat: bool,
    eps: f64,
    what: &str,
) -> Result<(), String> {
    let tol = tolerance(eps);
    let s = &mortar.summary;
    let covered = (s.covered_area - s.slave_area) / s.slave_area;
    if !within(covered.abs(), tol) {
        return Err(format!("{what}: covered area − slave area = {covered:e} of the slave area"));
    }
    if !within(covered, 1e-12) {
        return Err(format!("{what}: covered area above the slave area by {covered:e}"));
    }
    if !mortar.uncovered_nodes().is_empty() {
        return Err(format!("{what}: uncovered slave nodes {:?}", mortar.uncovered_nodes()));
    }
    let on = |p: usize| mortar.on_surface[p];
    if mortar.multiplier == Multiplier::Standard {
        let d1 = mortar.d.row_sums();
        // Against the noise-free assembly where its rule is not exact (module doc).
        let nodal = noise_free.unwrap_or(nodal);
        for p in (0..d1.len()).filter(|&p| on(p)) {
            let e = (d1[p] - nodal[p]).abs() / support[p];
            if !within(e, tol) {
                return Err(format!(
                    "{what}: D row sum of node {p} is {} against the nodal area {}: {e:e}",
                    d1[p], nodal[p]
                ));
            }
        }
    }
    let t1 = mortar.transfer().expect("T").apply(&vec![1.0; master.n_points()], 1);
    for p in (0..t1.len()).filter(|&p| on(p)) {
        if !within((t1[p] - 1.0).abs(), 1e-12) {
            return Err(format!("{what}: T·1 = {} at node {p}", t1[p]));
        }
    }
    if flat {
        let n = mortar.nodal_d();
        let size = slave.points().iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        for k in 0..3 {
            let xs: Vec<f64> = slave.points().iter().map(|x| x[k]).collect();
            let xm: Vec<f64> = master.points().iter().map(|x| x[k]).collect();
            let (dx, bx) = (n.mul_vec(&xs, 1), mortar.b.mul_vec(&xm, 1));
            for p in (0..dx.len()).filter(|&p| on(p)) {
                let e = (dx[p] - bx[p]).abs() / (support[p] * size);
                if !within(e, tol) {
                    return Err(format!(
                        "{what}: (D x − B x)_{p} for coordinate {k}: {e:e} of support × size"
                    ));
                }
            }
        }
    }
    Ok(())
}

#[test]
fn operator_under_noise() {
    let mut rng = Rng(31);
    let (mut worst, mut failures) = (0.0f64, Vec::new());
    for scene in scenes() {
        let flat = matches!(scene.surface, Surface::Flat);
        // Curved second-order faces: the rule of D (degree 8 on pieces with
        // parallelogram chords) is not exact on them (2.3e-10 of a node's
        // support on the Quad9 faces bent by 19° here), so the noise-free
        // assembly is the baseline that noise must move by O(ε) only.
        let noise_free = (!flat && scene.slave.0.second_order()).then(|| {
            let (master, slave) = scene.meshes(0.0, false, &mut Rng(0));
            let mortar = assemble(&master, &slave, &MortarOptions::default()).expect("the scene overlaps");
            mortar.d.row_sums()
        });
        for eps in NOISE {
            for normal in [false, true] {
                let (master, slave) = scene.meshes(eps, normal, &mut rng);
                let (nodal, support) = nodal_and_support_areas(&slave);
                for multiplier in [Multiplier::Standard, Multiplier::Dual] {
                    let options = MortarOptions { multiplier, ..Default::default() };
                    let mortar = assemble(&master, &slave, &options).expect("the scene overlaps");
                    let direction = if normal { "along the normal" } else { "in the plane" };
                    let what = format!("{}, {multiplier:?}, noise {eps:e} {direction}", scene.name);
                    let noise_free = noise_free.as_deref().filter(|_| multiplier == Multiplier::Standard);
                    if let Err(e) = check(
                        &mortar,
                        (&master, &slave),
                        (&nodal, &support),
                        noise_free,
                        flat,
                        scene.noise(eps),
                        &what,
                    ) {
                        failures.push(e);
                    }
                    let s = &mortar.summary;
                    let error = (s.covered_area - s.slave_area).abs() / s.slave_area;
                    worst = worst.max(error / tolerance(scene.noise(eps)));
                }
            }
        }
    }
    eprintln!("worst covered-area error: {worst:.3} of the tolerance");
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}

type Q = BigRational;

fn rational(p: Point2) -> [Q; 2] {
    p.map(|x| Q::from_float(x).expect("finite"))
}

/// The intersection of two convex counter-clockwise polygons by
/// Sutherland–Hodgman in exact arithmetic.
fn exact_clip(subject: &[Point2], clip: &[Point2]) -> Vec<[Q; 2]> {
    let clip: Vec<[Q; 2]> = clip.iter().map(|&p| rational(p)).collect();
    let mut out: Vec<[Q; 2]> = subject.iter().map(|&p| rational(p)).collect();
    for i in 0..clip.len() {
        let (a, b) = (&clip[i], &clip[(i + 1) % clip.len()]);
        let side = |q: &[Q; 2]| (&b[0] - &a[0]) * (&q[1] - &a[1]) - (&b[1] - &a[1]) * (&q[0] - &a[0]);
        let input = std::mem::take(&mut out);
        for j in 0..input.len() {
            let (p, q) = (&input[(j + input.len() - 1) % input.len()], &input[j]);
            let (sp, sq) = (side(p), side(q));
            if (sp.is_positive() && sq.is_negative()) || (sp.is_negative() && sq.is_positive()) {
                let t = &sp / (&sp - &sq);
                out.push([&p[0] + &t * (&q[0] - &p[0]), &p[1] + &t * (&q[1] - &p[1])]);
            }
            if !sq.is_negative() {
                out.push(q.clone());
            }
        }
        if out.len() < 3 {
            return Vec::new();
        }
    }
    out
}

fn exact_area(p: &[[Q; 2]]) -> f64 {
    let mut a = Q::zero();
    for i in 0..p.len() {
        let (u, w) = (&p[i], &p[(i + 1) % p.len()]);
        a += &u[0] * &w[1] - &u[1] * &w[0];
    }
    (a / Q::from_integer(2.into())).to_f64().expect("finite")
}

/// A random convex polygon (3 or 4 corners) of size about `size` at `at`.
fn random_convex(rng: &mut Rng, at: Point2, size: f64) -> Polygon {
    loop {
        let n = 3 + (rng.next() % 2) as usize;
        let corners: Vec<Point2> =
            (0..n).map(|_| [at[0] + size * rng.symmetric(), at[1] + size * rng.symmetric()]).collect();
        let p = face_polygon(&corners);
        if p.len() == n && polygon_area(&p) > 0.05 * size * size {
            return p;
        }
    }
}

/// Round-off of a clipped area: a few ulps of the coordinates times the
/// perimeter.
fn round_off(a: &[Point2], b: &[Point2]) -> f64 {
    let m = a.iter().chain(b).flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let perimeter = |p: &[Point2]| {
        (0..p.len())
            .map(|i| (p[(i + 1) % p.len()][0] - p[i][0]).hypot(p[(i + 1) % p.len()][1] - p[i][1]))
            .sum::<f64>()
    };
    64.0 * f64::EPSILON * m * (perimeter(a) + perimeter(b))
}

/// A second polygon near-degenerate with `a`: sharing an edge, a vertex on
/// an edge, collinear edges, nearly identical or nearly nested, each with
/// its corners moved by up to `eps` (relative to `a`'s size).
fn near_degenerate(rng: &mut Rng, a: &Polygon, eps: f64) -> Polygon {
    let n = a.len();
    let k = (rng.next() % n as u64) as usize;
    let (p, q) = (a[k], a[(k + 1) % n]);
    let size = polygon_area(a).sqrt();
    let e = [q[0] - p[0], q[1] - p[1]];
    let outward = [e[1], -e[0]];
    let at = |t: f64, s: f64| [p[0] + t * e[0] + s * outward[0], p[1] + t * e[1] + s * outward[1]];
    let corners: Vec<Point2> = match rng.next() % 5 {
        // The neighbour across edge k.
        0 => vec![p, at(0.5, 0.8), q],
        // A vertex on edge k, the triangle outside or across.
        1 => {
            let t = rng.unit();
            vec![at(t, 0.0), at(t + 0.3, 0.6), at(t - 0.4, 0.5 * rng.symmetric())]
        }
        // An edge along edge k, shifted along it.
        2 => {
            let t = 0.6 * rng.symmetric();
            vec![at(t, 0.0), at(t + 1.0, 0.0), at(t + 1.0, -0.7), at(t, -0.7)]
        }
        // Nearly the same polygon.
        3 => a.to_vec(),
        // Nearly nested: scaled about a corner.
        _ => a.iter().map(|c| [p[0] + 0.999 * (c[0] - p[0]), p[1] + 0.999 * (c[1] - p[1])]).collect(),
    };
    let moved: Vec<Point2> = corners
        .iter()
        .map(|c| [c[0] + eps * size * rng.symmetric(), c[1] + eps * size * rng.symmetric()])
        .collect();
    face_polygon(&moved)
}

#[test]
fn clipping_against_exact_rationals() {
    let mut rng = Rng(7);
    for case in 0..4000 {
        let at = [1e3 * rng.symmetric() * (case % 3) as f64, rng.symmetric()];
        let size = 0.5 + rng.unit();
        let a = random_convex(&mut rng, at, size);
        let eps = NOISE[case % NOISE.len()];
        let b = near_degenerate(&mut rng, &a, eps);
        if b.is_empty() {
            continue;
        }
        for (s, c) in [(&a, &b), (&b, &a)] {
            let got = polygon_area(&clip_polygon_polygon(s, c));
            let exact = exact_area(&exact_clip(s, c));
            let tol = round_off(s, c);
            assert!((got - exact).abs() <= tol, "case {case}: {got:e} against exact {exact:e}\n{s:?}\n{c:?}");
            assert!(
                got <= polygon_area(s).min(polygon_area(c)) + tol,
                "case {case}: {got:e} above the polygons"
            );
        }
    }
}

/// Master faces sharing their corners (a noisy grid of quads and triangles)
/// clipped against one slave polygon cover it, piece by piece, to round-off.
#[test]
fn clipped_pieces_tile_the_slave_polygon() {
    let mut rng = Rng(11);
    for case in 0..300 {
        let eps = NOISE[case % NOISE.len()];
        let n = 4 + case % 5;
        let h = 1.0 / n as f64;
        // Grid points, each moved once (shared by the faces that use it);
        // every tenth lies exactly on a grid line of the slave's corners.
        let mut points = vec![[0.0; 2]; (n + 1) * (n + 1)];
        for j in 0..=n {
            for i in 0..=n {
                let jitter = if case % 2 == 0 { 0.0 } else { 0.3 * h };
                let inner = i > 0 && i < n && j > 0 && j < n;
                let d = if inner { [jitter * rng.symmetric(), jitter * rng.symmetric()] } else { [0.0, 0.0] };
                let noise = [eps * rng.symmetric(), eps * rng.symmetric()];
                points[j * (n + 1) + i] = [i as f64 * h + d[0] + noise[0], j as f64 * h + d[1] + noise[1]];
            }
        }
        // The slave: a polygon inside the grid, corners on grid points for
        // even cases (nearly matching), anywhere for odd ones.
        let slave = if case % 4 < 2 {
            let (i, j) = (1 + case % (n - 2), 1);
            face_polygon(&[
                points[j * (n + 1) + i],
                points[j * (n + 1) + i + 1],
                points[(j + 1) * (n + 1) + i + 1],
                points[(j + 1) * (n + 1) + i],
            ])
        } else {
            random_convex(&mut rng, [0.5, 0.5], 0.3)
        };
        if slave.is_empty() {
            continue;
        }
        let (mut sum, mut tol) = (0.0, 0.0);
        for j in 0..n {
            for i in 0..n {
                let c =
                    [j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i];
                let c = c.map(|k| points[k]);
                let faces: Vec<Polygon> = if (i + j) % 3 == 0 {
                    vec![face_polygon(&[c[0], c[1], c[2]]), face_polygon(&[c[0], c[2], c[3]])]
                } else {
                    vec![face_polygon(&c)]
                };
                for face in faces {
                    sum += polygon_area(&clip_polygon_polygon(&face, &slave));
                    tol += round_off(&face, &slave);
                }
            }
        }
        let area = polygon_area(&slave);
        assert!((sum - area).abs() <= tol, "case {case}: pieces {sum:e}, slave {area:e}: {:e}", sum - area);
    }
}
