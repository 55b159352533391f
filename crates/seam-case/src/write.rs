//! The other direction of [`crate::solve::read_problem`]: a [`Problem`] made
//! in memory (a scene of `seam_fem::scene`, a built-in example) written as a
//! case, one Gmsh mesh per body and a `case.toml` ([`write_problem_case`];
//! the text alone: [`case_toml`]), so that `seam solve DIR/case.toml` solves
//! it again.
//!
//! What a case file can say is less than what a [`Problem`] can: the writer
//! refuses (with an error naming the item) interfaces whose options a case
//! cannot express (facing other than opposite, an angle limit other than 45°,
//! a relative gap limit other than the default, a fixed quadrature degree),
//! standard multipliers for contact,
//! and names that are not plain (letters, digits, `-`, `_`, `.`).

use crate::output::Staged;
use crate::CaseError;
use anyhow::Result;
use seam::{Facing, MaxGap, MortarOptions, Multiplier, Named};
use seam_fem::{Amplitude, Coupling, LoadSteps, Problem, Value};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Returns a [`CaseError`] with the formatted message.
macro_rules! refuse {
    ($($arg:tt)*) => {
        return Err(CaseError::new(format!($($arg)*)))
    };
}

/// Writing into a `String` cannot fail; `writeln!(…)?` needs the conversion.
impl From<std::fmt::Error> for CaseError {
    fn from(e: std::fmt::Error) -> CaseError {
        CaseError::new(e.to_string())
    }
}

/// The case's output directory, relative to the case file.
pub const OUTPUT_DIR: &str = "out";

/// The files of `problem` written as a case in `dir`: the inputs (one
/// `<body>.msh` per body, `case.toml`) and the results of `seam solve` in
/// `dir/out` (`<body>.vtu`, `<slave body>_<surface>_interface.vtu`,
/// `summary.json`).
pub struct CaseFiles {
    /// `<body>.msh`, in body order.
    pub meshes: Vec<PathBuf>,
    /// `case.toml`.
    pub case: PathBuf,
    /// The results, as `seam solve` names them.
    pub results: Vec<PathBuf>,
}

impl CaseFiles {
    /// The files of `problem` in `dir`.
    pub fn of(problem: &Problem, dir: &Path) -> CaseFiles {
        let out = dir.join(OUTPUT_DIR);
        let mut results: Vec<PathBuf> =
            problem.bodies.iter().map(|b| out.join(format!("{}.vtu", b.name))).collect();
        for f in &problem.interfaces {
            let body = &problem.bodies[f.slave.body];
            let surface = &body.surfaces[f.slave.surface].0;
            results.push(out.join(format!("{}_{surface}_interface.vtu", body.name)));
        }
        results.push(out.join("summary.json"));
        CaseFiles {
            meshes: problem.bodies.iter().map(|b| dir.join(format!("{}.msh", b.name))).collect(),
            case: dir.join("case.toml"),
            results,
        }
    }

    /// Every file, inputs first.
    pub fn all(&self) -> impl Iterator<Item = &PathBuf> {
        self.meshes.iter().chain([&self.case]).chain(&self.results)
    }
}

/// Writes `problem` into `dir` as a case: each body's mesh as `<body>.msh`
/// (Gmsh 4.1, the body's cells as the physical volume `<body>`, its named
/// surfaces as physical surfaces) and `case.toml` (module doc), which starts
/// with the comment lines `about`. All-or-nothing; existing files are only
/// replaced with `force`. Returns the case file's path.
///
/// # Errors
/// A problem a case file cannot express (module doc), an existing file
/// without `force`, or an I/O error.
pub fn write_problem_case(problem: &Problem, dir: &Path, about: &[String], force: bool) -> Result<PathBuf> {
    let text = case_toml(problem, about)?;
    let files = CaseFiles::of(problem, dir);
    let inputs: Vec<PathBuf> = files.meshes.iter().chain([&files.case]).cloned().collect();
    let mut staged = Staged::prepare(&inputs, &[], force)?;
    for (path, body) in files.meshes.iter().zip(&problem.bodies) {
        let surfaces: Vec<(&str, &seam::SurfaceMesh)> =
            body.surfaces.iter().map(|(n, s)| (n.as_str(), s)).collect();
        staged.write(path, |p| seam_io::write_volume_msh_file(p, &body.mesh, &body.name, &surfaces))?;
    }
    staged.write(&files.case, |p| std::fs::write(p, &text))?;
    staged.commit(&[])?;
    Ok(files.case)
}

/// The ids [`write_problem_case`] gives `body`'s nodes and cells in its
/// `<body>.msh` ([`seam_io::write_volume_msh`]): node tag i+1 for point i;
/// element tags from 1, the faces of the named surfaces first, then the cells.
pub(crate) fn written_ids(body: &seam_fem::ProblemBody) -> crate::solve::BodyIds {
    let faces: usize = body.surfaces.iter().map(|(_, s)| s.n_faces()).sum();
    let tags = |from: usize, n: usize| (from as u64 + 1..=(from + n) as u64).collect();
    crate::solve::BodyIds {
        nodes: tags(0, body.mesh.points().len()),
        elements: tags(faces, body.mesh.cells().len()),
    }
}

/// Writes each (path, bytes) all-or-nothing; existing files are only
/// replaced with `force`.
///
/// # Errors
/// An existing file without `force`, or an I/O error.
pub fn write_files(files: &[(PathBuf, Vec<u8>)], force: bool) -> Result<()> {
    let paths: Vec<PathBuf> = files.iter().map(|f| f.0.clone()).collect();
    let mut staged = Staged::prepare(&paths, &[], force)?;
    for (path, bytes) in files {
        staged.write(path, |p| std::fs::write(p, bytes))?;
    }
    staged.commit(&[])
}

/// A name usable as is in a file name and in TOML quotes.
fn plain(name: &str) -> bool {
    !name.is_empty()
        && !name.starts_with('.')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
}

/// `case.toml` of `problem` (module doc), starting with the comment lines
/// `about`.
///
/// # Errors
/// A problem a case file cannot express (module doc).
pub fn case_toml(problem: &Problem, about: &[String]) -> Result<String, CaseError> {
    let mut t = String::new();
    for line in about {
        writeln!(t, "# {line}")?;
    }
    writeln!(t, "# Rerun with: seam solve case.toml --force\n")?;
    let role = |b: usize| {
        if problem.interfaces.iter().any(|f| f.master.body == b) {
            "master side"
        } else if problem.interfaces.iter().any(|f| f.slave.body == b) {
            "slave side"
        } else {
            ""
        }
    };
    for (b, body) in problem.bodies.iter().enumerate() {
        for name in [&body.name].into_iter().chain(body.surfaces.iter().map(|s| &s.0)) {
            if !plain(name) {
                refuse!(
                    "body \"{}\": the name \"{name}\" is not plain (letters, digits, -, _, .)",
                    body.name
                );
            }
        }
        writeln!(t, "{}", commented("[[body]]", role(b)))?;
        writeln!(t, "name = \"{}\"\nmesh = \"{}.msh\"", body.name, body.name)?;
        writeln!(t, "young = {:?}\npoisson = {:?}", body.material.young(), body.material.poisson())?;
        if body.law != seam_fem::Law::Linear {
            writeln!(t, "material = \"{}\"", body.law.name())?;
        }
        if body.body_force != [0.0; 3] {
            writeln!(t, "body_force = {}", array(body.body_force))?;
        }
        amplitude(&mut t, "body_force_amplitude", &body.body_force_amplitude)?;
        writeln!(t)?;
    }
    for (i, f) in problem.interfaces.iter().enumerate() {
        let kind = match f.kind {
            Coupling::Glue => "glue",
            Coupling::Contact => "contact",
        };
        let what = format!(
            "interface {} ({} → {})",
            i + 1,
            problem.surface_name(f.slave),
            problem.surface_name(f.master)
        );
        let multiplier =
            multiplier(&f.options, kind == "contact").map_err(|e| CaseError::new(format!("{what}: {e}")))?;
        writeln!(t, "[[interface]]")?;
        writeln!(
            t,
            "master = \"{}\"\nslave = \"{}\"",
            problem.surface_name(f.master),
            problem.surface_name(f.slave)
        )?;
        writeln!(t, "kind = \"{kind}\"\nmultiplier = \"{multiplier}\"")?;
        if f.friction > 0.0 {
            writeln!(t, "friction = {:?}", f.friction)?;
        }
        match f.options.max_gap {
            MaxGap::Absolute(g) => writeln!(t, "max_gap = {g:?}")?,
            g if g == MaxGap::DEFAULT => {}
            g => {
                refuse!("{what}: the gap limit {g:?} is not expressible in a case (a length or the default)")
            }
        }
        writeln!(t)?;
    }
    if problem.steps != LoadSteps::default() {
        let times: Vec<String> = problem.steps.times().iter().map(|t| format!("{t:?}")).collect();
        writeln!(t, "[load]\ntimes = [{}]\n", times.join(", "))?;
    }
    for s in &problem.supports {
        let clamped = s.values.iter().all(|v| v.as_ref().and_then(Value::number) == Some(0.0));
        writeln!(t, "{}", commented("[[dirichlet]]", if clamped { "clamped" } else { "" }))?;
        writeln!(t, "boundary = \"{}\"", problem.surface_name(s.boundary))?;
        for (name, value) in ["ux", "uy", "uz"].iter().zip(&s.values) {
            if let Some(v) = value {
                writeln!(t, "{name} = {}", scalar(v))?;
            }
        }
        amplitude(&mut t, "amplitude", &s.amplitude)?;
        writeln!(t)?;
    }
    for l in &problem.loads {
        let [x, y, z] = l.t.each_ref().map(scalar);
        writeln!(
            t,
            "[[traction]]\nboundary = \"{}\"\nt = [{x}, {y}, {z}]",
            problem.surface_name(l.boundary)
        )?;
        amplitude(&mut t, "amplitude", &l.amplitude)?;
        writeln!(t)?;
    }
    writeln!(t, "[output]\ndir = \"{OUTPUT_DIR}\"")?;
    Ok(t)
}

/// A table header with a comment in column 19, or alone.
fn commented(header: &str, comment: &str) -> String {
    if comment.is_empty() {
        header.to_string()
    } else {
        format!("{header:<17} # {comment}")
    }
}

/// A value as TOML: a number in Rust's shortest round-trip form, an
/// expression as a string.
fn scalar(v: &Value) -> String {
    match v {
        Value::Number(v) => format!("{v:?}"),
        Value::Function(text, _) => toml::Value::String(text.clone()).to_string(),
    }
}

/// `key = [[t, a], …]` unless `a` is the default ramp.
fn amplitude(t: &mut String, key: &str, a: &Amplitude) -> Result<(), CaseError> {
    if !a.is_ramp() {
        let entries: Vec<String> = a.table().iter().map(|[t, a]| format!("[{t:?}, {a:?}]")).collect();
        writeln!(t, "{key} = [{}]", entries.join(", "))?;
    }
    Ok(())
}

/// "[x, y, z]" in Rust's shortest round-trip form.
fn array(v: [f64; 3]) -> String {
    format!("[{:?}, {:?}, {:?}]", v[0], v[1], v[2])
}

/// The case file's multiplier of an interface with `options`, after checking
/// that the rest of the options is what a case gives.
fn multiplier(options: &MortarOptions, contact: bool) -> Result<&'static str, CaseError> {
    if options.facing != Facing::Opposite {
        refuse!("a case pairs faces facing each other only (facing {:?})", options.facing);
    }
    if options.max_angle_degrees != MortarOptions::default().max_angle_degrees {
        refuse!("a case keeps the angle limit at 45° (not {}°)", options.max_angle_degrees);
    }
    if options.warped_quad_degree.is_some() {
        refuse!("a case chooses the quadrature degree of warped quads itself");
    }
    if contact && options.multiplier == Multiplier::Standard {
        refuse!("contact needs lumped or dual multipliers");
    }
    Ok(options.multiplier.name())
}

#[cfg(test)]
mod tests {
    use super::*;
    use seam_fem::scene::{
        bulging_contact, hertz, ironing, warped_glue, BulgingContact, Hertz, Ironing, WarpedGlue,
    };

    #[test]
    fn the_glue_scene_gives_the_case_of_the_warped_glue_example() {
        let problem = warped_glue(&WarpedGlue { slave_cells: 2, ratio: 1, ..WarpedGlue::default() }).unwrap();
        let text = case_toml(&problem, &["a comment".into()]).unwrap();
        assert!(text.starts_with(
            "# a comment\n# Rerun with: seam solve case.toml --force\n\n[[body]]          # master side\n"
        ));
        for part in [
            "name = \"lower\"\nmesh = \"lower.msh\"\nyoung = 1000.0\npoisson = 0.3\n",
            "[[interface]]\nmaster = \"lower:top\"\nslave = \"upper:bottom\"\nkind = \"glue\"\nmultiplier = \"standard\"\n\n",
            "[[dirichlet]]     # clamped\nboundary = \"lower:bottom\"\nux = 0.0\nuy = 0.0\nuz = 0.0\n",
            "[[traction]]\nboundary = \"upper:top\"\nt = [0.2, 0.0, -1.0]\n",
        ] {
            assert!(text.contains(part), "{part} in\n{text}");
        }
        let case: toml::Table = text.parse().unwrap();
        assert_eq!(case["body"].as_array().unwrap().len(), 2);
    }

    #[test]
    fn contact_scenes_keep_their_gap_limits_rollers_and_loads() {
        let p =
            bulging_contact(&BulgingContact { cells: 2, layers: 1, ..BulgingContact::default() }).unwrap();
        let text = case_toml(&p, &[]).unwrap();
        assert!(text.contains("kind = \"contact\"\nmultiplier = \"lumped\"\nmax_gap = 0.5\n"), "{text}");
        assert!(text.contains("boundary = \"upper:top\"\nux = 0.02\nuy = -0.01\nuz = -0.08\n"), "{text}");
        let h = Hertz { fine_cells: 2, ..Hertz::default() };
        let text = case_toml(&hertz(&h).unwrap(), &[]).unwrap();
        assert!(text.contains("[[dirichlet]]\nboundary = \"indenter:x0\"\nux = 0.0\n\n"), "{text}");
        assert!(text.contains("boundary = \"block:y0\"\nuy = 0.0\n\n"), "{text}");
        let case: toml::Table = text.parse().unwrap();
        let t = case["traction"][0]["t"].as_array().unwrap()[2].as_float().unwrap();
        assert_eq!(-t, h.force() / (4.0 * 0.5 * 0.5), "the traction round-trips");
        // Hyperelastic bodies keep their law, friction its μ.
        let p =
            ironing(&Ironing { cells: 2, indenter_cells: 2, friction: 0.3, ..Ironing::default() }).unwrap();
        let text = case_toml(&p, &[]).unwrap();
        let case: toml::Table = text.parse().unwrap();
        for body in case["body"].as_array().unwrap() {
            assert_eq!(body["material"].as_str(), Some("neo-hookean"), "{text}");
        }
        assert_eq!(case["interface"][0]["friction"].as_float(), Some(0.3), "{text}");
    }

    #[test]
    fn what_a_case_cannot_say_is_refused() {
        let mut p = warped_glue(&WarpedGlue { slave_cells: 2, ratio: 1, ..WarpedGlue::default() }).unwrap();
        p.interfaces[0].options.facing = Facing::Any;
        assert!(case_toml(&p, &[]).unwrap_err().to_string().contains("facing"));
        p.interfaces[0].options.facing = Facing::Opposite;
        p.interfaces[0].options.max_gap = MaxGap::Relative(0.1);
        assert!(case_toml(&p, &[])
            .unwrap_err()
            .to_string()
            .contains("interface 1 (upper:bottom → lower:top)"));
        p.interfaces[0].options.max_gap = MaxGap::DEFAULT;
        p.bodies[0].name = "lo wer".into();
        assert!(case_toml(&p, &[]).unwrap_err().to_string().contains("not plain"));
        p.bodies[0].name = "lower".into();
        p.interfaces[0].kind = Coupling::Contact;
        p.interfaces[0].options.multiplier = Multiplier::Standard;
        assert!(case_toml(&p, &[]).unwrap_err().to_string().contains("contact"));
    }
}
