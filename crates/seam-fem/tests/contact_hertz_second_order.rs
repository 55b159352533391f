//! Hertz contact ([`seam_fem::scene::hertz`], a quarter model, a/R = 0.08) on
//! second-order tetrahedra (Tet10, Tri6 slave faces) and hexahedra (Hex27,
//! Quad9 slave faces), dual multipliers in the transformed basis of Popp et
//! al. (2012), against first order at about the same number of unknowns:
//! first order with n slave cells across 1.5a, second order with n/2.
//!
//! MEASURED
mod common;

use common::hertz::{solve, Measured};
use seam::Multiplier;
use seam_fem::generate::BlockKind;
use seam_fem::scene::Hertz;

/// The scene with `n` fine slave cells of `cells`, first or second order.
fn scene(n: usize, cells: BlockKind, second_order: bool, multiplier: Multiplier) -> Hertz {
    Hertz { fine_cells: n, cells, second_order, multiplier, ..Hertz::default() }
}

/// Solves first order at n and second order at n/2, both dual; prints and
/// returns both.
fn compare(n: usize, cells: BlockKind) -> (Measured, Measured) {
    let first = solve(&format!("{cells:?} first order, n = {n}"), &scene(n, cells, false, Multiplier::Dual));
    let second = solve(
        &format!("{cells:?} second order, n = {}", n / 2),
        &scene(n / 2, cells, true, Multiplier::Dual),
    );
    (first, second)
}

/// The study behind the table of the module doc.
#[test]
#[ignore = "a study: cargo test --release -p seam-fem --test contact_hertz_second_order -- --ignored --nocapture"]
fn hertz_second_order_study() {
    for cells in [BlockKind::Tet, BlockKind::Hex] {
        for n in [4, 8] {
            compare(n, cells);
        }
        for n in [2, 4].into_iter().filter(|_| cells == BlockKind::Hex) {
            solve(
                &format!("{cells:?} second order lumped, n = {n}"),
                &scene(n, cells, true, Multiplier::Lumped),
            );
        }
    }
}
