//! The plane triangles segments are integrated on, and one quadrature point's
//! share of a pair's blocks (D4–D5): what the plane path (`kernel`) and the
//! curved path (`isoparametric`) share.

use crate::catalogue::Xi;

/// A plane triangle and the reference coordinates of its vertices on the
/// slave side (on the curved path: of the slave sub-face's chord) and on the
/// master face.
#[derive(Clone, Copy)]
pub(super) struct Piece {
    pub(super) q: [[f64; 2]; 3],
    pub(super) xs: [Xi; 3],
    pub(super) xm: [Xi; 3],
}

impl Piece {
    /// The midpoints of the plane edges 01, 12 and 20.
    pub(super) fn midpoints(&self) -> [[f64; 2]; 3] {
        edge_midpoints(self.q)
    }

    /// The four children of the cut at the midpoints, given the slave and
    /// master coordinates there.
    pub(super) fn children(&self, ms: [Xi; 3], mm: [Xi; 3]) -> [Piece; 4] {
        let ([q0, q1, q2], m) = (self.q, self.midpoints());
        let [xs, xm] = [self.xs, self.xm];
        [
            Piece { q: [q0, m[0], m[2]], xs: [xs[0], ms[0], ms[2]], xm: [xm[0], mm[0], mm[2]] },
            Piece { q: [m[0], q1, m[1]], xs: [ms[0], xs[1], ms[1]], xm: [mm[0], xm[1], mm[1]] },
            Piece { q: [m[2], m[1], q2], xs: [ms[2], ms[1], xs[2]], xm: [mm[2], mm[1], xm[2]] },
            Piece { q: [m[1], m[2], m[0]], xs: [ms[1], ms[2], ms[0]], xm: [mm[1], mm[2], mm[0]] },
        ]
    }
}

/// The point with barycentric coordinates (1−ξ−η, ξ, η) in triangle `t`.
#[inline]
pub(super) fn barycentric(t: [Xi; 3], pt: [f64; 2]) -> Xi {
    let l0 = 1.0 - pt[0] - pt[1];
    [l0 * t[0][0] + pt[0] * t[1][0] + pt[1] * t[2][0], l0 * t[0][1] + pt[0] * t[1][1] + pt[1] * t[2][1]]
}

/// Area of triangle `t`.
#[inline]
pub(super) fn triangle_area(t: [Xi; 3]) -> f64 {
    signed_area(t).abs()
}

/// Signed area of triangle `t` (positive when counter-clockwise).
#[inline]
pub(super) fn signed_area(t: [Xi; 3]) -> f64 {
    0.5 * ((t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[1][1] - t[0][1]) * (t[2][0] - t[0][0]))
}

/// One quadrature point's share of a pair's blocks: D_pq += w φ_p φ_q (upper
/// triangle, q ≥ p) and B_pq += w φ_p λ_q (fixed sizes, so the loops unroll;
/// shape arrays may be zero-padded).
#[inline(always)]
pub(super) fn add_point<const N: usize, const NS: usize, const NM: usize>(
    d: &mut [[f64; N]; N],
    b: &mut [[f64; N]; N],
    wj: f64,
    phi: &[f64; NS],
    lam: &[f64; NM],
) {
    add_d(d, wj, phi);
    add_b(b, wj, phi, lam);
}

/// D_pq += w φ_p φ_q, upper triangle (q ≥ p).
#[inline(always)]
pub(super) fn add_d<const N: usize, const NS: usize>(d: &mut [[f64; N]; N], wj: f64, phi: &[f64; NS]) {
    for p in 0..NS {
        let wp = wj * phi[p];
        for q in p..NS {
            d[p][q] += wp * phi[q];
        }
    }
}

/// B_pq += w φ_p λ_q, into B's columns `b[q][p]`.
#[inline(always)]
pub(super) fn add_b<const N: usize, const NS: usize, const NM: usize, const NB: usize>(
    b: &mut [[f64; NB]; N],
    wj: f64,
    phi: &[f64; NS],
    lam: &[f64; NM],
) {
    for q in 0..NM {
        let wq = wj * lam[q];
        for p in 0..NS {
            b[q][p] += wq * phi[p];
        }
    }
}

/// The midpoints of the edges 01, 12 and 20 of a triangle.
pub(super) fn edge_midpoints([a, b, c]: [[f64; 2]; 3]) -> [[f64; 2]; 3] {
    let mid = |a: [f64; 2], b: [f64; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    [mid(a, b), mid(b, c), mid(c, a)]
}
