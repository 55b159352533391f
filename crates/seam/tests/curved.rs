//! The operator on second-order (curved) faces: I1–I3 and I5 as for first
//! order, I4 on flat interfaces (where second-order spaces reproduce every
//! quadratic field), and I9: on curved interfaces with gaps of O(h³) the
//! transfer error ‖T f − I f‖ in the slave mass norm falls like h³.

use seam::{assemble, MaxGap, Mortar, MortarOptions, Multiplier, Point3, SurfaceMesh};

use seam::FaceKind;

const KINDS: [FaceKind; 3] = [FaceKind::Tri6, FaceKind::Quad8, FaceKind::Quad9];

/// A structured second-order mesh of `n`×`n` cells of the parameter square
/// [a, b]² on `map`.
fn patch(kind: FaceKind, n: usize, (a, b): (f64, f64), map: impl Fn(f64, f64) -> Point3) -> SurfaceMesh {
    seam::generate::quadratic_patch(n, n, kind, None, |u, v| map(a + (b - a) * u, a + (b - a) * v))
}

fn cylinder(r: f64) -> impl Fn(f64, f64) -> Point3 {
    move |u, v| {
        let t = 0.3 + u;
        [r * t.cos(), r * t.sin(), v]
    }
}

fn sphere(r: f64) -> impl Fn(f64, f64) -> Point3 {
    move |u, v| {
        let (t, p) = (0.2 + u, v - 0.5);
        [r * p.cos() * t.cos(), r * p.cos() * t.sin(), r * p.sin()]
    }
}

fn options(multiplier: Multiplier) -> MortarOptions {
    MortarOptions { multiplier, max_gap: MaxGap::Relative(0.5), ..Default::default() }
}

fn field(x: Point3) -> f64 {
    (1.3 * x[0]).sin() + (0.7 * x[1]).cos() * x[2] + 0.5 * x[2] * x[2]
}

/// ‖T f − I f‖ in the slave mass norm (the standard D of a full slave).
fn transfer_error(master: &SurfaceMesh, slave: &SurfaceMesh, multiplier: Multiplier) -> f64 {
    let mortar = assemble(master, slave, &options(multiplier)).unwrap();
    assert_eq!(mortar.summary.uncovered_slave_nodes, 0);
    let mass = assemble(master, slave, &options(Multiplier::Standard)).unwrap().d;
    let fm: Vec<f64> = master.points().iter().map(|&x| field(x)).collect();
    let ts = mortar.transfer().unwrap().apply(&fm, 1);
    let used = slave.used_points();
    let e: Vec<f64> = slave
        .points()
        .iter()
        .zip(&ts)
        .zip(&used)
        .map(|((&x, &t), &u)| if u { t - field(x) } else { 0.0 })
        .collect();
    let me = mass.mul_vec(&e, 1);
    e.iter().zip(&me).map(|(a, b)| a * b).sum::<f64>().sqrt()
}

fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let (x, y): (Vec<f64>, Vec<f64>) = h.iter().zip(e).map(|(h, e)| (h.ln(), e.ln())).unzip();
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

/// I1 row by row and I2, relative to the row scale.
fn check_rows(mortar: &Mortar, what: &str) {
    let (d1, b1) = (mortar.d.row_sums(), mortar.b.row_sums());
    let scale = d1.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (p, (a, b)) in d1.iter().zip(&b1).enumerate() {
        assert!((a - b).abs() <= 1e-13 * scale, "{what}: I1 row {p}: D1 = {a}, B1 = {b}");
    }
    let total: f64 = d1.iter().sum();
    let covered = mortar.summary.covered_area;
    assert!((total - covered).abs() <= 1e-12 * covered, "{what}: I2 1ᵀD1 = {total}, covered {covered}");
}

#[test]
fn rows_agree_and_the_covered_area_is_the_true_curved_area() {
    // Slave: a cylinder patch of radius 2 over [0,1]² (area 2 exactly);
    // master: a coarser, larger patch of radius 2.0005 (fully covering).
    for ks in KINDS {
        for km in [FaceKind::Tri6, FaceKind::Quad9] {
            let slave = patch(ks, 4, (0.0, 1.0), cylinder(2.0));
            let master = patch(km, 3, (-0.1, 1.1), cylinder(2.0005));
            for multiplier in [Multiplier::Standard, Multiplier::Dual] {
                let what = format!("{ks:?} slave, {km:?} master, {multiplier:?}");
                let mortar = assemble(&master, &slave, &options(multiplier)).unwrap();
                check_rows(&mortar, &what);
                assert_eq!(mortar.summary.inverse_failures, 0, "{what}");
                assert_eq!(mortar.summary.uncovered_slave_nodes, 0, "{what}");
                // The covered area (the plane quadrature over the segments)
                // is the area of the isoparametric slave surface (degree-20
                // rule on each face), itself that of the cylinder patch, 2, up
                // to the geometric error of quadratic faces.
                let (area, full) = (mortar.summary.covered_area, mortar.summary.slave_area);
                assert!((area - full).abs() < 1e-10 * full, "{what}: covered {area}, slave area {full}");
                assert!((full - 2.0).abs() < 1e-3, "{what}: slave area {full}");
            }
        }
    }
}

#[test]
fn identical_curved_meshes_give_the_identity() {
    for kind in KINDS {
        let mesh = patch(kind, 3, (0.0, 1.0), sphere(1.5));
        for multiplier in [Multiplier::Standard, Multiplier::Dual] {
            let mortar = assemble(&mesh, &mesh, &options(multiplier)).unwrap();
            let used = mesh.used_points();
            let t = mortar.transfer().unwrap();
            for p in (0..mesh.n_points()).filter(|&p| used[p]) {
                let mut e = vec![0.0; mesh.n_points()];
                e[p] = 1.0;
                let column = t.apply(&e, 1);
                for (q, &v) in column.iter().enumerate() {
                    let expected = if q == p { 1.0 } else { 0.0 };
                    assert!((v - expected).abs() < 1e-11, "{kind:?} {multiplier:?}: T[{q}][{p}] = {v}");
                }
            }
        }
    }
}

/// Max |T f − f| over the slave nodes for the master's nodal values of `f`.
fn reproduction_error(
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    multiplier: Multiplier,
    f: &dyn Fn(Point3) -> f64,
) -> f64 {
    let mortar = assemble(master, slave, &options(multiplier)).unwrap();
    let fm: Vec<f64> = master.points().iter().map(|&x| f(x)).collect();
    let ts = mortar.transfer().unwrap().apply(&fm, 1);
    let used = slave.used_points();
    (0..slave.n_points())
        .filter(|&p| used[p])
        .map(|p| (ts[p] - f(slave.points()[p])).abs())
        .fold(0.0, f64::max)
}

#[test]
fn flat_interfaces_reproduce_quadratic_fields_on_affine_faces_and_linear_ones_on_distorted_faces() {
    // Affine faces (a sheared plane): every space contains the quadratics.
    let sheared = |u: f64, v: f64| -> Point3 { [u + 0.3 * v, 0.9 * v, 0.0] };
    let quadratic =
        |x: Point3| 1.0 + 2.0 * x[0] - x[1] + 0.7 * x[0] * x[0] - 0.4 * x[0] * x[1] + 0.3 * x[1] * x[1];
    // Distorted faces: mid-side nodes moved along the plane, so the faces'
    // spaces contain the linear fields only (isoparametric).
    let wavy = |u: f64, v: f64| -> Point3 { [u + 0.05 * (3.0 * v).sin(), v + 0.04 * (2.0 * u).sin(), 0.0] };
    let linear = |x: Point3| 1.0 + 2.0 * x[0] - 3.0 * x[1];
    for ks in KINDS {
        for km in KINDS {
            for multiplier in [Multiplier::Standard, Multiplier::Dual] {
                let what = format!("{ks:?} slave, {km:?} master, {multiplier:?}");
                let slave = patch(ks, 3, (0.1, 0.9), sheared);
                let master = patch(km, 4, (0.0, 1.0), |u, v| sheared(1.0 - v, u));
                let e = reproduction_error(&master, &slave, multiplier, &quadratic);
                assert!(e < 1e-11, "{what}: quadratic on affine faces: {e:e}");
                let slave = patch(ks, 3, (0.1, 0.9), wavy);
                let master = patch(km, 4, (0.0, 1.0), |u, v| wavy(1.0 - v, u));
                let e = reproduction_error(&master, &slave, multiplier, &linear);
                assert!(e < 1e-11, "{what}: linear on distorted faces: {e:e}");
            }
        }
    }
}

/// A family of surfaces by radius.
type Surface = dyn Fn(f64) -> Box<dyn Fn(f64, f64) -> Point3>;

/// I9 for one surface and one (slave, master) kind pair.
fn i9_rate(surface: &Surface, ks: FaceKind, km: FaceKind, multiplier: Multiplier) -> f64 {
    let levels = [3usize, 6, 12, 24];
    let mut h = Vec::new();
    let mut e = Vec::new();
    for &n in &levels {
        let hs = 1.0 / n as f64;
        let slave = patch(ks, n, (0.0, 1.0), surface(1.5));
        // Non-matching: a master of 4/3 the resolution over a larger square,
        // with a gap of h³.
        let master = patch(km, (4 * n).div_ceil(3) + 1, (-0.1, 1.1), surface(1.5 + hs.powi(3)));
        h.push(hs);
        e.push(transfer_error(&master, &slave, multiplier));
    }
    let rate = fitted_rate(&h, &e);
    eprintln!(
        "I9 {ks:?} slave, {km:?} master, {multiplier:?}: errors {:?}, rate {rate:.2}",
        e.iter().map(|v| format!("{v:.3e}")).collect::<Vec<_>>()
    );
    rate
}

#[test]
fn i9_transfer_error_falls_like_h_cubed_on_curved_interfaces() {
    let cyl = |r: f64| -> Box<dyn Fn(f64, f64) -> Point3> { Box::new(cylinder(r)) };
    let sph = |r: f64| -> Box<dyn Fn(f64, f64) -> Point3> { Box::new(sphere(r)) };
    let surfaces: [(&str, &Surface); 2] = [("cylinder", &cyl), ("sphere", &sph)];
    for (name, surface) in surfaces {
        for (ks, km) in [
            (FaceKind::Quad9, FaceKind::Tri6),
            (FaceKind::Quad8, FaceKind::Tri6),
            (FaceKind::Tri6, FaceKind::Tri6),
            (FaceKind::Tri6, FaceKind::Quad9),
            (FaceKind::Tri6, FaceKind::Quad8),
        ] {
            for multiplier in [Multiplier::Standard, Multiplier::Dual] {
                let rate = i9_rate(surface, ks, km, multiplier);
                assert!(rate >= 2.8, "{name}: {ks:?} slave, {km:?} master, {multiplier:?}: rate {rate:.2}");
            }
        }
    }
}

/// On flat jittered Quad9 and Quad8 faces (bilinear geometry, chords not
/// parallelograms) fully covered by a non-matching Tri6 master, D is the
/// exact mass matrix ∫ ψ_p ψ_q |J| (here a polynomial in ξ, integrated with
/// degree 20 on the reference cell): the curved path's rule follows the fold
/// ratio of the slave's chord (`CURVED_LADDER`). A fixed degree-8 rule leaves
/// D 2e-7 to 1e-5 off.
#[test]
fn d_is_exact_on_distorted_flat_second_order_quads() {
    let rule = seam::triangle_rule(20).unwrap();
    for ks in [FaceKind::Quad9, FaceKind::Quad8] {
        for amplitude in [0.05, 0.3] {
            let slave = seam::generate::quadratic_patch(6, 6, ks, Some((amplitude, 7)), |u, v| [u, v, 0.0]);
            let master =
                seam::generate::quadratic_patch(7, 7, FaceKind::Tri6, Some((amplitude, 3)), |u, v| {
                    [-0.05 + 1.1 * u, -0.05 + 1.1 * v, 0.0]
                });
            let mortar = assemble(&master, &slave, &options(Multiplier::Standard)).unwrap();
            let n = slave.n_points();
            let mut exact = vec![0.0; n * n];
            for f in 0..slave.faces().len() {
                let face = seam::curved::CurvedFace::of(&slave, f);
                let nodes = slave.faces()[f].nodes();
                for t in [[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]] {
                    for (pt, &w) in rule.points.iter().zip(rule.weights) {
                        let l0 = 1.0 - pt[0] - pt[1];
                        let xi = [0, 1].map(|k| l0 * t[0][k] + pt[0] * t[1][k] + pt[1] * t[2][k]);
                        let phi = seam::curved::shape_and_gradients(face.kind, xi).0;
                        let wj = 0.5 * w * face.jacobian(xi);
                        for (p, &a) in nodes.iter().enumerate() {
                            for (q, &b) in nodes.iter().enumerate() {
                                exact[a * n + b] += wj * phi[p] * phi[q];
                            }
                        }
                    }
                }
            }
            let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let error =
                (0..n * n).fold(0.0f64, |m, k| m.max((mortar.d.get(k / n, k % n) - exact[k]).abs())) / scale;
            eprintln!("{ks:?}, jitter {amplitude}: D against the exact mass matrix {error:.1e}");
            assert!(error < 1e-12, "{ks:?}, jitter {amplitude}: {error:e}");
        }
    }
}

/// Where the master ends inside slave faces, the covered area converges to
/// the area of the master's region of the sphere like h², with the constant
/// of 2 × 2 sub-faces (measured: 1.2e-3, 2.9e-4, 7.4e-5 relative for
/// n = 4, 8, 16; with whole faces as chords it would be 4.9e-3, 1.2e-3,
/// 2.9e-4).
#[test]
fn partly_covered_curved_faces_end_where_the_master_ends() {
    // θ = 0.2 + u, φ = v − 0.5 over u, v ∈ [0.23, 0.71]: R² Δθ (sin φ₂ − sin φ₁).
    let exact = 0.48 * ((0.21f64).sin() + (0.27f64).sin());
    for (ks, km) in [(FaceKind::Quad9, FaceKind::Tri6), (FaceKind::Tri6, FaceKind::Quad9)] {
        let mut h = Vec::new();
        let mut e = Vec::new();
        for n in [4usize, 8, 16] {
            let slave = patch(ks, n, (0.0, 1.0), sphere(1.0));
            let master = patch(km, (4 * n).div_ceil(3) + 1, (0.23, 0.71), sphere(1.0));
            let mortar = assemble(&master, &slave, &options(Multiplier::Standard)).unwrap();
            check_rows(&mortar, "partly covered");
            h.push(1.0 / n as f64);
            e.push((mortar.summary.covered_area / exact - 1.0).abs());
        }
        let rate = fitted_rate(&h, &e);
        let shown: Vec<String> = e.iter().map(|v| format!("{v:.2e}")).collect();
        eprintln!("{ks:?} slave, {km:?} master: covered area errors {shown:?}, rate {rate:.2}");
        assert!(rate >= 1.9, "{ks:?} slave: rate {rate:.2}");
        assert!(e[1] <= 4e-4, "{ks:?} slave: covered area error {:.2e} at n = 8", e[1]);
    }
}

#[test]
fn dual_d_is_diagonal_and_positive_and_lumped_is_refused_where_its_diagonal_is_not() {
    for ks in KINDS {
        let slave = patch(ks, 3, (0.0, 1.0), sphere(1.5));
        let master = patch(FaceKind::Tri6, 4, (-0.1, 1.1), sphere(1.5001));
        let dual = assemble(&master, &slave, &options(Multiplier::Dual)).unwrap();
        assert!(dual.d.is_diagonal(), "{ks:?}");
        // Tri6 and Quad8 need the basis transformation; Quad9 keeps the plain
        // dual basis (its ∫λ_p are positive).
        let transformed = matches!(ks, FaceKind::Tri6 | FaceKind::Quad8);
        assert_eq!(dual.basis.is_some(), transformed, "{ks:?}: transformed basis");
        let used = slave.used_points();
        for (p, &v) in dual.d.diagonal().iter().enumerate() {
            assert!(!used[p] || v > 0.0, "{ks:?}: dual D[{p}][{p}] = {v}");
        }
        // I5 (standard): D symmetric positive definite on the covered nodes,
        // here shown by its Cholesky factorisation inside the transfer.
        let standard = assemble(&master, &slave, &options(Multiplier::Standard)).unwrap();
        assert!(standard.transfer().is_ok(), "{ks:?}");
        for p in 0..slave.n_points() {
            for q in 0..slave.n_points() {
                assert_eq!(standard.d.get(p, q), standard.d.get(q, p), "{ks:?}: D symmetric");
            }
        }
        let lumped = assemble(&master, &slave, &options(Multiplier::Lumped));
        match ks {
            // ∫λ of a Tri6 corner is 0 up to curvature, of a Quad8 corner < 0.
            FaceKind::Tri6 | FaceKind::Quad8 => {
                let e = lumped.unwrap_err();
                assert!(matches!(e, seam::MortarError::LumpedSecondOrder { face: 0, .. }), "{ks:?}: {e}");
                assert!(e.to_string().contains("use dual multipliers"), "{e}");
            }
            _ => {
                let lumped = lumped.unwrap();
                assert!(lumped.d.diagonal().iter().zip(&used).all(|(&v, &u)| !u || v > 0.0));
                check_rows(&lumped, "Quad9 lumped");
            }
        }
    }
}

#[test]
fn nodal_d_of_the_transformed_dual_basis_constrains_nodal_values() {
    // D_nodal u_s = B u_m for the nodal values of a field both spaces hold
    // (a linear field on a flat interface), and D_nodal 1 = D 1 (I1).
    let flat = |u: f64, v: f64| -> Point3 { [u, v + 0.1 * u * u, 0.0] };
    let linear = |x: Point3| 0.5 + x[0] - 2.0 * x[1];
    for ks in [FaceKind::Tri6, FaceKind::Quad8] {
        let slave = patch(ks, 3, (0.1, 0.9), flat);
        let master = patch(FaceKind::Quad9, 4, (0.0, 1.0), flat);
        let mortar = assemble(&master, &slave, &options(Multiplier::Dual)).unwrap();
        let nodal = mortar.nodal_d();
        let us: Vec<f64> = slave.points().iter().map(|&x| linear(x)).collect();
        let um: Vec<f64> = master.points().iter().map(|&x| linear(x)).collect();
        let (du, bu) = (nodal.mul_vec(&us, 1), mortar.b.mul_vec(&um, 1));
        let scale = du.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for p in (0..slave.n_points()).filter(|&p| mortar.covered[p]) {
            assert!((du[p] - bu[p]).abs() < 1e-12 * scale, "{ks:?}: row {p}: {} vs {}", du[p], bu[p]);
        }
    }
}

/// The enriched slave space ([`SurfaceMesh::enriched`]): with dual
/// multipliers on Tri7 and Quad9 faces made from Tri6 and Quad8 ones, the
/// multiplier space holds the linear functions, so the conservative transfer
/// Tᵀ of a linear traction's consistent slave forces M_s ℓ is exactly that
/// traction's consistent master forces, ∫_Γs ℓ λ^m_q (Σ_p c_p ψ_p = ℓ with
/// c = D⁻¹ M_s ℓ). Popp's transformed basis on the plain Tri6 and Quad8 faces
/// misses it by 2.9 % and 8.4 % of the largest force (its mid-edge functions
/// weigh the two sides of their edge unequally).
#[test]
fn enriched_dual_multipliers_transfer_linear_tractions_exactly() {
    let flat = |u: f64, v: f64| -> Point3 { [u, v, 0.0] };
    let linear = |x: Point3| 0.5 + x[0] - 2.0 * x[1];
    for ks in [FaceKind::Tri6, FaceKind::Quad8] {
        let plain = patch(ks, 4, (0.1, 0.9), flat);
        let master = patch(FaceKind::Tri6, 5, (0.0, 1.0), |u, v| [u, v, 1e-3]);
        let (enriched, owners) = plain.enriched();
        assert_eq!(owners.len(), plain.n_faces());
        assert_eq!(enriched.n_points(), plain.n_points() + plain.n_faces());
        let mut misses = Vec::new();
        for slave in [&plain, &enriched] {
            let standard = assemble(&master, slave, &options(Multiplier::Standard)).unwrap();
            let dual = assemble(&master, slave, &options(Multiplier::Dual)).unwrap();
            assert_eq!(dual.basis.is_some(), slave == &plain, "{ks:?}: transformed only without enrichment");
            let l: Vec<f64> = slave.points().iter().map(|&x| linear(x)).collect();
            let forces = dual.transfer().unwrap().apply_transpose(&standard.d.mul_vec(&l, 1), 1);
            let exact = standard.b.transpose().mul_vec(&l, 1);
            let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            misses.push(forces.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / scale);
        }
        eprintln!(
            "{ks:?}: largest miss of Tᵀ M ℓ, transformed {:.2e}, enriched {:.2e}",
            misses[0], misses[1]
        );
        assert!(misses[1] < 1e-13, "{ks:?} enriched: {:e}", misses[1]);
        assert!(misses[0] > 1e-4, "{ks:?} transformed: {:e}", misses[0]);
    }
}

/// I6 and I7 on curved faces, over more slave faces than one chunk of the
/// assembly (256), so that threads share the work: Quad9 and Tri6 slaves
/// (the latter with the transformed dual basis) on a cylinder against a
/// jittered, non-matching Tri6 master with a gap.
#[test]
fn curved_operators_conserve_and_do_not_depend_on_the_thread_count() {
    for (ks, n) in [(FaceKind::Quad9, 24), (FaceKind::Tri6, 17)] {
        let slave = patch(ks, n, (0.0, 1.0), cylinder(2.0));
        let master = seam::generate::quadratic_patch(19, 19, FaceKind::Tri6, Some((0.2, 5)), |u, v| {
            cylinder(2.0 + 1e-4)(-0.1 + 1.2 * u, -0.1 + 1.2 * v)
        });
        assert!(slave.n_faces() > 512, "{}", slave.n_faces());
        for multiplier in [Multiplier::Standard, Multiplier::Dual] {
            let what = format!("{ks:?} slave, {multiplier:?}");
            let o = options(multiplier);
            let reference = assemble(&master, &slave, &o).unwrap();
            assert_eq!(reference.summary.uncovered_slave_nodes, 0, "{what}");
            // I6: 1ᵀ(Tᵀ f) = 1ᵀ f.
            let t = reference.transfer().unwrap();
            let f: Vec<f64> = (0..slave.n_points()).map(|p| 1.0 + ((p * 7919) % 13) as f64).collect();
            let f: Vec<f64> =
                f.iter().zip(&reference.covered).map(|(v, &c)| if c { *v } else { 0.0 }).collect();
            let (total, moved): (f64, f64) = (f.iter().sum(), t.apply_transpose(&f, 1).iter().sum());
            assert!((total - moved).abs() <= 1e-12 * total, "{what}: I6 {moved} vs {total}");
            // I7: B, D (and Q) bit for bit with 1, 2 and 3 threads.
            for threads in [1, 2, 3] {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                let m = pool.install(|| assemble(&master, &slave, &o).unwrap());
                assert!(m.b == reference.b && m.d == reference.d, "{what}: I7 with {threads} threads");
                assert_eq!(m.basis, reference.basis, "{what}: I7 with {threads} threads");
            }
        }
    }
}

/// One mesh of first- and second-order faces, on either side: a flat square
/// whose left half is Quad9 (slave) or Tri6 (master) and right half Quad4 or
/// Tri3. Every face reproduces linear fields, so T does too (I4), and I1, I2
/// hold; the second-order faces' mid-side nodes get rows and columns.
#[test]
fn first_and_second_order_faces_mix_in_one_mesh() {
    /// A (2n+1)² grid of [0, 1]² at height z, cells of the left half as the
    /// `second` kind, of the right half as first order.
    fn half_and_half(n: usize, triangles: bool, z: f64) -> SurfaceMesh {
        let m = 2 * n + 1;
        let points: Vec<Point3> = (0..m * m)
            .map(|k| {
                let (u, v) = ((k % m) as f64 / (m - 1) as f64, (k / m) as f64 / (m - 1) as f64);
                [u, v, z]
            })
            .collect();
        let id = |i: usize, j: usize| j * m + i;
        let mut faces = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (a, b) = (2 * i, 2 * j);
                let c = [id(a, b), id(a + 2, b), id(a + 2, b + 2), id(a, b + 2)];
                let e = [id(a + 1, b), id(a + 2, b + 1), id(a + 1, b + 2), id(a, b + 1)];
                let mid = id(a + 1, b + 1);
                match (2 * i < n, triangles) {
                    (true, false) => {
                        faces.push(seam::Face::Quad9([c[0], c[1], c[2], c[3], e[0], e[1], e[2], e[3], mid]))
                    }
                    (false, false) => faces.push(seam::Face::Quad4(c)),
                    (true, true) => {
                        faces.push(seam::Face::Tri6([c[0], c[1], c[2], e[0], e[1], mid]));
                        faces.push(seam::Face::Tri6([c[0], c[2], c[3], mid, e[2], e[3]]));
                    }
                    (false, true) => {
                        faces.push(seam::Face::Tri3([c[0], c[1], c[2]]));
                        faces.push(seam::Face::Tri3([c[0], c[2], c[3]]));
                    }
                }
            }
        }
        SurfaceMesh::new(points, faces).unwrap()
    }
    let slave = half_and_half(4, false, 0.0);
    let master = half_and_half(5, true, 1e-3);
    let linear = |x: Point3| 0.7 - 1.3 * x[0] + 2.1 * x[1];
    for multiplier in [Multiplier::Standard, Multiplier::Dual] {
        let what = format!("{multiplier:?}");
        let mortar = assemble(&master, &slave, &options(multiplier)).unwrap();
        check_rows(&mortar, &what);
        assert_eq!(mortar.summary.uncovered_slave_nodes, 0, "{what}");
        assert!((mortar.summary.covered_area - 1.0).abs() < 1e-12, "{what}: {}", mortar.summary.covered_area);
        let fm: Vec<f64> = master.points().iter().map(|&x| linear(x)).collect();
        let ts = mortar.transfer().unwrap().apply(&fm, 1);
        let used = slave.used_points();
        let mut mid_side = 0;
        for (p, &x) in slave.points().iter().enumerate().filter(|&(p, _)| used[p]) {
            assert!(
                (ts[p] - linear(x)).abs() < 1e-12,
                "{what}: node {p} at {x:?}: {} vs {}",
                ts[p],
                linear(x)
            );
            mid_side += (x[0] * 8.0).round() as usize % 2;
        }
        assert!(mid_side > 0, "mid-side nodes have rows");
    }
}
