//! Quadrature rules on the reference triangle (placeholder, being written).

/// Highest polynomial degree for which a tabulated triangle rule exists.
pub const MAX_TRIANGLE_DEGREE: usize = 2;

/// A quadrature rule on the reference triangle {(0,0), (1,0), (0,1)}.
///
/// Points are reference coordinates (ξ, η); weights sum to 1, so
/// ∫_T f ≈ |T| Σ_l w_l f(x_l) on any triangle T mapped affinely.
#[derive(Clone, Copy, Debug)]
pub struct TriangleRule {
    /// Polynomial degree integrated exactly.
    pub degree: usize,
    /// Points (ξ, η).
    pub points: &'static [[f64; 2]],
    /// Weights, summing to 1.
    pub weights: &'static [f64],
}

const P2: [[f64; 2]; 3] = [[1.0 / 6.0, 1.0 / 6.0], [2.0 / 3.0, 1.0 / 6.0], [1.0 / 6.0, 2.0 / 3.0]];
const W2: [f64; 3] = [1.0 / 3.0; 3];

/// The cheapest tabulated rule exact for polynomials of degree ≤ `degree`.
///
/// Returns `None` when `degree > MAX_TRIANGLE_DEGREE`.
pub fn triangle_rule(degree: usize) -> Option<TriangleRule> {
    (degree <= MAX_TRIANGLE_DEGREE).then_some(TriangleRule { degree: 2, points: &P2, weights: &W2 })
}
