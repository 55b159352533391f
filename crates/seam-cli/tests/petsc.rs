//! `seam solve --solver petsc` (cargo feature `petsc`; `cargo test -p
//! seam-cli --features petsc --test main petsc::`), run as a user would: the same
//! answers as the direct solver to the solver tolerance, the summary's PETSc
//! report, PETSc's options from `--petsc-options` and `PETSC_OPTIONS`, and
//! one-line errors with exit code 2 that leave nothing behind.
use crate::common;

use common::{json, seam, stderr, vtu_field};
use std::path::Path;
use std::process::{Command, Output};

/// `seam example NAME -o DIR` with small sizes, then the case's multiplier set
/// to `multiplier` (the examples' own: standard for warped-glue).
fn example(dir: &Path, name: &str, extra: &[&str], multiplier: Option<&str>) {
    let o = seam(&[&["example", name, "-o", "ex"][..], extra].concat(), dir);
    assert!(o.status.success(), "{}", stderr(&o));
    if let Some(m) = multiplier {
        let path = dir.join("ex/case.toml");
        let text = std::fs::read_to_string(&path).unwrap();
        let text = text.replace("multiplier = \"standard\"", &format!("multiplier = \"{m}\""));
        std::fs::write(&path, text).unwrap();
    }
}

/// The largest difference of the point field `name` of two VTU files,
/// relative to the field's largest entry.
fn difference(a: &Path, b: &Path, name: &str) -> f64 {
    let ((_, u), (_, v)) = (vtu_field(a, name, false), vtu_field(b, name, false));
    let scale = u.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    u.iter().zip(&v).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

/// The displacements in `ex/direct` and `ex/petsc` agree to `tolerance`
/// relative, both bodies.
fn same_displacements(ex: &Path, tolerance: f64) {
    for body in ["lower", "upper"] {
        let (a, b) = (ex.join(format!("direct/{body}.vtu")), ex.join(format!("petsc/{body}.vtu")));
        let e = difference(&a, &b, "displacement");
        assert!(e <= tolerance, "{body}: PETSc against direct {e:.1e}");
    }
}

/// Solves `ex/case.toml` with `args`, the results moved to `ex/<to>`.
fn solve(dir: &Path, args: &[&str], to: &str) -> Output {
    let o = seam(&[&["solve", "ex/case.toml", "--force"][..], args].concat(), dir);
    if o.status.success() {
        std::fs::rename(dir.join("ex/out"), dir.join("ex").join(to)).unwrap();
    }
    o
}

#[test]
fn warped_glue_gives_the_direct_answer_and_reports_petsc() {
    for multiplier in ["dual", "standard"] {
        warped_glue(multiplier);
    }
}

/// Dual multipliers: CG on the reduced system; standard ones: FGMRES on the
/// saddle point.
fn warped_glue(multiplier: &str) {
    let tmp = tempfile::tempdir().unwrap();
    example(tmp.path(), "warped-glue", &["--ratio", "2"], Some(multiplier));
    let o = solve(tmp.path(), &[], "direct");
    assert!(o.status.success(), "{}", stderr(&o));
    let o = solve(tmp.path(), &["--solver", "petsc", "--rtol", "1e-12"], "petsc");
    assert!(o.status.success(), "{}", stderr(&o));
    let report = String::from_utf8_lossy(&o.stdout);
    let (ksp, pc) = if multiplier == "dual" { ("cg", "gamg") } else { ("fgmres", "fieldsplit") };
    assert!(report.contains(&format!("petsc      {ksp} + {pc}, iterations")), "{report}");
    let ex = tmp.path().join("ex");
    same_displacements(&ex, 1e-9);
    let s = json(&ex.join("petsc/summary.json"));
    assert_eq!(s["solver"], "petsc");
    let p = &s["petsc"];
    assert_eq!((p["ksp_type"].as_str(), p["pc_type"].as_str()), (Some(ksp), Some(pc)), "{p}");
    assert_eq!(p["iterations"].as_array().unwrap().len(), 1, "{p}");
    assert!(p["iterations"][0].as_u64().unwrap() > 0 && p["reasons"][0] == "CONVERGED_RTOL", "{p}");
    assert!(p["residual"].as_f64().unwrap() < 1e-9, "{p}");
    for phase in ["assembly", "setup", "solve"] {
        assert!(p["seconds"][phase].as_f64().unwrap() > 0.0, "{phase}: {p}");
    }
    assert!(json(&ex.join("direct/summary.json")).get("petsc").is_none(), "no petsc report for direct");
}

#[test]
fn contact_gives_the_direct_answer() {
    let tmp = tempfile::tempdir().unwrap();
    example(tmp.path(), "bulging-contact", &["--slave-cells", "4"], None);
    let o = solve(tmp.path(), &[], "direct");
    assert!(o.status.success(), "{}", stderr(&o));
    let o = solve(tmp.path(), &["--solver", "petsc", "--rtol", "1e-12"], "petsc");
    assert!(o.status.success(), "{}", stderr(&o));
    let ex = tmp.path().join("ex");
    same_displacements(&ex, 1e-8);
    let (d, s) = (json(&ex.join("direct/summary.json")), json(&ex.join("petsc/summary.json")));
    assert_eq!(d["contact"]["active_points"], s["contact"]["active_points"]);
    // One KSP solve per step, two for the step whose solve to 1e-3 left the
    // active set as it was and went on to --rtol.
    let steps = s["contact"]["steps"].as_array().unwrap();
    let ksp: Vec<u64> =
        s["petsc"]["iterations"].as_array().unwrap().iter().map(|k| k.as_u64().unwrap()).collect();
    let refined = steps.iter().position(|s| s["full_tolerance"] == true).expect("a step to --rtol");
    assert_eq!(ksp.len(), steps.len() + 1, "{ksp:?}");
    for (k, step) in steps.iter().enumerate() {
        let its = if k == refined { ksp[k] + ksp[k + 1] } else { ksp[k + usize::from(k > refined)] };
        assert_eq!(step["linear_iterations"].as_u64().unwrap(), its, "step {k}");
        assert_eq!(step["full_tolerance"], k >= refined, "step {k}");
    }
    // One PETSc system over the steps: set up at the first, refreshed for
    // each new active set (GAMG's interpolation kept), kept for the solve
    // to --rtol of the step whose active set stayed.
    let setups: Vec<&str> =
        s["petsc"]["setups"].as_array().unwrap().iter().map(|k| k.as_str().unwrap()).collect();
    assert_eq!(setups.len(), ksp.len(), "{setups:?}");
    for (k, setup) in setups.iter().enumerate() {
        let expected = match k {
            0 => "new",
            k if k == refined + 1 => "kept",
            _ => "refreshed",
        };
        assert_eq!(*setup, expected, "solve {k}: {setups:?}");
    }
}

#[test]
fn petsc_options_reach_petsc() {
    let tmp = tempfile::tempdir().unwrap();
    example(tmp.path(), "warped-glue", &["--ratio", "2"], Some("dual"));
    // --petsc-options: a direct solve through KSP (MUMPS LU), and -log_view's table at exit.
    let args =
        ["--solver", "petsc", "--petsc-options", "-pc_type lu -pc_factor_mat_solver_type mumps -log_view"];
    let o = solve(tmp.path(), &args, "lu");
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&tmp.path().join("ex/lu/summary.json"));
    assert_eq!(s["petsc"]["pc_type"], "lu");
    assert!(s["petsc"]["iterations"][0].as_u64().unwrap() <= 2, "{}", s["petsc"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("PETSc Performance Summary"), "-log_view prints at exit: {out}");
    // PETSC_OPTIONS, which --petsc-options overrides.
    let env = |options: &str, args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_seam"))
            .args([&["solve", "ex/case.toml", "--force", "--solver", "petsc"][..], args].concat())
            .env("PETSC_OPTIONS", options)
            .current_dir(tmp.path())
            .output()
            .unwrap()
    };
    let o = env("-pc_type jacobi", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(json(&tmp.path().join("ex/out/summary.json"))["petsc"]["pc_type"], "jacobi");
    let o = env("-pc_type jacobi", &["--petsc-options", "-pc_type gamg"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(json(&tmp.path().join("ex/out/summary.json"))["petsc"]["pc_type"], "gamg");
}

/// A bad option and a KSP that hits its cap: one line naming the case,
/// PETSc's reason, exit code 2, nothing written.
#[test]
fn bad_options_and_diverging_solves_fail_cleanly() {
    let tmp = tempfile::tempdir().unwrap();
    example(tmp.path(), "warped-glue", &["--ratio", "2"], Some("dual"));
    std::fs::remove_dir_all(tmp.path().join("ex/out")).unwrap();
    for (options, says) in [
        ("-pc_type nonsense", "Unable to find requested PC type nonsense"),
        ("-ksp_max_it 1", "DIVERGED_ITS after 1 iterations"),
    ] {
        let o = solve(tmp.path(), &["--solver", "petsc", "--petsc-options", options], "never");
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{options}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{options}: one line: {e}");
        assert!(e.contains("ex/case.toml") && e.contains(says), "{options}: {e}");
        assert!(!tmp.path().join("ex/out").exists(), "{options}: nothing written");
    }
    // --petsc-options without --solver petsc.
    let o = solve(tmp.path(), &["--petsc-options", "-ksp_monitor"], "never");
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--petsc-options needs --solver petsc"), "{}", stderr(&o));
}
