//! Glue and contact in one problem: base | contact | block | glue | block.
//!
//! A base [0,1]² × [0,1] (E = 2000), a block [0,1]² × [1,1.5] resting on it
//! through a frictionless contact interface (slave: the block's bottom), and a
//! top block [0,1]² × [1.5,2.2] glued to it (slave: the top block's bottom),
//! both blocks E = 1000, ν = 0.3 everywhere. The top is pressed by p = 3
//! (traction −p e_z); every body sits on rollers u_x = 0 at x = 0 and u_y = 0
//! at y = 0 (they touch both interfaces' slave sides), the base also on
//! u_z = 0 at z = 0. The blocks are held in z by the contact alone (force
//! control). The exact solution is uniaxial, σ = −p e_z⊗e_z in every body:
//! u = (ν p x / E, ν p y / E, −p z / E + c) per body with c making u_z
//! continuous across both interfaces; the contact pressure is p at every
//! contact point, every contact point is active, and the glued traction is
//! (0, 0, p) on the top block's bottom (outward normal −e_z).
//!
//! Asserted to 1e-10 relative for lumped and dual contact multipliers; dual
//! glue multipliers with the direct and PCG solvers (glued slave dofs
//! eliminated) and standard ones with both (a saddle point per active-set
//! step, by LDLᵀ or matrix-free PCG); hex and tet meshes, all three meshes
//! non-matching; KKT
//! residuals ≤ 1e-10; the same bits on 1 and 2 threads.
//!
//! Measured (`cargo test -p seam-fem --test main mixed:: -- --nocapture`): errors
//! ≤ 1e-13.
use crate::common;

use common::mixed::{Stack, RTOL};
use seam::Multiplier;
use seam_fem::generate::BlockKind;
use seam_fem::pcg::PcgOptions;
use seam_fem::{Solution, Solver};

#[test]
fn glue_and_contact_in_one_problem_pass_the_pressure_patch_test() {
    use BlockKind::*;
    let pcg = Solver::Pcg(PcgOptions { rtol: 1e-14, ..PcgOptions::default() });
    for kinds in [[Hex, Tet, Hex], [Tet, Hex, Tet]] {
        let stack = Stack::new(kinds);
        for contact in [Multiplier::Lumped, Multiplier::Dual] {
            for (glue, solver, name) in [
                (Multiplier::Dual, Solver::Direct, "direct"),
                (Multiplier::Dual, pcg, "PCG"),
                (Multiplier::Standard, Solver::Direct, "direct"),
                (Multiplier::Standard, pcg, "PCG"),
            ] {
                println!("  {kinds:?}, contact {contact:?}, glue {glue:?}, {name}");
                let s = stack.solve(contact, glue, solver).unwrap();
                let e = stack.error(&s);
                println!("    {}", s.report.method);
                assert!(e <= RTOL, "{kinds:?} {contact:?} {glue:?} {name}: error {e:.3e}");
            }
        }
    }
}

#[test]
fn glue_and_contact_give_the_same_bits_on_one_and_two_threads() {
    let stack = Stack::new([BlockKind::Hex, BlockKind::Tet, BlockKind::Hex]);
    let solve = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| stack.solve(Multiplier::Lumped, Multiplier::Dual, Solver::Direct).unwrap())
    };
    let (one, two) = (solve(1), solve(2));
    assert_eq!(one.displacement, two.displacement);
    for (a, b) in one.interfaces.iter().zip(&two.interfaces) {
        assert_eq!(a.traction, b.traction);
    }
    let pressure = |s: &Solution| s.interfaces[0].contact.as_ref().unwrap().pressure.clone();
    assert_eq!(pressure(&one), pressure(&two));
}
