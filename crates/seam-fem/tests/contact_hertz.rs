//! Hertz contact against the analytic solution: a³ = 3FR/(4E*),
//! p₀ = 3F/(2πa²), p(r) = p₀ √(1 − r²/a²), with a/R = 0.08 and the block
//! 12.5a wide and deep ([`seam_fem::scene::hertz`], a quarter model).
//!
//! Per mesh (slave element size h = 1.5a / n near the contact):
//! - the total contact force equals the applied force F/4 to 1e-8;
//! - the KKT conditions hold to 1e-8;
//! - the peak pressure (at the pole) is within 5 % of p₀, and the contact
//!   radius (the outermost active slave node on the symmetry axes) within one
//!   slave element of a;
//! - under refinement the error of p₀ decreases.
//!
//! Measured (`cargo test --release -p seam-fem --test main contact_hertz:: -- --nocapture`),
//! h = 1.5a/n:
//!
//! | n | dofs | steps | active | p₀ error | a − a_Hertz | max \|p − p_Hertz\| / p₀ on the axes |
//! |---|---|---|---|---|---|---|
//! | 4 | 18 945 | 8 | 8 | +1.87 % | −0.67 h | 0.028 |
//! | 6 | 39 045 | 10 | 19 | +0.73 % | 0 | 0.124 (the node at r = a) |
//! | 8 | 61 050 | 10 | 30 | +0.17 % | −0.33 h | 0.057 |
//!
//! KKT residuals ≤ 3e-16, force errors ≤ 3e-13.
use crate::common;

use common::hertz::{solve, Measured};
use seam_fem::scene::Hertz;

#[test]
fn hertz_contact_radius_and_peak_pressure() {
    let mut levels = Vec::new();
    for n in [4, 6, 8] {
        let p = Hertz { fine_cells: n, ..Hertz::default() };
        levels.push(solve(&format!("n = {n}"), &p));
    }
    for m in &levels {
        let (e_p0, e_a) = (m.p0 / m.p0_exact - 1.0, (m.a - m.a_exact).abs());
        assert!(e_p0.abs() <= 0.05, "p0 {} against {} ({:+.2} %)", m.p0, m.p0_exact, 100.0 * e_p0);
        assert!(
            e_a <= m.h * (1.0 + 1e-9),
            "a {} against {}: more than one slave element h = {}",
            m.a,
            m.a_exact,
            m.h
        );
    }
    for pair in levels.windows(2) {
        let error = |m: &Measured| (m.p0 / m.p0_exact - 1.0).abs();
        assert!(
            error(&pair[1]) < error(&pair[0]),
            "the p0 error does not decrease: h {} → {}",
            pair[0].h,
            pair[1].h
        );
    }
}
