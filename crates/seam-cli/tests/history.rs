//! Load history (`[load]`, amplitudes, values in x, y, z and t): each step
//! solved and written (`steps/`, `.pvd`), the final state as without steps,
//! and bad tables and expressions refused in one line.

use crate::common;

use common::{assert_rejected, json, seam, stacked_case, stderr, vtu_field, write_stacked_blocks};
use std::path::Path;

const E: f64 = 1000.0;
const NU: f64 = 0.25;

/// The stacked glued blocks of `common::stacked_case` (lower 3×3×2, upper
/// 2×2×2 with graded x, interface z = 1/2), with `rest` appended.
fn blocks(dir: &Path, rest: &str) {
    write_stacked_blocks(dir);
    let case = stacked_case((E, NU), (E, NU), "kind = \"glue\"\nmultiplier = \"dual\"", rest);
    std::fs::write(dir.join("case.toml"), case).unwrap();
}

/// The largest difference of a body's displacement from `exact`.
fn miss(path: &Path, exact: impl Fn([f64; 3]) -> [f64; 3]) -> f64 {
    let (points, u) = vtu_field(path, "displacement", false);
    points
        .iter()
        .zip(u.chunks(3))
        .flat_map(|(&x, u)| {
            let e = exact(x);
            (0..3).map(move |k| (u[k] - e[k]).abs())
        })
        .fold(0.0, f64::max)
}

/// Uniaxial strain ε in z with lateral contraction: σ = diag(0, 0, E ε).
fn uniaxial(eps: f64) -> impl Fn([f64; 3]) -> [f64; 3] {
    move |x| [-NU * eps * x[0], -NU * eps * x[1], eps * x[2]]
}

#[test]
fn each_load_step_is_solved_and_written_with_its_collection() {
    let tmp = tempfile::tempdir().unwrap();
    // Pressure 2 reached at t = 0.5 and held; steps at 0.25, 0.5, 0.75, 1.
    let rest = "[load]\nsteps = 4\n\n[[traction]]\nboundary = \"upper:top\"\nt = [0.0, 0.0, -2.0]\n\
                amplitude = [[0.0, 0.0], [0.5, 1.0], [1.0, 1.0]]\n";
    blocks(tmp.path(), rest);
    let o = seam(&["solve", "case.toml"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = tmp.path().join("out");
    let factors = [0.5, 1.0, 1.0, 1.0];
    for (k, a) in factors.iter().enumerate() {
        for body in ["lower", "upper"] {
            let step = out.join(format!("steps/{body}_{:04}.vtu", k + 1));
            let m = miss(&step, uniaxial(-2.0 * a / E));
            assert!(m < 1e-14, "step {} {body}: {m:e}", k + 1);
        }
        let f = seam_io::read_vtu_file(out.join(format!("steps/upper_bottom_interface_{:04}.vtu", k + 1)))
            .unwrap();
        let tn = &f.point_field("normal_traction").unwrap().values;
        assert!(tn.iter().all(|v| (v + 2.0 * a).abs() < 1e-10), "step {}: {tn:?}", k + 1);
    }
    // The final state under today's names is the last step's, byte for byte.
    for name in ["lower", "upper", "upper_bottom_interface"] {
        let last = std::fs::read(out.join(format!("steps/{name}_0004.vtu"))).unwrap();
        assert_eq!(std::fs::read(out.join(format!("{name}.vtu"))).unwrap(), last, "{name}");
        // The collection lists the steps at their times.
        let pvd = std::fs::read_to_string(out.join(format!("{name}.pvd"))).unwrap();
        for (k, t) in ["0.25", "0.5", "0.75", "1.0"].iter().enumerate() {
            let entry =
                format!("timestep=\"{t}\" group=\"\" part=\"0\" file=\"steps/{name}_{:04}.vtu\"", k + 1);
            assert!(pvd.contains(&entry), "{pvd}");
        }
    }
    let s = json(&out.join("summary.json"));
    assert_eq!(s["load"]["steps"], 4);
    assert_eq!(s["load"]["times"], serde_json::json!([0.25, 0.5, 0.75, 1.0]));
    let steps = s["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 4);
    for (step, t) in steps.iter().zip([0.25, 0.5, 0.75, 1.0]) {
        assert_eq!(step["time"], t);
        assert!(step["residuals"][0].as_f64().unwrap() < 1e-10, "{step}");
        assert_eq!(step["active"], 0);
    }
    // A second run refuses to overwrite the steps' files too, and --force replaces them.
    let o = seam(&["solve", "case.toml"], tmp.path());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(seam(&["solve", "case.toml", "--force"], tmp.path()).status.success());
}

#[test]
fn one_step_writes_what_a_case_without_load_writes() {
    let tmp = tempfile::tempdir().unwrap();
    let traction = "[[traction]]\nboundary = \"upper:top\"\nt = [0.3, 0.0, -2.0]\n";
    let mut files = Vec::new();
    for load in ["", "[load]\nsteps = 1\n\n", "[load]\ntimes = [1.0]\n\n"] {
        blocks(tmp.path(), &format!("{load}{traction}"));
        let o = seam(&["solve", "case.toml", "--force"], tmp.path());
        assert!(o.status.success(), "{}", stderr(&o));
        let out = tmp.path().join("out");
        assert!(!out.join("steps").exists() && !out.join("upper.pvd").exists());
        let read = |n: &str| std::fs::read(out.join(n)).unwrap();
        files.push([read("lower.vtu"), read("upper.vtu"), read("upper_bottom_interface.vtu")]);
        let s = json(&out.join("summary.json"));
        assert_eq!(s["load"]["steps"], 1);
        assert_eq!(s["steps"].as_array().unwrap().len(), 1);
    }
    assert!(files[1] == files[0] && files[2] == files[0], "byte-identical results");
}

#[test]
fn values_vary_in_space_and_time() {
    let tmp = tempfile::tempdir().unwrap();
    // The top held at the uniaxial field of ε = 10⁻³ t (a function of x, y, z
    // and t, with a constant amplitude): every step is that field, exactly.
    let rest = "[load]\ntimes = [0.3, 1.0]\n\n[[dirichlet]]\nboundary = \"upper:top\"\n\
                ux = \"-0.25e-3*x*t\"\nuy = \"-0.25e-3*y*t\"\nuz = \"1e-3*z*t\"\namplitude = [[0.0, 1.0]]\n";
    blocks(tmp.path(), rest);
    let o = seam(&["solve", "case.toml"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = tmp.path().join("out");
    for (k, t) in [0.3, 1.0].iter().enumerate() {
        for body in ["lower", "upper"] {
            let m = miss(&out.join(format!("steps/{body}_{:04}.vtu", k + 1)), uniaxial(1e-3 * t));
            assert!(m < 1e-15, "t = {t}, {body}: {m:e}");
        }
    }
    // A traction varying in space: t_z = −(1 + x) on the unit top, its
    // resultant −1.5 (the quadrature is exact for it).
    blocks(tmp.path(), "[[traction]]\nboundary = \"upper:top\"\nt = [0, \"0\", \"-(1 + x)\"]\n");
    let o = seam(&["solve", "case.toml", "--force"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&out.join("summary.json"));
    let load = s["bodies"][1]["applied_load"][2].as_f64().unwrap();
    assert!((load + 1.5).abs() < 1e-13, "{load}");
}

#[test]
fn bad_load_tables_and_expressions_fail_in_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    blocks(tmp.path(), "");
    let good = std::fs::read_to_string(tmp.path().join("case.toml")).unwrap();
    let traction =
        |t: &str, extra: &str| format!("{good}[[traction]]\nboundary = \"upper:top\"\nt = {t}\n{extra}");
    let pressed = traction("[0.0, 0.0, -1.0]", "");
    let cases = [
        (format!("{pressed}[load]\nsteps = 0\n"), "[load]: steps must be at least 1"),
        (
            format!("{pressed}[load]\ntimes = [0.5, 0.4, 1.0]\n"),
            "[load]: times must increase: 0.4 follows 0.5",
        ),
        (
            format!("{pressed}[load]\ntimes = [0.5, 0.9]\n"),
            "[load]: times must end at 1.0 (the full load), not 0.9",
        ),
        (format!("{pressed}[load]\ntimes = [0.0, 1.0]\n"), "must lie in (0, 1]: 0 does not"),
        (format!("{pressed}[load]\nsteps = 2\ntimes = [1.0]\n"), "[load]: give steps or times, not both"),
        (
            traction("[0.0, 0.0, -1.0]", "amplitude = [[0.0, 0.0], [0.6, 1.0], [0.5, 1.0]]\n"),
            "traction 1: amplitude: times must increase: 0.5 follows 0.6",
        ),
        (
            traction("[0.0, 0.0, -1.0]", "amplitude = [[0.0, 0.0], [2.0, 1.0]]\n"),
            "amplitude: times must lie in [0, 1]: 2 does not",
        ),
        (traction("[0.0, 0.0, \"-x*\"]", ""), "traction 1: t (z): the expression '-x*' does not parse"),
        (traction("[0.0, \"w\", 0.0]", ""), "uses 'w'; only x, y, z and t are known"),
        (traction("[0.0, 0.0, nan]", ""), "traction 1: t (z): NaN is not finite"),
        (good.replace("uz = 0.0", "uz = \"cos(\""), "dirichlet 1: uz: the expression 'cos(' does not parse"),
        (good.replace("uz = 0.0", "uz = true"), "a number or an expression in x, y, z and t"),
        (
            good.replace("uz = 0.0", "uz = 0.0\namplitude = []"),
            "dirichlet 1: amplitude: needs at least one [t, factor] pair",
        ),
        // At solve time: no finite value where the solver needs one.
        (
            good.replace("uz = 0.0", "uz = \"1/y\""),
            "dirichlet on lower:bottom, uz: the expression '1/y' is inf at (0, 0, 0), t = 1",
        ),
        (
            traction("[0.0, 0.0, \"-sqrt(x - 0.3)\"]", ""),
            "traction on upper:top, component 3: the expression '-sqrt(x - 0.3)' is NaN at (",
        ),
    ];
    assert_rejected(tmp.path(), &cases);
}
