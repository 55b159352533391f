//! `seam solve` with Coulomb friction (`friction = μ` on a contact
//! interface): a block held on a base by friction alone, and the bad inputs.

use crate::common;

use common::{assert_rejected, json, seam, stderr, write_block_of};
use seam_fem::generate::{BlockKind, Side};
use std::path::Path;

/// A base [0,1]² × [0, ½] (hexahedra) clamped at the bottom and a block
/// [0,1]² × [½, 1] (tetrahedra) on it, ν = 0, in contact with friction 0.3;
/// the block pressed by 2 and sheared by τ = 0.5 on its top, the sides
/// x = 0, 1 of both with the complementary shear of σ_xz = τ: a uniform
/// state, exact, with every contact point sticking.
fn case(dir: &Path, extra: &str) -> String {
    let sides = [("bottom", Side::ZMin), ("top", Side::ZMax), ("xmin", Side::XMin), ("xmax", Side::XMax)];
    write_block_of(
        &dir.join("base.msh"),
        ([3, 3, 2], BlockKind::Hex, false),
        |x, y, z| [x, y, 0.5 * z],
        &sides,
    );
    write_block_of(
        &dir.join("block.msh"),
        ([2, 2, 2], BlockKind::Tet, false),
        |x, y, z| [x, y, 0.5 + 0.5 * z],
        &sides,
    );
    let mut text = String::new();
    for body in ["base", "block"] {
        text +=
            &format!("[[body]]\nname = \"{body}\"\nmesh = \"{body}.msh\"\nyoung = 100.0\npoisson = 0.0\n\n");
    }
    text += "[[interface]]\nmaster = \"base:top\"\nslave = \"block:bottom\"\nkind = \"contact\"\nfriction = 0.3\n\n";
    text += "[[dirichlet]]\nboundary = \"base:bottom\"\nux = 0.0\nuy = 0.0\nuz = 0.0\n\n";
    text += "[[traction]]\nboundary = \"block:top\"\nt = [0.5, 0.0, -2.0]\n\n";
    for body in ["base", "block"] {
        text += &format!("[[traction]]\nboundary = \"{body}:xmin\"\nt = [0.0, 0.0, -0.5]\n\n");
        text += &format!("[[traction]]\nboundary = \"{body}:xmax\"\nt = [0.0, 0.0, 0.5]\n\n");
    }
    text + extra
}

#[test]
fn a_block_held_by_friction_alone_sticks_with_the_exact_traction() {
    held_by_friction_alone(&[], "sparse Cholesky, semismooth Newton on the condensed contact unknowns");
    if cfg!(feature = "petsc") {
        held_by_friction_alone(
            &["--solver", "petsc", "--rtol", "1e-13"],
            "PETSc KSP per semismooth Newton step on the reduced displacements",
        );
    }
}

/// The block held by friction alone, solved with `flags` by `method`.
fn held_by_friction_alone(flags: &[&str], method: &str) {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("case.toml"), case(tmp.path(), "[load]\nsteps = 2\n")).unwrap();
    let o = seam(&[&["solve", "case.toml"], flags].concat(), tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = tmp.path().join("out");
    for k in ["steps/block_bottom_interface_0001.vtu", "block_bottom_interface.vtu"] {
        let a = if k.starts_with("steps") { 0.5 } else { 1.0 };
        let f = seam_io::read_vtu_file(out.join(k)).unwrap();
        let field = |name: &str| f.point_field(name).unwrap_or_else(|| panic!("{name}")).values.clone();
        assert!(field("stick").iter().all(|&s| s == 1.0), "{k}");
        let t = field("traction");
        for t in t.chunks(3) {
            let miss = (t[0] + 0.5 * a).abs().max(t[1].abs()).max((t[2] - 2.0 * a).abs());
            assert!(miss < 1e-10, "{k}: {t:?}");
        }
        assert!(field("friction_bound").iter().all(|b| (b - 0.6 * a).abs() < 1e-10), "{k}");
        assert!(field("slip").iter().chain(&field("slip_increment")).all(|s| s.abs() < 1e-12), "{k}");
    }
    let s = json(&out.join("summary.json"));
    assert_eq!(s["method"], method);
    for step in s["steps"].as_array().unwrap() {
        assert_eq!(
            (step["active"].as_u64(), step["stick"].as_u64(), step["slip"].as_u64()),
            (Some(9), Some(9), Some(0))
        );
        assert!(step["iterations"].as_u64().unwrap() <= 3, "{step}");
        for key in ["cone", "stick", "slip_direction"] {
            assert!(step["friction"][key].as_f64().unwrap() < 1e-10, "{key}: {step}");
        }
    }
}

#[test]
fn bad_friction_fails_in_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let good = case(tmp.path(), "");
    let cases = [
        (
            good.replace("friction = 0.3", "friction = -0.1"),
            "friction = -0.1 must be a finite coefficient ≥ 0",
        ),
        (good.replace("friction = 0.3", "friction = nan"), "friction = NaN must be a finite coefficient ≥ 0"),
        (
            good.replace("kind = \"contact\"", "kind = \"glue\""),
            "friction applies to contact interfaces only",
        ),
    ];
    assert_rejected(tmp.path(), &cases);
    std::fs::write(tmp.path().join("case.toml"), &good).unwrap();
    let o = seam(&["solve", "case.toml", "--solver", "pcg"], tmp.path());
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("has friction: its semismooth Newton systems are not symmetric"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1);
    assert!(!tmp.path().join("out").exists());
}

#[test]
fn driven_past_the_bound_every_point_slips_and_coulomb_holds_in_every_step() {
    let tmp = tempfile::tempdir().unwrap();
    // The top pushed 0.05 along x over 10 steps, the sides with the shear μP = 0.6.
    let text = case(tmp.path(), "[[dirichlet]]\nboundary = \"block:top\"\nux = 0.05\n\n[load]\nsteps = 10\n")
        .replace("t = [0.5, 0.0, -2.0]", "t = [0.0, 0.0, -2.0]")
        .replace("t = [0.0, 0.0, -0.5]", "t = [0.0, 0.0, -0.6]")
        .replace("t = [0.0, 0.0, 0.5]", "t = [0.0, 0.0, 0.6]");
    std::fs::write(tmp.path().join("case.toml"), text).unwrap();
    let o = seam(&["solve", "case.toml"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&tmp.path().join("out/summary.json"));
    let steps = s["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 10);
    let last = steps.last().unwrap();
    assert_eq!((last["stick"].as_u64(), last["slip"].as_u64()), (Some(0), Some(9)), "{last}");
    for step in steps {
        for key in ["cone", "stick", "slip_direction"] {
            assert!(step["friction"][key].as_f64().unwrap() < 1e-10, "{key}: {step}");
        }
    }
    let f = seam_io::read_vtu_file(tmp.path().join("out/block_bottom_interface.vtu")).unwrap();
    let tt = &f.point_field("tangential_traction").unwrap().values;
    // The frictional traction on the block opposes its slip (+x).
    assert!(tt.chunks(3).all(|t| (t[0] + 0.6).abs() < 1e-10 && t[1].abs() < 1e-10), "{tt:?}");
}

/// Semismooth Newton stopped by `[contact] max_iterations`: one line naming
/// the case and what still changed, exit 2, nothing written.
#[test]
fn the_iteration_cap_stops_friction_in_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let extra = "[[dirichlet]]\nboundary = \"block:top\"\nux = 0.05\n\n[contact]\nmax_iterations = 1\n";
    std::fs::write(tmp.path().join("case.toml"), case(tmp.path(), extra)).unwrap();
    let o = seam(&["solve", "case.toml"], tmp.path());
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(
        err.contains("case.toml")
            && err.contains("semismooth Newton did not converge in 1 steps (last step: "),
        "{err}"
    );
    assert!(!tmp.path().join("out").exists());
}
