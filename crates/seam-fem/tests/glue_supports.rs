//! Patch tests with supports and other interfaces touching the slave side.
//!
//! Where slave interface dofs are prescribed (a symmetry roller on a face that
//! meets the interface) or constrained by an earlier interface (a crossline),
//! their multipliers move to their neighbours (Wohlmuth's modified basis) so
//! that a constant traction stays in the multiplier space. Every case below is
//! an affine displacement u = a x + c that the discretisation reproduces: the
//! solution must equal it at every node, the stress in every cell, and the
//! traction −λ must be σ n_s at every covered slave point, all to 1e-10
//! relative, for standard and dual multipliers, direct and PCG solvers.
//!
//! - Rollers: a master block under a slave block on the plane z = 1 + s x
//!   (s = 0 and s = 0.2), both bodies on a roller u_x = 0 at x = 0, the master
//!   clamped to the exact field at z = 0, every other outer face loaded by σ n,
//!   with σ_xx, σ_yy, σ_zz and σ_yz nonzero (the tilted interface carries shear
//!   and normal traction). Hex|tet and tet|hex, non-matching.
//! - Crossline: blocks A = [0,1]×[0,1]², B = [1,2]×[0,1]² and C = [0,2]×[0,1]×
//!   [1,1.6] glued A|B (x = 1), A|C and B|C (z = 1; C's bottom split at x = 1),
//!   C slave of both upper interfaces, so C's points on the line x = 1, z = 1
//!   are slave points of two interfaces and B's points on it are slave of A|B
//!   and master of B|C. The patch field, A clamped at z = 0, all other outer
//!   faces loaded.
//!
//! Measured (`cargo test -p seam-fem --test main glue_supports:: -- --nocapture`):
//! every error ≤ 3e-14.
use crate::common;

use common::{crossline_patch_error, rollers_patch_error};
use seam::Multiplier;
use seam_fem::generate::BlockKind;
use seam_fem::pcg::PcgOptions;
use seam_fem::Solver;

const RTOL: f64 = 1e-10;

/// Standard and dual, direct and PCG.
fn variants() -> [(Multiplier, Solver); 4] {
    let pcg = Solver::Pcg(PcgOptions { rtol: 1e-14, ..PcgOptions::default() });
    [
        (Multiplier::Standard, Solver::Direct),
        (Multiplier::Dual, Solver::Direct),
        (Multiplier::Standard, pcg),
        (Multiplier::Dual, pcg),
    ]
}

#[test]
fn patch_test_rollers_on_both_bodies_touching_the_interface() {
    use BlockKind::*;
    let mut methods = std::collections::BTreeSet::new();
    for slope in [0.0, 0.2] {
        // The last pair (a thick slave over a coarse master) is solved by
        // elimination (reduced Cholesky) for dual multipliers.
        for (m, s) in [
            (([4, 3, 2], Hex), ([3, 5, 2], Tet)),
            (([3, 4, 2], Tet), ([5, 3, 2], Hex)),
            (([2, 2, 1], Hex), ([6, 6, 6], Hex)),
        ] {
            for variant in variants() {
                let (e, method, label) = rollers_patch_error(m, s, slope, variant);
                assert!(e <= RTOL, "{label} {variant:?}: error {e:.3e}");
                methods.insert(method);
            }
        }
    }
    assert_eq!(methods.len(), 3, "every glue solver ran: {methods:?}");
}

#[test]
fn patch_test_three_blocks_meeting_along_a_crossline() {
    use BlockKind::*;
    for kinds in [[Hex, Tet, Hex], [Tet, Hex, Tet]] {
        for variant in variants() {
            let (e, _, label) = crossline_patch_error(kinds, variant);
            assert!(e <= RTOL, "{label} {variant:?}: error {e:.3e}");
        }
    }
}
