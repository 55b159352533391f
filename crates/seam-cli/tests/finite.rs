//! Hyperelastic bodies in finite deformation from a case file
//! (`material = "neo-hookean"`, `[newton]`): glued, over load steps, the
//! Cauchy stress written, Newton's iterations in `summary.json`; mixed or
//! bad materials refused in one line.

use crate::common;

use common::{assert_rejected, json, seam, stacked_case, stderr, vtu_field, write_stacked_blocks};
use seam_fem::hyperelastic::Hyperelastic;
use seam_fem::Material;

const E: f64 = 1000.0;
const NU: f64 = 0.3;

/// The stacked glued blocks (dual multipliers), both neo-Hookean, the upper
/// top pressed by the dead load `t` per reference area, then `rest`.
fn case(t: f64, rest: &str) -> String {
    let text = stacked_case(
        (E, NU),
        (E, NU),
        "kind = \"glue\"\nmultiplier = \"dual\"",
        &format!("[[traction]]\nboundary = \"upper:top\"\nt = [0.0, 0.0, {t:?}]\n\n{rest}"),
    );
    text.replace("poisson = 0.3\n", "poisson = 0.3\nmaterial = \"neo-hookean\"\n")
}

/// `seam solve` on `text` as case.toml in `dir`: the output directory and
/// the `n` load steps of its summary.
fn solved_steps(dir: &std::path::Path, text: &str, n: usize) -> (std::path::PathBuf, Vec<serde_json::Value>) {
    std::fs::write(dir.join("case.toml"), text).unwrap();
    let o = seam(&["solve", "case.toml"], dir);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = dir.join("out");
    let steps = json(&out.join("summary.json"))["steps"].as_array().unwrap().clone();
    assert_eq!(steps.len(), n);
    (out, steps)
}

/// `seam solve` on `text` as case.toml in `dir`, refused: exit 2, one line
/// on stderr (returned), no output directory.
fn refused_line(dir: &std::path::Path, text: &str) -> String {
    std::fs::write(dir.join("case.toml"), text).unwrap();
    let o = seam(&["solve", "case.toml"], dir);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let line = stderr(&o);
    assert_eq!(line.trim_end().lines().count(), 1, "{line}");
    assert!(!dir.join("out").exists());
    line
}

/// Compressed by a fifth of E over three load steps: a homogeneous state
/// F = diag(s, s, λ) in both bodies (their displacements affine), whose
/// Cauchy stress in the VTU is the law's at that F (σ_xx = σ_yy = 0) and
/// carries the dead load, s² σ_zz = t; every step converged by Newton, its
/// residuals and line-search steps in `summary.json`.
#[test]
fn glued_neo_hookean_blocks_under_a_dead_load_over_load_steps() {
    let tmp = tempfile::tempdir().unwrap();
    write_stacked_blocks(tmp.path());
    let t = -200.0;
    let text = case(t, "[load]\nsteps = 3\n\n[newton]\nrtol = 1e-11\n");
    let (out, steps) = solved_steps(tmp.path(), &text, 3);
    for step in steps {
        let residuals = step["residuals"].as_array().unwrap();
        let line_search = step["line_search"].as_array().unwrap();
        assert!(!residuals.is_empty() && residuals.len() == line_search.len(), "{step}");
        assert_eq!(step["iterations"].as_u64().unwrap() as usize, residuals.len(), "{step}");
        assert!(residuals.last().unwrap().as_f64().unwrap() <= 1e-11, "{step}");
    }
    let law = Hyperelastic::neo_hookean(&Material::new(E, NU).unwrap());
    for body in ["lower", "upper"] {
        let path = out.join(format!("{body}.vtu"));
        let (points, u) = vtu_field(&path, "displacement", false);
        // F from two points: u_x = (s − 1) x, u_z = (λ − 1) z (the bottom at z = 0 held in z).
        let (mut s_x, mut lambda) = (None, None);
        for (x, u) in points.iter().zip(u.chunks(3)) {
            if x[0] > 0.5 {
                s_x.get_or_insert(1.0 + u[0] / x[0]);
            }
            if x[2] > 0.4 {
                lambda.get_or_insert(1.0 + u[2] / x[2]);
            }
        }
        let (s_x, lambda) = (s_x.unwrap(), lambda.unwrap());
        for (x, u) in points.iter().zip(u.chunks(3)) {
            let exact = [(s_x - 1.0) * x[0], (s_x - 1.0) * x[1], (lambda - 1.0) * x[2]];
            for k in 0..3 {
                assert!((u[k] - exact[k]).abs() <= 1e-9, "{body}: u at {x:?}: {u:?} against {exact:?}");
            }
        }
        let sigma = law.cauchy(&[[s_x, 0.0, 0.0], [0.0, s_x, 0.0], [0.0, 0.0, lambda]]).unwrap();
        let (_, stress) = vtu_field(&path, "stress", false);
        for v in stress.chunks(6) {
            assert!(v[0].abs() <= 1e-8 * t.abs() && v[1].abs() <= 1e-8 * t.abs(), "{body}: {v:?}");
            assert!((v[2] - sigma[2][2]).abs() <= 1e-8 * t.abs(), "{body}: {v:?} against {sigma:?}");
            assert!((s_x * s_x * v[2] - t).abs() <= 1e-8 * t.abs(), "{body}: the dead load: {v:?}");
        }
        assert!(lambda < 0.9 && s_x > 1.0, "{body}: compressed: λ = {lambda}, s = {s_x}");
    }
}

/// A linear body with a hyperelastic one, an unknown material, a bad
/// `[newton]`: one line, exit 2, nothing written.
#[test]
fn mixed_and_bad_materials_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    write_stacked_blocks(tmp.path());
    let good = case(-1.0, "");
    let mixed = good.replacen("material = \"neo-hookean\"\n", "", 1);
    assert_rejected(
        tmp.path(),
        &[
            (mixed, "body \"lower\" is linear and body \"upper\" hyperelastic"),
            (good.replacen("neo-hookean", "rubber", 1), "rubber"),
            (good.clone() + "[newton]\nrtol = 0.0\n", "[newton]: rtol = 0 must lie in (0, 1)"),
            (good.clone() + "[newton]\nmax_iterations = 0\n", "[newton]: max_iterations must be at least 1"),
            (
                good.replace("multiplier = \"dual\"", "multiplier = \"standard\""),
                "needs dual or lumped multipliers",
            ),
        ],
    );
}

/// Neo-Hookean blocks in contact from a case file, frictionless and with
/// μ = 0.3: the upper top pressed down by a tenth of its height over three
/// steps; every step converged by Newton with its active points (and with
/// friction its sticking and slipping points) in `summary.json`, the
/// contact pressure in the interface's VTU positive where the points are
/// active and zero elsewhere.
#[test]
fn neo_hookean_blocks_in_contact_from_a_case_file() {
    for friction in [0.0, 0.3] {
        blocks_in_contact(friction);
    }
}

fn blocks_in_contact(friction: f64) {
    let tmp = tempfile::tempdir().unwrap();
    write_stacked_blocks(tmp.path());
    let text = stacked_case(
        (E, NU),
        (E, NU),
        &format!("kind = \"contact\"\nmultiplier = \"dual\"\nfriction = {friction:?}"),
        "[[dirichlet]]\nboundary = \"upper:top\"\nux = 0.0\nuy = 0.0\nuz = -0.05\n\n[load]\nsteps = 3\n",
    )
    .replace("poisson = 0.3\n", "poisson = 0.3\nmaterial = \"neo-hookean\"\n");
    let (out, steps) = solved_steps(tmp.path(), &text, 3);
    for step in steps {
        let residuals = step["residuals"].as_array().unwrap();
        assert!(!residuals.is_empty(), "{step}");
        assert!(residuals.last().unwrap().as_f64().unwrap() <= 1e-10, "{step}");
        assert!(step["active"].as_u64().unwrap() > 0, "{step}");
        if friction > 0.0 {
            let (stick, slip) = (step["stick"].as_u64().unwrap(), step["slip"].as_u64().unwrap());
            assert_eq!(stick + slip, step["active"].as_u64().unwrap(), "{step}");
        }
    }
    let interface = out.join("upper_bottom_interface.vtu");
    let (_, pressure) = vtu_field(&interface, "contact_pressure", false);
    let (_, active) = vtu_field(&interface, "active", false);
    assert!(active.contains(&1.0));
    for (p, a) in pressure.iter().zip(&active) {
        assert!(if *a == 1.0 { *p > 0.0 } else { *p == 0.0 }, "pressure {p}, active {a}");
    }
}

/// A prescribed displacement that turns a cell inside out (the upper block
/// on the lower, both 0.5 thick, pressed down by 1.2 over two steps): one
/// line naming the body,
/// the cell by its Gmsh element tag and type in the mesh file, and the load
/// step; exit 2, nothing written.
#[test]
fn an_inverted_element_is_named_by_its_gmsh_tag_and_the_load_step() {
    let tmp = tempfile::tempdir().unwrap();
    write_stacked_blocks(tmp.path());
    let text = stacked_case(
        (E, NU),
        (E, NU),
        "kind = \"glue\"\nmultiplier = \"dual\"",
        "[[dirichlet]]\nboundary = \"upper:top\"\nuz = -1.2\n\n[load]\nsteps = 2\n",
    )
    .replace("poisson = 0.3\n", "poisson = 0.3\nmaterial = \"neo-hookean\"\n");
    let line = refused_line(tmp.path(), &text);
    for part in [
        "case.toml: finite deformation: load step 2 of 2 (t = 1): body \"",
        "\": element ",
        " (an 8-node hexahedron) of ",
        ".msh is inverted by the displacements (J ≤ 0)",
    ] {
        assert!(line.contains(part), "'{part}' in {line}");
    }
}

/// Newton not converging within `[newton] max_iterations` (one iteration,
/// even after the step is cut in halves): one line with the load step, the
/// iterations and the residual; exit 2, nothing written.
#[test]
fn newton_not_converging_names_the_step_the_iterations_and_the_residual() {
    let tmp = tempfile::tempdir().unwrap();
    write_stacked_blocks(tmp.path());
    let text = case(-200.0, "[load]\nsteps = 2\n\n[newton]\nmax_iterations = 1\n");
    let line = refused_line(tmp.path(), &text);
    for part in [
        "case.toml: finite deformation: load step 1 of 2 (t = 0.5): ",
        "Newton did not converge in 1 iterations (relative residual ",
        "asked 1e-10) (after cutting the step in halves 5 times)",
    ] {
        assert!(line.contains(part), "'{part}' in {line}");
    }
}
