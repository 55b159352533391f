//! Quadrature rules on the reference cells of the volume elements
//! ([`crate::catalogue`]): tetrahedron, hexahedron, prism and pyramid.
//!
//! [`volume_rule`] gives rules of any degree (loads, error norms):
//!
//! - tetrahedron: centroid (degree ≤ 1), 4-point rule (degree 2), otherwise the
//!   collapsed (Duffy) Gauss rule with n = ⌈(degree+3)/2⌉ points per direction;
//! - hexahedron: n × n × n Gauss, n = ⌈(degree+1)/2⌉;
//! - prism: [`triangle_rule`]`(degree)` × n Gauss, n = ⌈(degree+1)/2⌉;
//! - pyramid: n × n Gauss in (a, b) and ⌈(degree+3)/2⌉ in ζ, collapsed.
//!
//! The stiffness rules ([`CellType::stiffness`](crate::CellType::stiffness))
//! are exact for the stiffness of affine cells, and for ∫_e ∇N_i dV and the
//! volume of any (trilinear, prismatic, collapsed) cell, which is what the
//! patch test needs:
//!
//! | element | points | why it is enough |
//! |---|---:|---|
//! | Tet4 | 1 (centroid) | ∇N constant |
//! | Hex8 | 2×2×2 Gauss | cof(J)ᵀ∇_ξN and det J are of degree ≤ 3 in each variable |
//! | Prism6 | 3-point triangle (degree 2) × 2 Gauss | degree ≤ 2 in (ξ, η), ≤ 3 in ζ |
//! | Pyramid5 | 2×2×2 collapsed Gauss | in (a, b, ζ) the cell is a degenerate trilinear hex |
//! | Tet10 | 4-point, degree 2 | ∇N_i·∇N_j of degree 2 |
//! | Hex20, Hex27 | 3×3×3 Gauss | ≤ 4 in each variable |
//! | Prism15, Prism18 | degree-4 triangle rule × 3 Gauss | ≤ 4 in (ξ, η), ≤ 4 in ζ |
//! | Pyramid13, Pyramid14 | 3×3×3 collapsed Gauss | ≤ 4 in each of a, b, ζ with (1−ζ)² |
//!
//! The pyramid rule is the Gauss rule of the cube (a, b, ζ) ∈ \[−1,1\]²×\[0,1\]
//! mapped by ξ = a(1−ζ), η = b(1−ζ), the Duffy factor (1−ζ)² folded into the
//! weights. For an affine Pyramid5 the stiffness integrand ∇N_i·C∇N_j(1−ζ)² has
//! degree ≤ 2 in each of a, b, ζ, so 2 points per direction are exact; 3×3×3
//! would cost 27/8 as much for no gain on affine cells, and the rule is of full
//! rank (the element stiffness has exactly the 6 rigid-body zero modes).
//!
//! On isoparametric (curved) hexes and prisms cof(J)ᵀ∇_ξN_i is of degree ≤ 5
//! in each hex variable (prisms: ≤ 4 in (ξ, η), ≤ 5 in ζ), so the second-order
//! rules also give ∫_e ∇N_i dV exactly there: curved Hex20/27 and Prism15/18
//! meshes pass the patch test. Tet10 and the pyramids are exact on
//! straight-sided cells.

use std::sync::LazyLock;

use super::triangle_rule;
use crate::catalogue::{CellKind, Shape, StiffnessRule, Xi3};

/// A quadrature rule on a reference cell: ∫ f dξ ≈ Σ_q w_q f(ξ_q).
///
/// Weights sum to the volume of the reference cell ([`CellKind::reference_volume`]).
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeRule {
    /// Points ξ_q in reference coordinates, all inside the cell.
    pub points: Vec<Xi3>,
    /// Weights w_q, all positive.
    pub weights: Vec<f64>,
}

impl VolumeRule {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True for a rule without points (never returned by this module).
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// (ξ_q, w_q) pairs.
    pub fn iter(&self) -> impl Iterator<Item = (Xi3, f64)> + '_ {
        self.points.iter().copied().zip(self.weights.iter().copied())
    }
}

static STIFFNESS_RULES: LazyLock<[VolumeRule; CellKind::ALL.len()]> = LazyLock::new(|| {
    CellKind::ALL.map(|kind| match kind.info().stiffness {
        StiffnessRule::Degree(degree) => kind.rule(degree),
        StiffnessRule::Collapsed(n) => pyramid_rule(n, n),
    })
});

/// The rules of a cell kind (here, so that the catalogue needs no quadrature).
impl CellKind {
    /// The rule the stiffness is integrated with ([`crate::CellType::stiffness`]):
    /// 1, 8, 6 and 8 points for first-order kinds; 4 (Tet10), 27 (hexes),
    /// 18 (prisms) and 27 (pyramids) for second-order kinds.
    pub fn stiffness_rule(self) -> &'static VolumeRule {
        stiffness_rule(self)
    }

    /// A rule exact for polynomials of total degree ≤ `degree` on the reference
    /// cell ([`volume_rule`]); second-order kinds use the
    /// rule of their family.
    ///
    /// # Panics
    /// Prisms with `degree > seam::MAX_TRIANGLE_DEGREE`.
    pub fn rule(self, degree: usize) -> VolumeRule {
        volume_rule(self.reference_shape(), degree)
    }
}

/// The rule `kind`'s stiffness is integrated with ([`CellKind::stiffness_rule`]).
pub(crate) fn stiffness_rule(kind: CellKind) -> &'static VolumeRule {
    &STIFFNESS_RULES[kind as usize]
}

/// A rule exact for polynomials of total degree ≤ `degree` on the reference
/// cell of `shape` (module doc); for the pyramid: polynomials in (ξ, η, ζ), and
/// also every function of degree ≤ `degree` in each collapsed coordinate a, b,
/// ζ times (1−ζ)², e.g. products of its shape functions.
///
/// # Panics
/// A prism with `degree > seam::MAX_TRIANGLE_DEGREE`, or a shape that is not
/// a cell's.
pub fn volume_rule(shape: Shape, degree: usize) -> VolumeRule {
    match shape {
        Shape::Tetrahedron => match degree {
            0 | 1 => VolumeRule { points: vec![[0.25; 3]], weights: vec![1.0 / 6.0] },
            2 => {
                let a = (5.0 + 3.0 * 5f64.sqrt()) / 20.0;
                let b = (5.0 - 5f64.sqrt()) / 20.0;
                VolumeRule {
                    points: vec![[b, b, b], [a, b, b], [b, a, b], [b, b, a]],
                    weights: vec![1.0 / 24.0; 4],
                }
            }
            _ => tet_collapsed_rule((degree + 4) / 2),
        },
        Shape::Hexahedron => {
            let (x, w) = gauss_legendre(degree / 2 + 1);
            let mut rule = VolumeRule { points: Vec::new(), weights: Vec::new() };
            for k in 0..x.len() {
                for j in 0..x.len() {
                    for i in 0..x.len() {
                        rule.points.push([x[i], x[j], x[k]]);
                        rule.weights.push(w[i] * w[j] * w[k]);
                    }
                }
            }
            rule
        }
        Shape::Prism => {
            let tri = triangle_rule(degree).expect("triangle rule degree within the tabulated range");
            let (x, w) = gauss_legendre(degree / 2 + 1);
            let mut rule = VolumeRule { points: Vec::new(), weights: Vec::new() };
            for k in 0..x.len() {
                for (p, wt) in tri.points.iter().zip(tri.weights) {
                    rule.points.push([p[0], p[1], x[k]]);
                    rule.weights.push(0.5 * wt * w[k]);
                }
            }
            rule
        }
        Shape::Pyramid => pyramid_rule(degree / 2 + 1, (degree + 4) / 2),
        other => panic!("volume rules are for cells, not a {}", other.noun()),
    }
}

/// Gauss points on \[0,1\]: (points, weights summing to 1).
fn gauss_unit(n: usize) -> (Vec<f64>, Vec<f64>) {
    let (x, w) = gauss_legendre(n);
    (x.iter().map(|x| 0.5 * (1.0 + x)).collect(), w.iter().map(|w| 0.5 * w).collect())
}

/// The collapsed tet rule with n points per direction: (u, v, w) ∈ \[0,1\]³ ↦
/// ξ = u(1−v)(1−w), η = v(1−w), ζ = w, Jacobian (1−v)(1−w)²; exact for total
/// degree ≤ 2n − 3.
fn tet_collapsed_rule(n: usize) -> VolumeRule {
    let (x, w) = gauss_unit(n);
    let mut rule = VolumeRule { points: Vec::new(), weights: Vec::new() };
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let (u, v, t) = (x[i], x[j], x[k]);
                rule.points.push([u * (1.0 - v) * (1.0 - t), v * (1.0 - t), t]);
                rule.weights.push(w[i] * w[j] * w[k] * (1.0 - v) * (1.0 - t) * (1.0 - t));
            }
        }
    }
    rule
}

/// The collapsed pyramid rule: n_ab × n_ab Gauss in (a, b) ∈ \[−1,1\]², n_z Gauss
/// in ζ ∈ \[0,1\]; ξ = a(1−ζ), η = b(1−ζ), weight w_a w_b w_ζ (1−ζ)².
fn pyramid_rule(n_ab: usize, n_z: usize) -> VolumeRule {
    let (a, wa) = gauss_legendre(n_ab);
    let (z, wz) = gauss_unit(n_z);
    let mut rule = VolumeRule { points: Vec::new(), weights: Vec::new() };
    for k in 0..n_z {
        let s = 1.0 - z[k];
        for j in 0..n_ab {
            for i in 0..n_ab {
                rule.points.push([a[i] * s, a[j] * s, z[k]]);
                rule.weights.push(wa[i] * wa[j] * wz[k] * s * s);
            }
        }
    }
    rule
}

/// The n-point Gauss–Legendre rule on \[−1,1\], points ascending: exact for
/// polynomials of degree ≤ 2n − 1. Newton's iteration on P_n from Chebyshev-like
/// initial guesses; weights w_i = 2 / ((1 − x_i²) P_n'(x_i)²).
///
/// # Panics
/// If `n == 0`.
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    assert!(n > 0, "a Gauss rule needs at least one point");
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        let mut t = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (p, d) = legendre(n, t);
            dp = d;
            let dt = p / d;
            t -= dt;
            if dt.abs() < 1e-16 {
                break;
            }
        }
        let (_, d) = legendre(n, t);
        if d != 0.0 {
            dp = d;
        }
        x[n - 1 - i] = t;
        w[n - 1 - i] = 2.0 / ((1.0 - t * t) * dp * dp);
    }
    (x, w)
}

/// (P_n(t), P_n'(t)) by the three-term recurrence.
fn legendre(n: usize, t: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, t);
    for k in 2..=n {
        let p2 = ((2 * k - 1) as f64 * t * p1 - (k - 1) as f64 * p0) / k as f64;
        p0 = p1;
        p1 = p2;
    }
    // n = 1: P_0 = 1, P_1 = t.
    let d = n as f64 * (t * p1 - p0) / (t * t - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
        for n in 1..=6 {
            let (x, w) = gauss_legendre(n);
            assert!(x.windows(2).all(|p| p[0] < p[1]));
            for d in 0..2 * n {
                let exact = if d % 2 == 0 { 2.0 / (d as f64 + 1.0) } else { 0.0 };
                let q: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(d as i32)).sum();
                assert!((q - exact).abs() < 1e-14, "n = {n}, degree {d}: {q} vs {exact}");
            }
        }
    }

    fn factorial(n: usize) -> f64 {
        (1..=n).map(|k| k as f64).product()
    }

    /// ∫ ξ^a η^b ζ^c over the reference cell.
    fn monomial_integral(kind: CellKind, a: usize, b: usize, c: usize) -> f64 {
        let sym = |p: usize| if p % 2 == 0 { 2.0 / (p as f64 + 1.0) } else { 0.0 };
        match kind.reference_shape() {
            Shape::Tetrahedron => factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3),
            Shape::Hexahedron => sym(a) * sym(b) * sym(c),
            Shape::Prism => factorial(a) * factorial(b) / factorial(a + b + 2) * sym(c),
            // ∫_0^1 ζ^c (1−ζ)^{a+b+2} dζ · ∫ a^a ∫ b^b
            _ => sym(a) * sym(b) * factorial(c) * factorial(a + b + 2) / factorial(a + b + c + 3),
        }
    }

    #[test]
    fn rules_integrate_monomials_of_their_degree() {
        for kind in CellKind::FIRST_ORDER {
            for degree in 0..=7 {
                let rule = kind.rule(degree);
                assert!(rule.weights.iter().all(|&w| w > 0.0));
                for a in 0..=degree {
                    for b in 0..=degree - a {
                        for c in 0..=degree - a - b {
                            let q: f64 = rule
                                .iter()
                                .map(|(p, w)| {
                                    w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32)
                                })
                                .sum();
                            let exact = monomial_integral(kind, a, b, c);
                            assert!(
                                (q - exact).abs() < 1e-14 * kind.reference_volume(),
                                "{kind:?} rule({degree}): ξ^{a}η^{b}ζ^{c}: {q} vs {exact}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn stiffness_rules() {
        let sizes: Vec<usize> = CellKind::ALL.iter().map(|k| k.stiffness_rule().len()).collect();
        assert_eq!(sizes, [1, 8, 6, 8, 4, 27, 27, 18, 18, 27, 27, 64]);
        for kind in CellKind::ALL {
            let v: f64 = kind.stiffness_rule().weights.iter().sum();
            // 27-point rules on the volume-8 hex sum to 8 within 1.1e-14: relative there.
            let tol = if kind.order() == 1 { 1e-14 } else { 1e-14 * kind.reference_volume() };
            assert!((v - kind.reference_volume()).abs() < tol, "{kind:?}: Σw = {v}");
        }
    }
}
