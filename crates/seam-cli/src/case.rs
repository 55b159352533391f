//! Case files of `seam solve CASE.toml`: several linear-elastic bodies, glued
//! or in frictionless contact through interfaces, with Dirichlet conditions and
//! tractions on named boundaries.
//!
//! ```toml
//! [[body]]              # one per body
//! name = "lower"        # also the name of its output file, lower.vtu
//! mesh = "lower.msh"    # Gmsh volume mesh; its physical surfaces name the boundaries
//! volume = "steel"      # optional: the cells of this physical volume (default: all cells)
//! young = 1.0e3
//! poisson = 0.3
//! body_force = [0.0, 0.0, 0.0]   # optional, force per volume
//!
//! [[interface]]         # surfaces are named "body:physical-surface"
//! master = "lower:top"
//! slave = "upper:bottom"
//! kind = "glue"                  # or "contact" (frictionless, no penetration)
//! multiplier = "standard"        # or "dual", "lumped"; default "standard" for glue,
//!                                # "lumped" for contact (which takes "lumped" or "dual")
//! max_gap = 0.01                 # optional (default: half the diameter of each slave face);
//!                                # for contact, slave points farther from the master than
//!                                # this are never checked for contact
//!
//! [contact]             # optional: the active-set method of contact cases
//! max_iterations = 50   # the default: the most active-set steps before giving up
//!
//! [[dirichlet]]         # any subset of ux, uy, uz
//! boundary = "lower:bottom"
//! uz = 0.0
//!
//! [[traction]]
//! boundary = "upper:top"
//! t = [0.0, 0.0, -1.0]
//!
//! [output]              # optional
//! dir = "out"           # the default
//! ```
//!
//! The interfaces of a case are all glue or all contact (mixing them is not
//! supported yet). Everything that can be checked without solving is checked by
//! [`Case::read`], before any heavy work: names, references, material ranges,
//! multipliers, and that every body is held by a Dirichlet condition, directly or
//! through its interfaces (glued or in contact: a body held only by contact is
//! legitimate, e.g. a loaded indenter; if nothing presses it on, the contact
//! solve reports a singular step).

use anyhow::{anyhow, bail, Context, Result};
use serde::Deserialize;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A case file, as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Case {
    #[serde(rename = "body")]
    pub bodies: Vec<Body>,
    #[serde(rename = "interface", default)]
    pub interfaces: Vec<Interface>,
    #[serde(default)]
    pub dirichlet: Vec<Dirichlet>,
    #[serde(default)]
    pub traction: Vec<Traction>,
    #[serde(default)]
    pub output: Output,
    /// Settings of the contact solve (used when the case has contact interfaces).
    #[serde(default)]
    pub contact: ContactSettings,
    /// The directory of the case file: meshes and outputs are relative to it.
    #[serde(skip)]
    pub base: PathBuf,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Body {
    pub name: String,
    pub mesh: PathBuf,
    /// The physical volume (name or number) whose cells make the body.
    pub volume: Option<String>,
    pub young: f64,
    pub poisson: f64,
    #[serde(default)]
    pub body_force: [f64; 3],
}

#[derive(Debug, Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum InterfaceKind {
    Glue,
    Contact,
}

#[derive(Debug, Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum CaseMultiplier {
    Standard,
    Dual,
    Lumped,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Interface {
    pub master: String,
    pub slave: String,
    pub kind: InterfaceKind,
    /// As written; [`Interface::multiplier`] applies the default of the kind.
    #[serde(rename = "multiplier")]
    pub multiplier_given: Option<CaseMultiplier>,
    /// Largest normal distance between paired points (default: half a slave face).
    pub max_gap: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dirichlet {
    pub boundary: String,
    pub ux: Option<f64>,
    pub uy: Option<f64>,
    pub uz: Option<f64>,
}

impl Dirichlet {
    /// The prescribed components as (component, value).
    pub fn components(&self) -> Vec<(usize, f64)> {
        [self.ux, self.uy, self.uz].iter().enumerate().filter_map(|(k, v)| v.map(|v| (k, v))).collect()
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Traction {
    pub boundary: String,
    pub t: [f64; 3],
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    #[serde(default = "default_output_dir")]
    pub dir: PathBuf,
}

fn default_output_dir() -> PathBuf {
    PathBuf::from("out")
}

impl Default for Output {
    fn default() -> Self {
        Output { dir: default_output_dir() }
    }
}

/// The `[contact]` table.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSettings {
    /// The most active-set steps.
    #[serde(default = "default_max_iterations")]
    pub max_iterations: usize,
}

fn default_max_iterations() -> usize {
    seam_fem::contact::ContactOptions::default().max_iterations
}

impl Default for ContactSettings {
    fn default() -> Self {
        ContactSettings { max_iterations: default_max_iterations() }
    }
}

impl Interface {
    /// The interface's name in messages: "slave → master".
    pub fn describe(&self, index: usize) -> String {
        format!("interface {} ({} → {})", index + 1, self.slave, self.master)
    }

    /// The multiplier: as written, else "standard" for glue and "lumped" for contact.
    pub fn multiplier(&self) -> CaseMultiplier {
        self.multiplier_given.unwrap_or(match self.kind {
            InterfaceKind::Glue => CaseMultiplier::Standard,
            InterfaceKind::Contact => CaseMultiplier::Lumped,
        })
    }
}

/// A boundary reference "body:surface", split.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SurfaceRef {
    pub body: String,
    pub surface: String,
}

impl SurfaceRef {
    pub fn parse(text: &str, context: &str) -> Result<SurfaceRef> {
        match text.split_once(':') {
            Some((b, s)) if !b.trim().is_empty() && !s.trim().is_empty() => {
                Ok(SurfaceRef { body: b.trim().to_string(), surface: s.trim().to_string() })
            }
            _ => bail!("{context}: \"{text}\" is not of the form \"body:surface\""),
        }
    }
}

impl Case {
    /// Reads and checks a case file (see the module doc).
    pub fn read(path: &Path) -> Result<Case> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
        let mut case: Case = toml::from_str(&text)
            .map_err(|e| anyhow!("{}: {}", path.display(), e.to_string().trim().replace('\n', " ")))?;
        case.base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        case.check().map_err(|e| anyhow!("{}: {e:#}", path.display()))?;
        Ok(case)
    }

    /// Whether the interfaces are contact interfaces (a case does not mix kinds).
    pub fn is_contact(&self) -> bool {
        self.interfaces.iter().any(|f| f.kind == InterfaceKind::Contact)
    }

    /// A path of the case (relative to the case file's directory).
    pub fn resolve(&self, p: &Path) -> PathBuf {
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.base.join(p)
        }
    }

    fn check(&self) -> Result<()> {
        if self.bodies.is_empty() {
            bail!("no [[body]]");
        }
        let mut names = BTreeSet::new();
        for b in &self.bodies {
            if !names.insert(b.name.as_str()) {
                bail!("body \"{}\" is defined twice", b.name);
            }
            if b.name.is_empty() || b.name.contains([':', '/', '\\']) || b.name.starts_with('.') {
                bail!(
                    "body name \"{}\" must be non-empty, not start with '.' and hold no ':', '/' or '\\' \
                     (it names the output file)",
                    b.name
                );
            }
            if !(b.young.is_finite() && b.young > 0.0) {
                bail!("body \"{}\": young = {} must be positive", b.name, b.young);
            }
            if !(b.poisson > -1.0 && b.poisson < 0.5) {
                bail!("body \"{}\": poisson = {} must lie in (-1, 0.5)", b.name, b.poisson);
            }
            if b.body_force.iter().any(|v| !v.is_finite()) {
                bail!("body \"{}\": body_force must be finite", b.name);
            }
            let mesh = self.resolve(&b.mesh);
            if !mesh.is_file() {
                bail!("body \"{}\": mesh {} does not exist", b.name, mesh.display());
            }
        }
        let known = |r: &SurfaceRef, what: &str| -> Result<()> {
            if names.contains(r.body.as_str()) {
                Ok(())
            } else {
                bail!(
                    "{what}: no body named \"{}\" (bodies: {})",
                    r.body,
                    names.iter().cloned().collect::<Vec<_>>().join(", ")
                )
            }
        };
        let mut slaves = BTreeMap::new();
        for (i, f) in self.interfaces.iter().enumerate() {
            let what = format!("interface {}", i + 1);
            let (m, s) = (SurfaceRef::parse(&f.master, &what)?, SurfaceRef::parse(&f.slave, &what)?);
            known(&m, &what)?;
            known(&s, &what)?;
            if m.body == s.body {
                bail!("{what}: master and slave belong to the same body \"{}\"", m.body);
            }
            if let Some(j) = slaves.insert((s.body.clone(), s.surface.clone()), i) {
                bail!("{what}: {} is already the slave side of interface {}", f.slave, j + 1);
            }
            if f.kind == InterfaceKind::Contact && f.multiplier() == CaseMultiplier::Standard {
                bail!("{}: contact needs multiplier \"lumped\" (the default) or \"dual\"", f.describe(i));
            }
            if let Some(g) = f.max_gap {
                if !(g.is_finite() && g >= 0.0) {
                    bail!("{what}: max_gap = {g} must be a non-negative length");
                }
            }
        }
        if self.is_contact() && self.interfaces.iter().any(|f| f.kind == InterfaceKind::Glue) {
            bail!("glued and contact interfaces in one case are not supported yet");
        }
        if self.contact.max_iterations == 0 {
            bail!("[contact]: max_iterations must be at least 1");
        }
        for (i, d) in self.dirichlet.iter().enumerate() {
            let what = format!("dirichlet {}", i + 1);
            known(&SurfaceRef::parse(&d.boundary, &what)?, &what)?;
            if d.components().is_empty() {
                bail!("{what}: give at least one of ux, uy, uz");
            }
            if d.components().iter().any(|(_, v)| !v.is_finite()) {
                bail!("{what}: values must be finite");
            }
        }
        for (i, t) in self.traction.iter().enumerate() {
            let what = format!("traction {}", i + 1);
            known(&SurfaceRef::parse(&t.boundary, &what)?, &what)?;
            if t.t.iter().any(|v| !v.is_finite()) {
                bail!("{what}: t must be finite");
            }
        }
        self.check_held()
    }

    /// Every body must be held against rigid motion: some body of its group
    /// (bodies connected by interfaces, glued or in contact) needs a Dirichlet
    /// condition on each of the three components (a necessary condition; the
    /// factorisation detects the rest, for contact in each active-set step).
    fn check_held(&self) -> Result<()> {
        let index: BTreeMap<&str, usize> =
            self.bodies.iter().enumerate().map(|(i, b)| (b.name.as_str(), i)).collect();
        let mut group: Vec<usize> = (0..self.bodies.len()).collect();
        fn root(g: &mut [usize], mut i: usize) -> usize {
            while g[i] != i {
                g[i] = g[g[i]];
                i = g[i];
            }
            i
        }
        for f in &self.interfaces {
            let (m, s) = (SurfaceRef::parse(&f.master, "")?, SurfaceRef::parse(&f.slave, "")?);
            let (a, b) = (root(&mut group, index[m.body.as_str()]), root(&mut group, index[s.body.as_str()]));
            group[a] = b;
        }
        let mut held = vec![[false; 3]; self.bodies.len()];
        for d in &self.dirichlet {
            let r = root(&mut group, index[SurfaceRef::parse(&d.boundary, "")?.body.as_str()]);
            for (k, _) in d.components() {
                held[r][k] = true;
            }
        }
        let neighbour = if self.is_contact() { "in contact with it" } else { "glued to it" };
        for (i, b) in self.bodies.iter().enumerate() {
            let r = root(&mut group, i);
            if let Some(k) = (0..3).find(|&k| !held[r][k]) {
                bail!(
                    "body \"{}\" can move freely along {} (no Dirichlet condition on {} in it or in a body {neighbour}): \
                     the problem is singular",
                    b.name,
                    ["x", "y", "z"][k],
                    ["ux", "uy", "uz"][k]
                );
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(dir: &Path, text: &str) -> Result<Case> {
        std::fs::write(dir.join("a.msh"), "").unwrap();
        std::fs::write(dir.join("b.msh"), "").unwrap();
        let path = dir.join("case.toml");
        std::fs::write(&path, text).unwrap();
        Case::read(&path)
    }

    const GOOD: &str = r#"
[[body]]
name = "lower"
mesh = "a.msh"
young = 1.0e3
poisson = 0.3

[[body]]
name = "upper"
mesh = "b.msh"
young = 2.0e3
poisson = 0.25

[[interface]]
master = "lower:top"
slave = "upper:bottom"
kind = "glue"
multiplier = "dual"

[[dirichlet]]
boundary = "lower:bottom"
ux = 0.0
uy = 0.0
uz = 0.0

[[traction]]
boundary = "upper:top"
t = [0.0, 0.0, -1.0]

[output]
dir = "out"
"#;

    #[test]
    fn a_good_case_reads() {
        let tmp = tempfile::tempdir().unwrap();
        let c = case(tmp.path(), GOOD).unwrap();
        assert_eq!(c.bodies.len(), 2);
        assert_eq!(c.interfaces[0].multiplier(), CaseMultiplier::Dual);
        assert!(!c.is_contact());
        assert_eq!(c.contact.max_iterations, 50);
        assert_eq!(c.dirichlet[0].components(), vec![(0, 0.0), (1, 0.0), (2, 0.0)]);
        assert_eq!(c.resolve(Path::new("a.msh")), tmp.path().join("a.msh"));
    }

    #[test]
    fn input_errors_are_named_before_any_work() {
        let tmp = tempfile::tempdir().unwrap();
        let cases = [
            (GOOD.replace("young = 2.0e3", "young = -1.0"), "young = -1 must be positive"),
            (GOOD.replace("poisson = 0.25", "poisson = 0.5"), "poisson = 0.5 must lie in (-1, 0.5)"),
            (GOOD.replace("b.msh", "missing.msh"), "missing.msh does not exist"),
            (GOOD.replace("slave = \"upper:bottom\"", "slave = \"middle:bottom\""), "no body named \"middle\""),
            (GOOD.replace("boundary = \"upper:top\"", "boundary = \"upper\""), "is not of the form \"body:surface\""),
            (GOOD.replace("[[interface]]\nmaster = \"lower:top\"\nslave = \"upper:bottom\"\nkind = \"glue\"\nmultiplier = \"dual\"\n", ""), "body \"upper\" can move freely along x"),
            (GOOD.replace("uz = 0.0", ""), "can move freely along z"),
            (GOOD.replace("kind = \"glue\"", "kind = \"weld\""), "unknown variant `weld`"),
            (GOOD.replace("young = 1.0e3", "youngs = 1.0e3"), "unknown field `youngs`"),
            (GOOD.replace("name = \"upper\"", "name = \"lower\""), "body \"lower\" is defined twice"),
            (
                GOOD.replace("kind = \"glue\"\nmultiplier = \"dual\"", "kind = \"contact\"\nmultiplier = \"standard\""),
                "interface 1 (upper:bottom → lower:top): contact needs multiplier \"lumped\" (the default) or \"dual\"",
            ),
            (
                GOOD.replace("kind = \"glue\"", "kind = \"contact\"").replace(
                    "[output]",
                    "[[interface]]\nmaster = \"lower:side\"\nslave = \"upper:side\"\nkind = \"glue\"\n\n[output]",
                ),
                "glued and contact interfaces in one case are not supported yet",
            ),
            (GOOD.replace("[output]", "[contact]\nmax_iteration = 5\n\n[output]"), "unknown field `max_iteration`"),
            (GOOD.replace("[output]", "[contact]\nmax_iterations = 0\n\n[output]"), "max_iterations must be at least 1"),
            (
                GOOD.replace("kind = \"glue\"", "kind = \"contact\"").replace("ux = 0.0\n", ""),
                "(no Dirichlet condition on ux in it or in a body in contact with it)",
            ),
        ];
        for (text, message) in cases {
            let err = format!("{:#}", case(tmp.path(), &text).unwrap_err());
            assert!(err.contains(message), "expected '{message}' in: {err}");
            assert!(err.contains("case.toml"), "the error names the file: {err}");
        }
    }

    #[test]
    fn contact_defaults_to_lumped_and_reads_its_table() {
        let tmp = tempfile::tempdir().unwrap();
        let text = GOOD
            .replace("kind = \"glue\"\nmultiplier = \"dual\"", "kind = \"contact\"")
            .replace("[output]", "[contact]\nmax_iterations = 7\n\n[output]");
        // The upper body has no Dirichlet condition: it is held through the contact.
        let c = case(tmp.path(), &text).unwrap();
        assert!(c.is_contact());
        assert_eq!(c.interfaces[0].multiplier(), CaseMultiplier::Lumped);
        assert_eq!(c.contact.max_iterations, 7);
        // Glue keeps its default.
        let c = case(tmp.path(), &GOOD.replace("multiplier = \"dual\"\n", "")).unwrap();
        assert_eq!(c.interfaces[0].multiplier(), CaseMultiplier::Standard);
    }
}
