//! B and D exact on flat, strongly distorted quads.
//!
//! The preimage of a master edge under a non-parallelogram quad's bilinear map
//! is curved, so a segment that is a straight triangle in the slave's
//! reference coordinates (D2) misses part of the overlap (up to 5.5e-3 of B on
//! `flatj`); the quadrature of such pairs lives in the projection plane.
//!
//! The reference here is independent of the operator's code: for a quad Q
//! against a triangle T of the plane z = 0, with χ the quad's bilinear map,
//!
//! ```text
//! ∫_{Q∩T} λ^Q_p μ^T_q dA = ∫_{χ⁻¹(Q∩T)} g dξ dη ,  g = λ_p(ξ) μ_q(χ(ξ)) det ∂χ/∂ξ ,
//! ```
//!
//! a polynomial g over a region bounded by the preimages of straight edges;
//! by Green's theorem it is ∮ G dη with G(ξ, η) = ∫₀^ξ g(s, η) ds (exact by
//! Gauss–Legendre), integrated along each edge t ↦ ξ(t) = χ⁻¹(a + t(b − a))
//! (closed-form roots of the bilinear system) by adaptive Gauss–Legendre. The
//! polygon Q∩T comes from the test's own Sutherland–Hodgman clipping. Both
//! roles are checked: quad slaves against triangle masters (ψ = λ^Q) and
//! triangle slaves against quad masters (ψ = μ^T, B_pq = ∫ μ_p λ_q).
//!
//! Measured (`cargo test -p seam --test main exact_segments:: -- --nocapture`),
//! max |B − B_ref| / max |B_ref| and the same for D (standard multipliers):
//!
//! | quads | distortion ε ≤ | B before (straight in ξ_s) | B now | D now |
//! |---|---|---|---|---|
//! | slave, moved by 0.2 cell (as `flatj`) | 0.38 | 1.3e-3 | 6.7e-16 | 1.0e-14 |
//! | slave, moved by 0.3 cell | 0.65 | 2.9e-3 | 1.2e-15 | 6.5e-15 |
//! | master, moved by 0.3 cell | 0.65 | 7.1e-5 | 1.4e-15 | 4.1e-16 |
//! | `flatj` of the peer comparison, F = 10 000 (ignored test below) | 0.62 | 5.1e-3 | 8.8e-15 | 1.0e-13 |
//!
//! Two faces that are both distorted quads have no reference cell in which
//! the integrand is a polynomial; they are not checked here.
use seam::generate::{flat, patch, Pattern};
use seam::{assemble, CsrMatrix, Face, FaceElement, MortarOptions, SurfaceMesh};

type P2 = [f64; 2];

fn cross(a: P2, b: P2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn sub(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
}

/// The bilinear map of a quad q(ξ, η) = a + bξ + cη + dξη on [0, 1]².
struct Bilinear {
    a: P2,
    b: P2,
    c: P2,
    d: P2,
}

impl Bilinear {
    fn new(q: [P2; 4]) -> Self {
        let d = [q[0][0] - q[1][0] + q[2][0] - q[3][0], q[0][1] - q[1][1] + q[2][1] - q[3][1]];
        Bilinear { a: q[0], b: sub(q[1], q[0]), c: sub(q[3], q[0]), d }
    }

    fn map(&self, x: P2) -> P2 {
        let s = x[0] * x[1];
        std::array::from_fn(|k| self.a[k] + self.b[k] * x[0] + self.c[k] * x[1] + self.d[k] * s)
    }

    fn jacobian(&self, x: P2) -> [P2; 2] {
        let ja = [self.b[0] + self.d[0] * x[1], self.b[1] + self.d[1] * x[1]];
        let jb = [self.c[0] + self.d[0] * x[0], self.c[1] + self.d[1] * x[0]];
        [ja, jb]
    }

    /// The root in [0, 1]² of q(ξ) = p: with e = p − a, crossing
    /// e = bξ + cη + dξη with (c + dξ) gives (b×d) ξ² + (b×c − e×d) ξ − e×c = 0.
    fn inverse(&self, p: P2) -> P2 {
        let e = sub(p, self.a);
        let (qa, qb, qc) =
            (cross(self.b, self.d), cross(self.b, self.c) - cross(e, self.d), -cross(e, self.c));
        let roots: Vec<f64> = if qa.abs() < 1e-14 * qb.abs() {
            vec![-qc / qb]
        } else {
            let disc = (qb * qb - 4.0 * qa * qc).max(0.0).sqrt();
            // The stable pair of roots.
            let t = -0.5 * (qb + qb.signum() * disc);
            vec![t / qa, qc / t]
        };
        let outside = |v: f64| (v.clamp(0.0, 1.0) - v).abs();
        let xi = roots.into_iter().min_by(|&x, &y| outside(x).total_cmp(&outside(y))).unwrap();
        let den = [self.c[0] + self.d[0] * xi, self.c[1] + self.d[1] * xi];
        let k = if den[0].abs() > den[1].abs() { 0 } else { 1 };
        [xi, (e[k] - self.b[k] * xi) / den[k]]
    }
}

fn bilinear_shape(x: P2) -> [f64; 4] {
    [(1.0 - x[0]) * (1.0 - x[1]), x[0] * (1.0 - x[1]), x[0] * x[1], (1.0 - x[0]) * x[1]]
}

/// Barycentric coordinates of p in triangle t.
fn barycentric(t: [P2; 3], p: P2) -> [f64; 3] {
    let a = cross(sub(t[1], t[0]), sub(t[2], t[0]));
    let l1 = cross(sub(p, t[0]), sub(t[2], t[0])) / a;
    let l2 = cross(sub(t[1], t[0]), sub(p, t[0])) / a;
    [1.0 - l1 - l2, l1, l2]
}

/// Sutherland–Hodgman: convex polygon `poly` clipped by convex CCW `clip`.
fn clip(poly: &[P2], clip: &[P2]) -> Vec<P2> {
    let mut out = poly.to_vec();
    for i in 0..clip.len() {
        let (a, b) = (clip[i], clip[(i + 1) % clip.len()]);
        let side = |p: P2| cross(sub(b, a), sub(p, a));
        let input = std::mem::take(&mut out);
        for j in 0..input.len() {
            let (p, q) = (input[j], input[(j + 1) % input.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// Gauss–Legendre nodes and weights on [0, 1] (10 points).
fn gauss_legendre() -> [(f64, f64); 10] {
    const X: [f64; 5] =
        [0.1488743389816312, 0.4333953941292472, 0.6794095682990244, 0.8650633666889845, 0.9739065285171717];
    const W: [f64; 5] =
        [0.2955242247147529, 0.2692667193099963, 0.219086362515982, 0.1494513491505806, 0.0666713443086881];
    std::array::from_fn(|i| {
        let (x, w) = if i < 5 { (-X[i], W[i]) } else { (X[i - 5], W[i - 5]) };
        (0.5 * (1.0 + x), 0.5 * w)
    })
}

/// ∫_a^b f by Gauss–Legendre, bisected until the halves agree with the whole
/// to `tol` (the halves, of degree 19 on half the interval, are then far more
/// accurate than that).
fn adaptive(f: &dyn Fn(f64) -> [f64; 12], a: f64, b: f64, tol: f64, depth: u32) -> [f64; 12] {
    let gl = gauss_legendre();
    let on = |lo: f64, hi: f64| {
        let mut s = [0.0; 12];
        for &(x, w) in &gl {
            let v = f(lo + (hi - lo) * x);
            for k in 0..12 {
                s[k] += w * (hi - lo) * v[k];
            }
        }
        s
    };
    let m = 0.5 * (a + b);
    let (whole, left, right) = (on(a, b), on(a, m), on(m, b));
    let halves: [f64; 12] = std::array::from_fn(|k| left[k] + right[k]);
    if depth == 0 || (0..12).all(|k| (whole[k] - halves[k]).abs() <= tol) {
        return halves;
    }
    let (l, r) = (adaptive(f, a, m, tol, depth - 1), adaptive(f, m, b, tol, depth - 1));
    std::array::from_fn(|k| l[k] + r[k])
}

/// [∫_{Q∩T} λ^Q_p μ^T_q dA]_{p,q} (4 × 3, row-major) by Green's theorem.
fn overlap_integrals(quad: [P2; 4], tri: [P2; 3]) -> [f64; 12] {
    let polygon = clip(&quad, &tri);
    if polygon.len() < 3 {
        return [0.0; 12];
    }
    let chi = Bilinear::new(quad);
    // Absolute: 1e-14 of twice the quad's area (the cross product of its diagonals).
    let tol = 1e-14 * (cross(sub(quad[2], quad[0]), sub(quad[3], quad[1]))).abs();
    let g = |x: P2| -> [f64; 12] {
        let (l, m) = (bilinear_shape(x), barycentric(tri, chi.map(x)));
        let [ja, jb] = chi.jacobian(x);
        let det = cross(ja, jb);
        std::array::from_fn(|k| l[k / 3] * m[k % 3] * det)
    };
    // G(ξ, η) = ∫₀^ξ g(s, η) ds: g is cubic in ξ, 10 points are exact.
    let big_g = |x: P2| -> [f64; 12] {
        let mut s = [0.0; 12];
        for (t, w) in gauss_legendre() {
            let v = g([t * x[0], x[1]]);
            for k in 0..12 {
                s[k] += w * x[0] * v[k];
            }
        }
        s
    };
    let mut total = [0.0; 12];
    for i in 0..polygon.len() {
        let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
        let dp = sub(b, a);
        let integrand = |t: f64| -> [f64; 12] {
            let x = chi.inverse([a[0] + t * dp[0], a[1] + t * dp[1]]);
            let [ja, jb] = chi.jacobian(x);
            // dη/dt from J (dξ/dt, dη/dt) = dp.
            let eta_t = cross(ja, dp) / cross(ja, jb);
            let v = big_g(x);
            std::array::from_fn(|k| v[k] * eta_t)
        };
        let e = adaptive(&integrand, 0.0, 1.0, tol, 16);
        for k in 0..12 {
            total[k] += e[k];
        }
    }
    total
}

/// The bounding box of `points`.
fn bounds(points: &[P2]) -> (P2, P2) {
    points.iter().fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(lo, hi), p| {
        ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
    })
}

fn corners<const N: usize>(mesh: &SurfaceMesh, nodes: &[usize]) -> [P2; N] {
    std::array::from_fn(|i| {
        let x = mesh.points()[nodes[i]];
        [x[0], x[1]]
    })
}

/// B and D of quads against triangles (or the reverse when `quads_slave` is
/// false), from [`overlap_integrals`].
fn reference(quads: &SurfaceMesh, tris: &SurfaceMesh, quads_slave: bool) -> (Sparse, Sparse) {
    let (mut b, mut d) = (Sparse::new(), Sparse::new());
    for fq in quads.faces() {
        let Face::Quad4(qn) = *fq else { panic!("quads only") };
        let quad = corners::<4>(quads, &qn);
        let (lo, hi) = bounds(&quad);
        for ft in tris.faces() {
            let Face::Tri3(tn) = *ft else { panic!("triangles only") };
            let tri = corners::<3>(tris, &tn);
            let (tlo, thi) = bounds(&tri);
            if (0..2).any(|k| thi[k] < lo[k] || tlo[k] > hi[k]) {
                continue;
            }
            let v = overlap_integrals(quad, tri);
            for p in 0..4 {
                for q in 0..3 {
                    match quads_slave {
                        true => *b.entry((qn[p], tn[q])).or_default() += v[3 * p + q],
                        false => *b.entry((tn[q], qn[p])).or_default() += v[3 * p + q],
                    }
                }
            }
        }
    }
    // D over the whole (fully covered) slave faces: ∫ λ_p λ_q det dξ on the
    // square by 10 × 10 Gauss–Legendre points (exact), the classical triangle
    // mass matrix A/12 (1 + δ_pq).
    if quads_slave {
        for fq in quads.faces() {
            let Face::Quad4(qn) = *fq else { unreachable!() };
            let chi = Bilinear::new(corners::<4>(quads, &qn));
            for (x, wx) in gauss_legendre() {
                for (y, wy) in gauss_legendre() {
                    let [ja, jb] = chi.jacobian([x, y]);
                    let (l, w) = (bilinear_shape([x, y]), wx * wy * cross(ja, jb));
                    for p in 0..4 {
                        for q in 0..4 {
                            *d.entry((qn[p], qn[q])).or_default() += w * l[p] * l[q];
                        }
                    }
                }
            }
        }
    } else {
        for ft in tris.faces() {
            let Face::Tri3(tn) = *ft else { unreachable!() };
            let t = corners::<3>(tris, &tn);
            let area = 0.5 * cross(sub(t[1], t[0]), sub(t[2], t[0])).abs();
            for p in 0..3 {
                for q in 0..3 {
                    *d.entry((tn[p], tn[q])).or_default() += area / 12.0 * if p == q { 2.0 } else { 1.0 };
                }
            }
        }
    }
    (b, d)
}

/// A reference matrix: (row, column) → value.
type Sparse = std::collections::HashMap<(usize, usize), f64>;

/// max |X − X_ref| / max |X_ref| over the entries of both.
fn max_difference(x: &CsrMatrix, reference: &Sparse) -> f64 {
    let scale = reference.values().fold(0.0f64, |s, v| s.max(v.abs()));
    let mut worst = reference.iter().fold(0.0f64, |w, (&(p, q), v)| w.max((x.get(p, q) - v).abs()));
    for p in 0..x.nrows {
        let (cols, vals) = x.row(p);
        for (&q, &v) in cols.iter().zip(vals) {
            worst = worst.max((v - reference.get(&(p, q)).copied().unwrap_or(0.0)).abs());
        }
    }
    worst / scale
}

/// B and D of the operator against the reference, quads moved by up to
/// `amplitude` cell sizes; returns the two relative differences.
fn compare(amplitude: f64, quads_slave: bool) -> (f64, f64) {
    let quads = patch(7, 6, Pattern::JitteredQuads { amplitude, seed: 5 }, flat(1.0, 1.0));
    let tris = patch(5, 6, Pattern::JitteredTriangles { amplitude: 0.25, seed: 3 }, flat(1.0, 1.0));
    let (master, slave) = if quads_slave { (&tris, &quads) } else { (&quads, &tris) };
    let m = assemble(master, slave, &MortarOptions::default()).unwrap();
    let (b_ref, d_ref) = reference(&quads, &tris, quads_slave);
    let (eb, ed) = (max_difference(&m.b, &b_ref), max_difference(&m.d, &d_ref));
    let largest = (0..quads.n_faces())
        .map(|f| {
            let e = FaceElement::of(&quads, f);
            e.project(|x| [x[0], x[1]]).distortion()
        })
        .fold(0.0f64, f64::max);
    let roles = if quads_slave { "quad slaves, triangle masters" } else { "triangle slaves, quad masters" };
    println!("{roles}, quads moved by {amplitude}: distortion <= {largest:.2}, B {eb:.1e}, D {ed:.1e}");
    (eb, ed)
}

/// B and D exact to 1e-10 (relative to their largest entry) on flat distorted
/// quads, in both roles; measured 1.0e-14 and below.
#[test]
fn flat_distorted_quads_integrate_exactly() {
    for (amplitude, quads_slave) in [(0.2, true), (0.3, true), (0.3, false)] {
        let (eb, ed) = compare(amplitude, quads_slave);
        assert!(
            eb < 1e-10 && ed < 1e-10,
            "amplitude {amplitude}, quad slaves {quads_slave}: B {eb:e}, D {ed:e}"
        );
    }
}

/// The reference itself: on parallelograms (where the straight segments of the
/// paper are exact too) and for the total ∫ = area.
#[test]
fn green_reference_is_exact_on_parallelograms() {
    let quads = patch(4, 3, Pattern::Quads, flat(1.0, 1.0));
    let tris = patch(3, 5, Pattern::JitteredTriangles { amplitude: 0.25, seed: 3 }, flat(1.0, 1.0));
    let m = assemble(&tris, &quads, &MortarOptions::default()).unwrap();
    let (b_ref, d_ref) = reference(&quads, &tris, true);
    let total: f64 = b_ref.values().sum();
    assert!((total - 1.0).abs() < 1e-14, "Σ B_ref = {total}");
    assert!(max_difference(&m.b, &b_ref) < 1e-13 && max_difference(&m.d, &d_ref) < 1e-13);
}

/// Reads the peer harness's `.mesh` format ('nodes N', N lines 'x y z',
/// 'faces M', M lines 'k i1 .. ik', 0-based).
fn read_peer_mesh(path: &std::path::Path) -> SurfaceMesh {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut t = text.split_whitespace();
    let mut next = || t.next().expect("truncated mesh");
    assert_eq!(next(), "nodes");
    let n: usize = next().parse().unwrap();
    let points = (0..n).map(|_| std::array::from_fn(|_| next().parse::<f64>().unwrap())).collect();
    assert_eq!(next(), "faces");
    let m: usize = next().parse().unwrap();
    let faces = (0..m)
        .map(|_| {
            let k: usize = next().parse().unwrap();
            let v: Vec<usize> = (0..k).map(|_| next().parse().unwrap()).collect();
            Face::from_nodes(&v)
        })
        .collect();
    SurfaceMesh::new(points, faces).unwrap()
}

/// The peer comparison's `flatj` case (BENCHMARKS.md): F = 10 000 jittered
/// quads (nodes moved by up to 0.2 cell) against jittered triangles, from the
/// peer harness's `gen_meshes.py` in the directory `$SEAM_PEER_MESHES`:
///
/// ```text
/// python3 ../shared/peers/dune-grid-glue/gen_meshes.py /tmp/meshes --sizes 10000
/// SEAM_PEER_MESHES=/tmp/meshes cargo test --release -p seam --test main exact_segments:: -- --ignored --nocapture
/// ```
///
/// Measured: B 5.1e-3 before (straight segments in ξ_s), 8.8e-15 now; D
/// 2.0e-15 before, 1.0e-13 now.
#[test]
#[ignore = "needs the peer harness's meshes in $SEAM_PEER_MESHES"]
fn flatj_of_the_peer_comparison() {
    let dir = std::path::PathBuf::from(std::env::var("SEAM_PEER_MESHES").expect("SEAM_PEER_MESHES"));
    let quads = read_peer_mesh(&dir.join("flat_quadj_10000.mesh"));
    let tris = read_peer_mesh(&dir.join("flat_tri_10000.mesh"));
    let m = assemble(&tris, &quads, &MortarOptions::default()).unwrap();
    let (b_ref, d_ref) = reference(&quads, &tris, true);
    let (eb, ed) = (max_difference(&m.b, &b_ref), max_difference(&m.d, &d_ref));
    println!("flatj F = 10000: B {eb:.1e}, D {ed:.1e}");
    assert!(eb < 1e-10 && ed < 1e-10, "B {eb:e}, D {ed:e}");
}
