//! `seam solve` on frictionless contact cases, run as a user would: two stacked
//! blocks meshed independently (the interface does not match node for node),
//! a case file, the binary, and its output files read back.

use crate::common;

use common::{assert_rejected, json, seam, stacked_case, stderr, vtu_field, write_block};
use seam_fem::generate::Side;
use std::path::Path;

/// The lower block (master): E, ν.
const E1: f64 = 1000.0;
const NU1: f64 = 0.25;
/// The upper block (slave), softer and laterally more compliant, so that the
/// two sides slide along the frictionless interface.
const E2: f64 = 500.0;
const NU2: f64 = 0.3;
/// The height of each block.
const H: f64 = 0.5;
/// The pressure on top of the upper block.
const P: f64 = 2.0;
/// Slave points on the interface: the upper block's 3 × 3 faces.
const SLAVE_NODES: usize = 16;

/// The lower block [0,1]² × [0, H], 4×4×2 hexahedra (master), and the upper
/// one over [0,1]² from z = H + gap(x) to 2H + gap(x), 3×3×2 hexahedra graded
/// along x (slave), each with rollers on x = 0 (ux = 0) and y = 0 (uy = 0), the
/// lower one on z = 0 (uz = 0), and `top` (a traction or a Dirichlet condition
/// on "upper:top").
fn contact_case(dir: &Path, gap: impl Fn(f64) -> f64, multiplier: &str, top: &str) {
    let sides = [("bottom", Side::ZMin), ("top", Side::ZMax), ("xmin", Side::XMin), ("ymin", Side::YMin)];
    write_block(&dir.join("lower.msh"), [4, 4, 2], |u, v, w| [u, v, H * w], &sides);
    write_block(
        &dir.join("upper.msh"),
        [3, 3, 2],
        |u, v, w| {
            let x = 0.7 * u + 0.3 * u * u;
            [x, v, H + gap(x) + H * w]
        },
        &sides,
    );
    let rollers = "[[dirichlet]]\nboundary = \"upper:xmin\"\nux = 0.0\n\n[[dirichlet]]\nboundary = \"upper:ymin\"\nuy = 0.0\n";
    let case = stacked_case(
        (E1, NU1),
        (E2, NU2),
        &format!("kind = \"contact\"\n{multiplier}"),
        &format!("{rollers}\n{top}"),
    );
    std::fs::write(dir.join("case.toml"), case).unwrap();
}

fn pressed() -> String {
    format!("[[traction]]\nboundary = \"upper:top\"\nt = [0.0, 0.0, -{P:?}]\n")
}

fn moved(uz: f64) -> String {
    format!("[[dirichlet]]\nboundary = \"upper:top\"\nuz = {uz:?}\n")
}

/// A point field of an interface VTU file written by `seam solve`, with its
/// points, through seam-io's reader.
fn field(path: &Path, name: &str) -> (Vec<[f64; 3]>, Vec<f64>) {
    let f = seam_io::read_vtu_file(path).unwrap();
    let values = f.point_field(name).unwrap_or_else(|| panic!("{} has no field {name}", path.display()));
    (f.mesh.points().to_vec(), values.values.clone())
}

fn f64s(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

/// Runs `seam solve case.toml ARGS` in `dir` and returns summary.json and stdout.
fn solve(dir: &Path, args: &[&str]) -> (serde_json::Value, String) {
    let o = seam(&[&["solve", "case.toml"], args].concat(), dir);
    assert!(o.status.success(), "{}", stderr(&o));
    (json(&dir.join("out/summary.json")), String::from_utf8_lossy(&o.stdout).into_owned())
}

/// The interface VTU's contact fields are consistent with each other: traction
/// = −pressure · normal, active where the pressure is positive.
fn check_interface_fields(path: &Path) {
    let (_, p) = field(path, "contact_pressure");
    let (_, n) = field(path, "normal");
    let (_, t) = field(path, "traction");
    for (k, &p) in p.iter().enumerate() {
        for c in 0..3 {
            assert!((t[3 * k + c] + p * n[3 * k + c]).abs() <= 1e-14 * P.max(p), "traction at {k}");
        }
    }
    for name in
        ["gap", "initial_gap", "active", "normal_traction", "displacement", "constrained", "body_point"]
    {
        assert_eq!(field(path, name).1.len() % SLAVE_NODES, 0, "{name}");
    }
}

/// The active-set steps of summary.json's `contact` add up: their number is
/// `iterations`, each starts from the last one's set, the last one changes
/// nothing and ran with the final active set.
fn check_steps(c: &serde_json::Value) {
    let steps = c["steps"].as_array().unwrap();
    assert_eq!(c["iterations"].as_u64().unwrap() as usize, steps.len());
    let count = |s: &serde_json::Value, key: &str| s[key].as_u64().unwrap();
    for pair in steps.windows(2) {
        let next = count(&pair[0], "active") + count(&pair[0], "added") - count(&pair[0], "removed");
        assert_eq!(count(&pair[1], "active"), next, "{steps:?}");
    }
    let last = steps.last().unwrap();
    assert_eq!((count(last, "added"), count(last, "removed")), (0, 0), "{steps:?}");
    assert_eq!(last["active"], c["active_points"]);
}

/// The displacements in out/{lower,upper}.vtu are those of the uniaxial stress
/// σ_zz = −p through both blocks, the upper one started `gap0` above the lower
/// one and ending `gap1` above it: u = (ν₁ p x, ν₁ p y, −p z)/E₁ below; above
/// the lateral expansion ν₂ p/E₂ is larger (the sides slide), and the
/// shortening adds to the closed part of the gap.
fn check_uniaxial(out: &Path, p: f64, gap0: f64, gap1: f64, what: &str) {
    let scale = p / E2 + gap0;
    for body in ["lower", "upper"] {
        let (points, u) = vtu_field(&out.join(format!("{body}.vtu")), "displacement", false);
        for (x, u) in points.iter().zip(u.chunks(3)) {
            let exact = if body == "lower" {
                [NU1 * p * x[0] / E1, NU1 * p * x[1] / E1, -p * x[2] / E1]
            } else {
                let bottom = -p * H / E1 - (gap0 - gap1);
                [NU2 * p * x[0] / E2, NU2 * p * x[1] / E2, bottom - p * (x[2] - H - gap0) / E2]
            };
            for k in 0..3 {
                assert!(
                    (u[k] - exact[k]).abs() <= 1e-9 * scale,
                    "{what} {body} at {x:?}: {u:?} vs {exact:?}"
                );
            }
        }
    }
}

/// The uniaxial stress σ_zz = −P through both blocks: the contact pressure is
/// P at every slave point, the displacement is linear in each block and exact.
#[test]
fn a_pressed_stack_carries_the_uniaxial_contact_pressure() {
    for (multiplier, solver) in [("", "direct"), ("multiplier = \"dual\"", "direct"), ("", "pcg")] {
        let tmp = tempfile::tempdir().unwrap();
        let what = format!("{multiplier:?} {solver}");
        contact_case(tmp.path(), |_| 0.0, multiplier, &pressed());
        let (s, report) = solve(tmp.path(), &["--solver", solver, "--rtol", "1e-13"]);
        for part in
            ["contact    1 active-set step (active points per step: 16)", "16 of 16 points active", "KKT max"]
        {
            assert!(report.contains(part), "{what}: '{part}' in:\n{report}");
        }

        let out = tmp.path().join("out");
        let interface = out.join("upper_bottom_interface.vtu");
        let (points, pressure) = field(&interface, "contact_pressure");
        assert_eq!(points.len(), SLAVE_NODES);
        for (x, p) in points.iter().zip(&pressure) {
            assert!((p - P).abs() <= 1e-8 * P, "{what}: pressure {p} at {x:?}");
        }
        assert!(field(&interface, "active").1.iter().all(|&a| a == 1.0));
        assert!(field(&interface, "gap").1.iter().all(|g| g.abs() <= 1e-12), "{what}: closed");
        assert!(field(&interface, "initial_gap").1.iter().all(|g| g.abs() <= 1e-14));
        let (_, n) = field(&interface, "normal");
        assert!(n.chunks(3).all(|n| n == [0.0, 0.0, -1.0]), "{what}: {n:?}");
        check_interface_fields(&interface);

        check_uniaxial(&out, P, 0.0, 0.0, &what);

        let c = &s["contact"];
        assert_eq!(s["multiplier"], if multiplier.is_empty() { "lumped" } else { "dual" });
        assert_eq!(c["iterations"], 1, "{what}: in contact from the start, and it stays");
        assert_eq!(c["steps"].as_array().unwrap().len(), 1);
        assert_eq!(c["steps"][0]["active"], SLAVE_NODES);
        check_steps(c);
        assert_eq!(c["active_points"], SLAVE_NODES);
        assert_eq!(c["contact_points"], SLAVE_NODES);
        assert_eq!(c["max_iterations"], 50);
        let kkt = c["kkt"]["max"].as_f64().unwrap();
        assert!(kkt <= 1e-8, "{what}: KKT {kkt}");
        for key in ["equilibrium", "pressure", "penetration", "complementarity"] {
            assert!(c["kkt"][key].as_f64().unwrap() <= kkt, "{key}");
        }
        assert_eq!(s["residual"].as_f64().unwrap(), kkt);
        // The contact force: P over the unit square, pushing the upper block up.
        let force = f64s(&c["interfaces"][0]["force"]);
        let exact = [0.0, 0.0, P];
        assert!((0..3).all(|k| (force[k] - exact[k]).abs() <= 1e-8 * P), "{what}: {force:?}");
        assert!((c["interfaces"][0]["force_magnitude"].as_f64().unwrap() - P).abs() <= 1e-8 * P);
        assert_eq!(f64s(&s["interfaces"][0]["force"]), force);
        assert_eq!(s["interfaces"][0]["constrained_nodes"], SLAVE_NODES);
        let balance: Vec<f64> = f64s(&s["bodies"][1]["applied_load"])
            .iter()
            .zip(f64s(&s["bodies"][1]["interface_force"]))
            .map(|(a, b)| a + b)
            .collect();
        assert!(balance.iter().all(|b| b.abs() <= 1e-8 * P), "{what}: {balance:?}");
        for phase in
            ["read", "assembly", "mortar", "setup", "factorization", "solve", "stresses", "output", "total"]
        {
            assert!(s["seconds"][phase].as_f64().unwrap() >= 0.0, "{phase}");
        }
    }
}

/// The upper block starts 0.01 above the lower one and its top is moved
/// down: by 0.005 the gap stays open (no pressure, nothing active, a rigid
/// motion); by 0.02 it closes and every point presses with the pressure of two
/// springs in series, 0.01 / (H/E₁ + H/E₂).
#[test]
fn a_gap_stays_open_or_closes_as_the_upper_block_moves_down() {
    for (uz, pressure, active) in [(-0.005, 0.0, 0), (-0.02, 0.01 / (H / E1 + H / E2), SLAVE_NODES)] {
        let tmp = tempfile::tempdir().unwrap();
        contact_case(tmp.path(), |_| 0.01, "", &moved(uz));
        let (s, report) = solve(tmp.path(), &[]);
        assert!(report.contains(&format!("{active} of 16 points active")), "{report}");
        let interface = tmp.path().join("out/upper_bottom_interface.vtu");
        let (_, p) = field(&interface, "contact_pressure");
        assert_eq!(p.len(), SLAVE_NODES);
        assert!(p.iter().all(|p| (p - pressure).abs() <= 1e-8 * pressure), "{p:?} vs {pressure}");
        let on = if active > 0 { 1.0 } else { 0.0 };
        assert!(field(&interface, "active").1.iter().all(|&a| a == on));
        let gap = (0.01 + uz).max(0.0);
        assert!(field(&interface, "gap").1.iter().all(|g| (g - gap).abs() <= 1e-12), "{uz}");
        assert!(field(&interface, "initial_gap").1.iter().all(|g| (g - 0.01).abs() <= 1e-12));
        check_interface_fields(&interface);
        check_uniaxial(&tmp.path().join("out"), pressure, 0.01, gap, &format!("uz = {uz}"));
        let c = &s["contact"];
        assert_eq!(c["active_points"], active);
        assert_eq!(c["contact_points"], SLAVE_NODES);
        check_steps(c);
        let force = c["interfaces"][0]["force_magnitude"].as_f64().unwrap();
        assert!((force - pressure).abs() <= 1e-8 * pressure, "{force} vs {pressure} over the unit square");
        assert!(c["kkt"]["max"].as_f64().unwrap() <= 1e-8);
    }
}

/// A wedge: the upper block's bottom rises from touching at x = 0 to 0.02
/// above at x = 1, and its top is moved down by 0.01. The contact zone grows
/// from x = 0 over several active-set steps and ends short of x = 1; the
/// solution meets the KKT conditions point by point. With one step fewer
/// allowed in `[contact]`, the active set does not settle.
#[test]
fn a_wedge_comes_into_contact_step_by_step() {
    let tmp = tempfile::tempdir().unwrap();
    contact_case(tmp.path(), |x| 0.02 * x, "", &moved(-0.01));
    let (s, _) = solve(tmp.path(), &[]);
    let c = &s["contact"];
    check_steps(c);
    let iterations = c["iterations"].as_u64().unwrap();
    assert!(iterations >= 2, "{c}");
    let active_points = c["active_points"].as_u64().unwrap() as usize;
    assert!(0 < active_points && active_points < SLAVE_NODES, "{c}");
    assert!(c["kkt"]["max"].as_f64().unwrap() <= 1e-8, "{c}");

    let interface = tmp.path().join("out/upper_bottom_interface.vtu");
    let (points, pressure) = field(&interface, "contact_pressure");
    let (_, active) = field(&interface, "active");
    let (_, gap) = field(&interface, "gap");
    assert_eq!(active.iter().filter(|&&a| a == 1.0).count(), active_points);
    for (k, x) in points.iter().enumerate() {
        if active[k] == 1.0 {
            assert!(
                pressure[k] > 0.0 && gap[k].abs() <= 1e-12,
                "active at {x:?}: {} {}",
                pressure[k],
                gap[k]
            );
        } else {
            assert!(pressure[k] == 0.0 && gap[k] > 0.0, "open at {x:?}: {} {}", pressure[k], gap[k]);
        }
        if x[0] == 0.0 {
            assert_eq!(active[k], 1.0, "touching from the start at {x:?}");
        }
        if x[0] == 1.0 {
            assert_eq!(active[k], 0.0, "0.02 away, moved by 0.01, at {x:?}");
        }
    }
    check_interface_fields(&interface);

    let text = std::fs::read_to_string(tmp.path().join("case.toml")).unwrap();
    let capped = format!("{text}\n[contact]\nmax_iterations = {}\n", iterations - 1);
    std::fs::write(tmp.path().join("case.toml"), capped).unwrap();
    let o = seam(&["solve", "case.toml", "--force"], tmp.path());
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    let settle = format!("did not settle in {} steps", iterations - 1);
    assert!(err.contains("case.toml") && err.contains(&settle), "{err}");
}

/// Case errors of contact stop with one line naming the case file, before
/// any mesh is read or any output is written.
#[test]
fn contact_input_errors_fail_with_one_line_before_any_work() {
    let tmp = tempfile::tempdir().unwrap();
    contact_case(tmp.path(), |_| 0.0, "", &pressed());
    let good = std::fs::read_to_string(tmp.path().join("case.toml")).unwrap();
    let cases = [
        (
            good.replace("kind = \"contact\"", "kind = \"contact\"\nmultiplier = \"standard\""),
            "interface 1 (upper:bottom → lower:top): contact needs multiplier \"lumped\" (the default) or \"dual\"",
        ),
        (good.clone() + "[contact]\nmax_iterations = 10\ntolerance = 1e-9\n", "unknown field `tolerance`"),
        (good.clone() + "[contact]\nmax_iterations = 0\n", "max_iterations must be at least 1"),
    ];
    assert_rejected(tmp.path(), &cases);
}

/// Without its roller on x = 0 the upper block can slide along the
/// frictionless interface: the case check passes (the lower block, which it
/// touches, is held in x), but the first active-set step is singular, and
/// seam says so in one line.
#[test]
fn a_body_free_to_slide_fails_with_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    contact_case(tmp.path(), |_| 0.0, "", &pressed());
    let text = std::fs::read_to_string(tmp.path().join("case.toml")).unwrap();
    let free = text.replace("[[dirichlet]]\nboundary = \"upper:xmin\"\nux = 0.0\n", "");
    assert_ne!(free, text);
    std::fs::write(tmp.path().join("case.toml"), free).unwrap();
    let o = seam(&["solve", "case.toml"], tmp.path());
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    for part in ["case.toml", "contact: the system is singular", "add supports"] {
        assert!(err.contains(part), "'{part}' in: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
    assert!(!tmp.path().join("out").exists(), "nothing written");
}

/// Glue and contact in one case: a third block [0,1]² × [2H, 2.8H] (2×3×2
/// hexahedra, E₂, ν₂) glued on top of the upper one (dual and standard
/// multipliers, direct and PCG solvers),
/// rollers on its x = 0 and y = 0 sides (they touch the glued interface's
/// slave side), pressed by P. Uniaxial stress throughout: the contact
/// pressure is P at every contact point, the glued traction (0, 0, P), and
/// the displacements are exact.
#[test]
fn glue_and_contact_in_one_case_carry_the_uniaxial_stress() {
    for (multiplier, solver) in
        [("dual", "direct"), ("dual", "pcg"), ("standard", "direct"), ("standard", "pcg")]
    {
        let tmp = tempfile::tempdir().unwrap();
        contact_case(tmp.path(), |_| 0.0, "", "");
        let sides = [("bottom", Side::ZMin), ("top", Side::ZMax), ("xmin", Side::XMin), ("ymin", Side::YMin)];
        write_block(&tmp.path().join("cap.msh"), [2, 3, 2], |u, v, w| [u, v, 2.0 * H + 0.8 * H * w], &sides);
        let case = std::fs::read_to_string(tmp.path().join("case.toml")).unwrap()
            + &format!(
                "\n[[body]]\nname = \"cap\"\nmesh = \"cap.msh\"\nyoung = {E2:?}\npoisson = {NU2:?}\n\n\
                 [[interface]]\nmaster = \"upper:top\"\nslave = \"cap:bottom\"\nkind = \"glue\"\nmultiplier = \"{multiplier}\"\n\n\
                 [[dirichlet]]\nboundary = \"cap:xmin\"\nux = 0.0\n\n[[dirichlet]]\nboundary = \"cap:ymin\"\nuy = 0.0\n\n\
                 [[traction]]\nboundary = \"cap:top\"\nt = [0.0, 0.0, -{P:?}]\n"
            );
        std::fs::write(tmp.path().join("case.toml"), case).unwrap();
        let (s, _) = solve(tmp.path(), &["--solver", solver, "--rtol", "1e-13"]);
        let out = tmp.path().join("out");
        let (_, pressure) = field(&out.join("upper_bottom_interface.vtu"), "contact_pressure");
        assert_eq!(pressure.len(), SLAVE_NODES);
        assert!(pressure.iter().all(|p| (p - P).abs() <= 1e-9 * P), "{solver}: {pressure:?}");
        let (points, t) = field(&out.join("cap_bottom_interface.vtu"), "traction");
        assert_eq!(points.len(), 12);
        for (x, t) in points.iter().zip(t.chunks(3)) {
            let e = [0.0, 0.0, P];
            assert!((0..3).all(|k| (t[k] - e[k]).abs() <= 1e-9 * P), "{solver}: traction {t:?} at {x:?}");
        }
        check_uniaxial(&out, P, 0.0, 0.0, solver);
        let (points, u) = vtu_field(&out.join("cap.vtu"), "displacement", false);
        for (x, u) in points.iter().zip(u.chunks(3)) {
            let exact = [NU2 * P * x[0] / E2, NU2 * P * x[1] / E2, -P * H / E1 - P * (x[2] - H) / E2];
            assert!((0..3).all(|k| (u[k] - exact[k]).abs() <= 1e-9 * P / E2), "{solver} cap at {x:?}: {u:?}");
        }
        assert_eq!(s["interfaces"].as_array().unwrap().len(), 2);
        assert_eq!(s["multiplier"], "mixed");
        assert_eq!(s["interfaces"][1]["kind"], "glue");
        assert_eq!(s["contact"]["interfaces"].as_array().unwrap().len(), 1);
        assert!(s["contact"]["kkt"]["max"].as_f64().unwrap() <= 1e-10);
        // The cap's load reaches the ground: the lower block's interface force balances P.
        let force = f64s(&s["interfaces"][1]["force"]);
        assert!((force[2] - P).abs() <= 1e-9 * P, "{solver}: glued force {force:?}");
    }
}
