//! Case files of `seam solve CASE.toml`: several linear-elastic bodies, glued
//! or in frictionless contact through interfaces, with Dirichlet conditions and
//! tractions on named boundaries (the schema is in the README).
//!
//! ```toml
//! [[body]]              # one per body
//! name = "lower"        # also the name of its output file, lower.vtu
//! mesh = "lower.msh"    # Gmsh volume mesh (or Abaqus/CalculiX "lower.inp", Exodus II "lower.exo");
//!                       # its physical surfaces (*SURFACE of an .inp, side sets) name the boundaries
//! # format = "abaqus"   # optional: "gmsh", "abaqus" or "exodus" (default: by extension, .inp is
//!                       # abaqus, .e/.exo/.ex2/.g exodus)
//! volume = "steel"      # optional: the cells of this physical volume (*ELSET, element block name
//!                       # or id; default: all cells)
//! young = 1.0e3
//! poisson = 0.3
//! material = "linear"   # or "neo-hookean", "saint-venant-kirchhoff" (finite deformation)
//! body_force = [0.0, 0.0, 0.0]   # optional, force per volume
//! # body_force_amplitude = [[0.0, 0.0], [1.0, 1.0]]   # its factor over t (default)
//!
//! [[interface]]         # surfaces are named "body:physical-surface"
//! master = "lower:top"
//! slave = "upper:bottom"
//! kind = "glue"                  # or "contact" (frictionless, no penetration)
//! multiplier = "standard"        # or "dual", "lumped"; default "standard" for glue,
//!                                # "lumped" for contact (which takes "lumped" or "dual"),
//!                                # "dual" for contact on a slave surface with second-order
//!                                # faces (Tri6, Quad8, Quad9; lumped is refused on Tri6, Quad8)
//! max_gap = 0.01                 # optional (default: half the diameter of each slave face)
//!
//! [contact]             # optional: the active-set method of contact cases
//! max_iterations = 50   # the default: the most active-set steps before giving up
//!
//! [newton]              # optional: hyperelastic bodies' Newton iteration
//! rtol = 1e-10          # the default
//! max_iterations = 25   # the default
//!
//! [load]                # optional: pseudo-time t from 0 to 1 in load steps
//! steps = 1             # the default: equal increments, t_k = k / steps
//! # times = [0.5, 0.75, 1.0]   # or increasing times in (0, 1], the last one 1.0
//!
//! [[dirichlet]]         # any subset of ux, uy, uz; a boundary may have several
//! boundary = "lower:bottom"
//! uz = 0.0              # a number, or an expression in x, y, z and t: "1e-3*z*t"
//! # amplitude = [[0.0, 0.0], [1.0, 1.0]]   # factor over t, piecewise linear (default)
//!
//! [[traction]]
//! boundary = "upper:top"
//! t = [0.0, 0.0, -1.0]  # numbers or expressions: ["0", "0", "-x*y"]
//! # amplitude = [[0.0, 0.0], [0.5, 1.0], [1.0, 1.0]]
//!
//! [output]              # optional
//! dir = "out"           # the default
//! ```
//!
//! [`Case::read`] checks everything that can be checked without reading the
//! meshes, before any heavy work: names and references, materials (through
//! [`seam_fem::Material::new`]: ranges and locking), multipliers, the coupling
//! graph, that every body is held against rigid motion, and that each mesh is a
//! regular file. [`Case::from_toml`] does the same without the file system.
//!
//! # The coupling graph
//!
//! Interfaces are directed edges slave body → master body: the slave side is
//! constrained by the master side. The graph must not couple the same two
//! surfaces twice (in either direction: the constraints would be counted twice)
//! and must have no directed cycle (a body constrained, through a chain of
//! interfaces, by itself: the elimination u_s = T u_m has no order, and
//! A → B with B → A over one interface doubles its constraints). Every acyclic
//! orientation is allowed, so a refused case always has a valid one: swap
//! master and slave of an interface of the cycle.

use seam::Multiplier;
use serde::Deserialize;
use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::path::{Path, PathBuf};

/// A case file that cannot be used: one line naming the file (when read from
/// one) and the item at fault.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CaseError {
    path: Option<PathBuf>,
    message: String,
}

impl CaseError {
    pub(crate) fn new(message: impl Into<String>) -> CaseError {
        CaseError { path: None, message: message.into() }
    }

    /// The same error, attributed to the case file at `path`.
    #[must_use]
    pub fn with_path(mut self, path: impl AsRef<Path>) -> CaseError {
        self.path = Some(path.as_ref().to_path_buf());
        self
    }

    /// The case file, when the error came from one.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// What is wrong, without the file name.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for CaseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.path {
            Some(path) => write!(f, "{}: {}", path.display(), self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for CaseError {}

/// Fails with `message`.
fn fail<T>(message: impl Into<String>) -> Result<T, CaseError> {
    Err(CaseError::new(message))
}

/// A case file, as written (after [`Case::read`] or [`Case::from_toml`]: checked).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Case {
    /// The `[[body]]` tables.
    #[serde(rename = "body")]
    pub bodies: Vec<Body>,
    /// The `[[interface]]` tables.
    #[serde(rename = "interface", default)]
    pub interfaces: Vec<Interface>,
    /// The `[[dirichlet]]` tables.
    #[serde(default)]
    pub dirichlet: Vec<Dirichlet>,
    /// The `[[traction]]` tables.
    #[serde(default)]
    pub traction: Vec<Traction>,
    /// The `[output]` table.
    #[serde(default)]
    pub output: Output,
    /// Settings of the contact solve (used when the case has contact interfaces).
    #[serde(default)]
    pub contact: ContactSettings,
    /// The `[load]` table: the load steps.
    #[serde(default)]
    pub load: LoadTable,
    /// The `[newton]` table: finite deformation's Newton iteration.
    #[serde(default)]
    pub newton: NewtonSettings,
    /// The directory of the case file: meshes and outputs are relative to it.
    #[serde(skip)]
    pub base: PathBuf,
}

/// A `[[body]]` table.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// Its name: unique, and the name of its output file.
    pub name: String,
    /// Its volume mesh, relative to the case file's directory: a Gmsh MSH
    /// file, an Abaqus / CalculiX input file (`.inp`) or an Exodus II file
    /// (`.e`, `.exo`, `.ex2`, `.g`), or
    /// any name with `format`.
    pub mesh: PathBuf,
    /// The mesh's format, one of [`seam_io::ModelFormat::NAMES`] (default:
    /// by the extension, [`seam_io::ModelFormat::of_path`]).
    pub format: Option<String>,
    /// The physical volume (name or number; an `.inp` file's element set, an Exodus block)
    /// whose cells make the body.
    pub volume: Option<String>,
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// The law: "linear" (small strain, the default), "neo-hookean" or
    /// "saint-venant-kirchhoff" (finite deformation).
    #[serde(default)]
    pub material: MaterialLaw,
    /// Force per volume.
    #[serde(default)]
    pub body_force: [f64; 3],
    /// The body force's factor over pseudo-time (default: the ramp).
    pub body_force_amplitude: Option<Vec<[f64; 2]>>,
}

impl Body {
    /// The format its mesh is read as: `format`, else by the extension
    /// (`.inp`: Abaqus, `.e`/`.exo`/`.ex2`/`.g`: Exodus; [`seam_io::read_model_file`]).
    pub fn model_format(&self) -> seam_io::ModelFormat {
        self.format
            .as_deref()
            .and_then(seam_io::ModelFormat::from_name)
            .unwrap_or_else(|| seam_io::ModelFormat::of_path(&self.mesh))
    }
}

/// A body's `material`: its constitutive law.
#[derive(Debug, Deserialize, Clone, Copy, Default, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum MaterialLaw {
    /// Linear elasticity, small strain.
    #[default]
    Linear,
    /// Compressible neo-Hookean, finite deformation.
    NeoHookean,
    /// Saint Venant–Kirchhoff, finite deformation.
    SaintVenantKirchhoff,
}

impl MaterialLaw {
    /// The solver's law.
    pub fn law(self) -> seam_fem::Law {
        match self {
            MaterialLaw::Linear => seam_fem::Law::Linear,
            MaterialLaw::NeoHookean => seam_fem::Law::NeoHookean,
            MaterialLaw::SaintVenantKirchhoff => seam_fem::Law::SaintVenantKirchhoff,
        }
    }
}

/// How an interface couples its two surfaces.
#[derive(Debug, Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum InterfaceKind {
    /// u_slave = T u_master in the mortar sense.
    Glue,
    /// Frictionless contact: the normal direction only, in compression only.
    Contact,
}

/// An `[[interface]]` table.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Interface {
    /// The master surface, "body:surface".
    pub master: String,
    /// The slave surface, "body:surface", where the multiplier lives.
    pub slave: String,
    /// Glue or contact.
    pub kind: InterfaceKind,
    /// As written; [`Interface::multiplier`] applies the default of the kind.
    #[serde(rename = "multiplier")]
    pub multiplier_given: Option<Multiplier>,
    /// Largest normal distance between paired points (default: half a slave face).
    pub max_gap: Option<f64>,
    /// Contact: the Coulomb friction coefficient μ ≥ 0 (default 0, frictionless).
    pub friction: Option<f64>,
}

/// A `[[dirichlet]]` table: prescribed displacement components on a boundary.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dirichlet {
    /// The boundary, "body:surface".
    pub boundary: String,
    /// Prescribed u_x.
    pub ux: Option<Scalar>,
    /// Prescribed u_y.
    pub uy: Option<Scalar>,
    /// Prescribed u_z.
    pub uz: Option<Scalar>,
    /// The factor over pseudo-time (default: the ramp).
    pub amplitude: Option<Vec<[f64; 2]>>,
}

impl Dirichlet {
    /// The prescribed components as (component, value).
    pub fn components(&self) -> Vec<(usize, &Scalar)> {
        [&self.ux, &self.uy, &self.uz]
            .into_iter()
            .enumerate()
            .filter_map(|(k, v)| Some((k, v.as_ref()?)))
            .collect()
    }
}

/// A `[[traction]]` table: a force per area on a boundary.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Traction {
    /// The boundary, "body:surface".
    pub boundary: String,
    /// The traction vector's components.
    pub t: [Scalar; 3],
    /// The factor over pseudo-time (default: the ramp).
    pub amplitude: Option<Vec<[f64; 2]>>,
}

/// A prescribed value in a case: a number, or an expression in x, y, z
/// (reference coordinates) and the pseudo-time t, in the language of
/// `seam transfer --expr` ([`crate::Expression::parse_in_time`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Scalar {
    /// A number.
    Number(f64),
    /// The text of an expression.
    Expression(String),
}

impl<'de> Deserialize<'de> for Scalar {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Scalar, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = Scalar;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number or an expression in x, y, z and t (a string)")
            }
            fn visit_f64<E>(self, v: f64) -> Result<Scalar, E> {
                Ok(Scalar::Number(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<Scalar, E> {
                Ok(Scalar::Number(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<Scalar, E> {
                Ok(Scalar::Number(v as f64))
            }
            fn visit_str<E>(self, v: &str) -> Result<Scalar, E> {
                Ok(Scalar::Expression(v.to_string()))
            }
        }
        d.deserialize_any(Visitor)
    }
}

impl Scalar {
    /// The value for the solver: a number, or the parsed expression.
    ///
    /// # Errors
    /// A number that is not finite, or an expression that does not parse,
    /// as one line.
    pub fn value(&self) -> Result<seam_fem::Value, String> {
        match self {
            Scalar::Number(v) if v.is_finite() => Ok(seam_fem::Value::Number(*v)),
            Scalar::Number(v) => Err(format!("{v} is not finite")),
            Scalar::Expression(text) => {
                let e = crate::Expression::parse_in_time(text).map_err(|e| e.to_string())?;
                let f = move |x: seam::Point3, t: f64| e.at_time(x, t).map_err(|e| e.to_string());
                Ok(seam_fem::Value::Function(text.clone(), std::sync::Arc::new(f)))
            }
        }
    }
}

/// The `[load]` table: `steps` equal increments of the pseudo-time, or
/// explicit `times` (not both).
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct LoadTable {
    /// The number of equal increments.
    pub steps: Option<usize>,
    /// Increasing times in (0, 1], the last one 1.
    pub times: Option<Vec<f64>>,
}

impl LoadTable {
    /// The load steps (one step, t = 1, without the table).
    ///
    /// # Errors
    /// Both keys given, zero steps, or bad times, as one line.
    pub fn steps(&self) -> Result<seam_fem::LoadSteps, CaseError> {
        let steps = match (self.steps, &self.times) {
            (Some(_), Some(_)) => return fail("[load]: give steps or times, not both"),
            (Some(n), None) => seam_fem::LoadSteps::equal(n),
            (None, Some(times)) => seam_fem::LoadSteps::at(times.clone()),
            (None, None) => Ok(seam_fem::LoadSteps::default()),
        };
        steps.map_err(|e| CaseError::new(format!("[load]: {e}")))
    }
}

/// An amplitude table as written (the ramp when absent), checked.
///
/// # Errors
/// As [`seam_fem::Amplitude::new`], as one line starting with `what`.
pub fn amplitude(table: Option<&Vec<[f64; 2]>>, what: &str) -> Result<seam_fem::Amplitude, CaseError> {
    match table {
        None => Ok(seam_fem::Amplitude::ramp()),
        Some(t) => seam_fem::Amplitude::new(t.clone()).map_err(|e| CaseError::new(format!("{what}: {e}"))),
    }
}

/// The `[output]` table.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// The output directory, relative to the case file's directory.
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
    seam_fem::SolveOptions::default().max_active_set_steps
}

impl Default for ContactSettings {
    fn default() -> Self {
        ContactSettings { max_iterations: default_max_iterations() }
    }
}

/// The `[newton]` table (bodies in finite deformation).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NewtonSettings {
    /// Converged when the residual falls to rtol times the force level.
    #[serde(default = "default_newton_rtol")]
    pub rtol: f64,
    /// The most Newton iterations per load step.
    #[serde(default = "default_newton_iterations")]
    pub max_iterations: usize,
}

fn default_newton_rtol() -> f64 {
    seam_fem::hyperelastic::NewtonOptions::default().rtol
}

fn default_newton_iterations() -> usize {
    seam_fem::hyperelastic::NewtonOptions::default().max_iterations
}

impl Default for NewtonSettings {
    fn default() -> Self {
        NewtonSettings { rtol: default_newton_rtol(), max_iterations: default_newton_iterations() }
    }
}

impl Interface {
    /// The interface's name in messages: "interface 2 (slave → master)", 1-based.
    pub fn describe(&self, index: usize) -> String {
        format!("interface {} ({} → {})", index + 1, self.slave, self.master)
    }

    /// The multiplier, the one place its default is decided: as written,
    /// else "standard" for glue and "lumped" for contact, except that contact
    /// on a slave surface with second-order faces takes "dual" (with Popp et
    /// al.'s basis transformation D is diagonal and positive there, while
    /// lumping is refused on Tri6 and Quad8 faces). A written "lumped" stays
    /// as written.
    pub fn multiplier(&self, second_order_slave: bool) -> Multiplier {
        self.multiplier_given.unwrap_or(match self.kind {
            InterfaceKind::Glue => Multiplier::Standard,
            InterfaceKind::Contact if second_order_slave => Multiplier::Dual,
            InterfaceKind::Contact => Multiplier::Lumped,
        })
    }
}

/// A boundary reference "body:surface", split.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct SurfaceRef {
    /// The body's name.
    pub body: String,
    /// The physical surface of its mesh (name or number).
    pub surface: String,
}

impl SurfaceRef {
    /// Splits "body:surface" (spaces around either part are trimmed).
    ///
    /// # Errors
    /// When `text` is not of that form; the message starts with `context`.
    pub fn parse(text: &str, context: &str) -> Result<SurfaceRef, CaseError> {
        match text.split_once(':') {
            Some((b, s)) if !b.trim().is_empty() && !s.trim().is_empty() => {
                Ok(SurfaceRef { body: b.trim().to_string(), surface: s.trim().to_string() })
            }
            _ => fail(format!("{context}: \"{text}\" is not of the form \"body:surface\"")),
        }
    }
}

impl fmt::Display for SurfaceRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.body, self.surface)
    }
}

impl Case {
    /// Reads and checks a case file: [`Case::from_toml`], then that every mesh
    /// is a regular file. Every error names `path`.
    ///
    /// # Errors
    /// A [`CaseError`] naming the file and the item at fault (module doc).
    pub fn read(path: &Path) -> Result<Case, CaseError> {
        let text = read_text(path).map_err(|e| e.with_path(path))?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let case = Case::from_toml(&text, &base).map_err(|e| e.with_path(path))?;
        case.check_mesh_files().map_err(|e| e.with_path(path))?;
        Ok(case)
    }

    /// Parses and checks the text of a case file whose directory is `base`,
    /// without touching the file system (the meshes are not looked at).
    ///
    /// # Errors
    /// A [`CaseError`] naming the item at fault.
    pub fn from_toml(text: &str, base: &Path) -> Result<Case, CaseError> {
        let mut case: Case = toml::from_str(text).map_err(|e| toml_error(text, &e))?;
        case.base = base.to_path_buf();
        case.check()?;
        Ok(case)
    }

    /// Parses and checks a case given as JSON with the schema of a case file
    /// (as a Python dict is), whose relative paths are relative to `base`:
    /// the JSON becomes TOML text for [`Case::from_toml`]. Does not touch the
    /// file system.
    ///
    /// # Errors
    /// A [`CaseError`]: JSON that is no table of TOML values (a null, say), or
    /// as [`Case::from_toml`].
    pub fn from_json(json: &str, base: &Path) -> Result<Case, CaseError> {
        let value: toml::Table =
            serde_json::from_str(json).map_err(|e| CaseError::new(format!("not a case: {e}")))?;
        let text = toml::to_string(&value).map_err(|e| CaseError::new(format!("not a case: {e}")))?;
        Case::from_toml(&text, base)
    }

    /// Whether the case has contact interfaces.
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

    /// The mesh files of the bodies, resolved.
    pub fn mesh_paths(&self) -> Vec<PathBuf> {
        self.bodies.iter().map(|b| self.resolve(&b.mesh)).collect()
    }

    /// Every mesh is a regular file (a directory, a device or a pipe would fail
    /// later, or never end); [`Case::read`] checks it.
    ///
    /// # Errors
    /// A [`CaseError`] naming the body and its mesh.
    pub fn check_mesh_files(&self) -> Result<(), CaseError> {
        for b in &self.bodies {
            let mesh = self.resolve(&b.mesh);
            if let Err(why) = regular_file(&mesh) {
                return fail(format!("body \"{}\": mesh {} {why}", b.name, mesh.display()));
            }
        }
        Ok(())
    }

    fn check(&self) -> Result<(), CaseError> {
        if self.bodies.is_empty() {
            return fail("no [[body]]");
        }
        let mut names = BTreeSet::new();
        for b in &self.bodies {
            if !names.insert(b.name.as_str()) {
                return fail(format!("body \"{}\" is defined twice", b.name));
            }
            if b.name.is_empty() || b.name.contains([':', '/', '\\']) || b.name.starts_with('.') {
                return fail(format!(
                    "body name \"{}\" must be non-empty, not start with '.' and hold no ':', '/' or '\\' \
                     (it names the output file)",
                    b.name
                ));
            }
            if let Err(e) = seam_fem::Material::new(b.young, b.poisson) {
                return fail(format!("body \"{}\": {e}", b.name));
            }
            if let Some(format) = b.format.as_deref().filter(|f| seam_io::ModelFormat::from_name(f).is_none())
            {
                return fail(format!(
                    "body \"{}\": unknown format \"{format}\" (formats: \"{}\")",
                    b.name,
                    seam_io::ModelFormat::NAMES.join("\", \"")
                ));
            }
            if b.body_force.iter().any(|v| !v.is_finite()) {
                return fail(format!("body \"{}\": body_force must be finite", b.name));
            }
            let what = format!("body \"{}\": body_force_amplitude", b.name);
            amplitude(b.body_force_amplitude.as_ref(), &what)?;
        }
        let known = |r: &SurfaceRef, what: &str| -> Result<(), CaseError> {
            if names.contains(r.body.as_str()) {
                return Ok(());
            }
            let bodies: Vec<&str> = names.iter().copied().collect();
            fail(format!("{what}: no body named \"{}\" (bodies: {})", r.body, bodies.join(", ")))
        };
        let mut slaves = BTreeMap::new();
        let mut pairs = BTreeMap::new();
        for (i, f) in self.interfaces.iter().enumerate() {
            let what = format!("interface {}", i + 1);
            let (m, s) = (SurfaceRef::parse(&f.master, &what)?, SurfaceRef::parse(&f.slave, &what)?);
            known(&m, &what)?;
            known(&s, &what)?;
            if m.body == s.body {
                return fail(format!("{what}: master and slave belong to the same body \"{}\"", m.body));
            }
            if let Some(j) = slaves.insert(s.clone(), i) {
                return fail(format!("{what}: {} is already the slave side of interface {}", f.slave, j + 1));
            }
            let pair = if m < s { (m, s) } else { (s, m) };
            if let Some(j) = pairs.insert(pair, i) {
                return fail(format!(
                    "{} couples the same two surfaces as {}: each pair of surfaces is coupled once",
                    f.describe(i),
                    self.interfaces[j].describe(j)
                ));
            }
            if f.kind == InterfaceKind::Contact && f.multiplier_given == Some(Multiplier::Standard) {
                return fail(format!(
                    "{}: contact needs multiplier \"lumped\" (the default) or \"dual\"",
                    f.describe(i)
                ));
            }
            match (f.friction, f.kind) {
                (Some(mu), InterfaceKind::Contact) if !(mu.is_finite() && mu >= 0.0) => {
                    return fail(format!(
                        "{}: friction = {mu} must be a finite coefficient ≥ 0",
                        f.describe(i)
                    ));
                }
                (Some(_), InterfaceKind::Glue) => {
                    return fail(format!(
                        "{}: friction applies to contact interfaces only (a glued interface transmits every traction)",
                        f.describe(i)
                    ));
                }
                _ => {}
            }
            if let Some(g) = f.max_gap {
                if !(g.is_finite() && g >= 0.0) {
                    return fail(format!("{what}: max_gap = {g} must be a non-negative length"));
                }
            }
        }
        self.check_acyclic()?;
        if self.contact.max_iterations == 0 {
            return fail("[contact]: max_iterations must be at least 1");
        }
        let linear = self.bodies.iter().find(|b| b.material == MaterialLaw::Linear);
        if let (Some(l), Some(h)) = (linear, self.bodies.iter().find(|b| b.material != MaterialLaw::Linear)) {
            return fail(format!(
                "body \"{}\" is linear and body \"{}\" hyperelastic: a case is solved either in small strain or \
                 in finite deformation, so give every body a hyperelastic material or none",
                l.name, h.name
            ));
        }
        let newton = &self.newton;
        if !(newton.rtol > 0.0 && newton.rtol < 1.0) {
            return fail(format!("[newton]: rtol = {} must lie in (0, 1)", newton.rtol));
        }
        if newton.max_iterations == 0 {
            return fail("[newton]: max_iterations must be at least 1");
        }
        for (i, d) in self.dirichlet.iter().enumerate() {
            let what = format!("dirichlet {}", i + 1);
            known(&SurfaceRef::parse(&d.boundary, &what)?, &what)?;
            if d.components().is_empty() {
                return fail(format!("{what}: give at least one of ux, uy, uz"));
            }
            for (k, v) in d.components() {
                v.value().map_err(|e| CaseError::new(format!("{what}: {}: {e}", ["ux", "uy", "uz"][k])))?;
            }
            amplitude(d.amplitude.as_ref(), &format!("{what}: amplitude"))?;
        }
        for (i, t) in self.traction.iter().enumerate() {
            let what = format!("traction {}", i + 1);
            known(&SurfaceRef::parse(&t.boundary, &what)?, &what)?;
            for (k, v) in t.t.iter().enumerate() {
                v.value().map_err(|e| CaseError::new(format!("{what}: t ({}): {e}", ["x", "y", "z"][k])))?;
            }
            amplitude(t.amplitude.as_ref(), &format!("{what}: amplitude"))?;
        }
        self.load.steps()?;
        self.check_held()
    }

    /// Index of each body by name (the names are checked unique and every
    /// reference known before this is used).
    fn body_index(&self) -> BTreeMap<&str, usize> {
        self.bodies.iter().enumerate().map(|(i, b)| (b.name.as_str(), i)).collect()
    }

    /// (slave body, master body) of every interface.
    fn edges(&self) -> Result<Vec<(usize, usize)>, CaseError> {
        let index = self.body_index();
        self.interfaces
            .iter()
            .map(|f| {
                let (m, s) = (SurfaceRef::parse(&f.master, "")?, SurfaceRef::parse(&f.slave, "")?);
                Ok((index[s.body.as_str()], index[m.body.as_str()]))
            })
            .collect()
    }

    /// No directed cycle slave → master → … → slave (module doc). Depth-first
    /// search with an explicit stack; the first cycle found is named by its
    /// interfaces.
    fn check_acyclic(&self) -> Result<(), CaseError> {
        let edges = self.edges()?;
        let n = self.bodies.len();
        // 0: unvisited, 1: on the current path, 2: done.
        let mut state = vec![0u8; n];
        // The interface by which each body on the path was entered.
        let mut entered_by: Vec<Option<usize>> = vec![None; n];
        for root in 0..n {
            if state[root] != 0 {
                continue;
            }
            // (body, next interface to try)
            let mut stack = vec![(root, 0usize)];
            state[root] = 1;
            while let Some(&mut (body, ref mut next)) = stack.last_mut() {
                match (*next..edges.len()).find(|&i| edges[i].0 == body) {
                    Some(i) => {
                        *next = i + 1;
                        let to = edges[i].1;
                        match state[to] {
                            0 => {
                                state[to] = 1;
                                entered_by[to] = Some(i);
                                stack.push((to, 0));
                            }
                            1 => return fail(self.describe_cycle(&edges, &stack, &entered_by, i)),
                            _ => {}
                        }
                    }
                    None => {
                        state[body] = 2;
                        stack.pop();
                    }
                }
            }
        }
        Ok(())
    }

    /// "interfaces 1 (a → b) and 2 (b → a) form a cycle a → b → a …" for the
    /// path `stack` closed by interface `closing`.
    fn describe_cycle(
        &self,
        edges: &[(usize, usize)],
        stack: &[(usize, usize)],
        entered_by: &[Option<usize>],
        closing: usize,
    ) -> String {
        let start = edges[closing].1;
        let at = stack.iter().position(|&(b, _)| b == start).unwrap_or(0);
        let mut interfaces: Vec<usize> = stack[at + 1..].iter().filter_map(|&(b, _)| entered_by[b]).collect();
        interfaces.push(closing);
        let mut bodies: Vec<&str> = stack[at..].iter().map(|&(b, _)| self.bodies[b].name.as_str()).collect();
        bodies.push(&self.bodies[start].name);
        let mut list: Vec<String> = interfaces
            .iter()
            .map(|&i| format!("{} ({} → {})", i + 1, self.interfaces[i].slave, self.interfaces[i].master))
            .collect();
        let last = list.pop().unwrap_or_default();
        let list = if list.is_empty() { last } else { format!("{} and {last}", list.join(", ")) };
        format!(
            "interfaces {list} form a cycle {} (each body is the slave of the next): a body would be \
             constrained by itself; swap master and slave of one of them",
            bodies.join(" → ")
        )
    }

    /// Every body must be held against rigid motion: some body of its group
    /// (bodies connected by interfaces, glued or in contact) needs a Dirichlet
    /// condition on each of the three components (a necessary condition; the
    /// factorisation detects the rest, for contact in each active-set step).
    fn check_held(&self) -> Result<(), CaseError> {
        let index = self.body_index();
        let mut group: Vec<usize> = (0..self.bodies.len()).collect();
        fn root(g: &mut [usize], mut i: usize) -> usize {
            while g[i] != i {
                g[i] = g[g[i]];
                i = g[i];
            }
            i
        }
        for (s, m) in self.edges()? {
            let (a, b) = (root(&mut group, s), root(&mut group, m));
            group[a] = b;
        }
        let mut held = vec![[false; 3]; self.bodies.len()];
        for d in &self.dirichlet {
            let r = root(&mut group, index[SurfaceRef::parse(&d.boundary, "")?.body.as_str()]);
            for (k, _) in d.components() {
                held[r][k] = true;
            }
        }
        let glue = self.interfaces.iter().any(|f| f.kind == InterfaceKind::Glue);
        let neighbour = match (glue, self.is_contact()) {
            (true, true) => "glued to it or in contact with it",
            (false, true) => "in contact with it",
            _ => "glued to it",
        };
        for (i, b) in self.bodies.iter().enumerate() {
            let r = root(&mut group, i);
            if let Some(k) = (0..3).find(|&k| !held[r][k]) {
                return fail(format!(
                    "body \"{}\" can move freely along {} (no Dirichlet condition on {} in it or in a body \
                     {neighbour}): the problem is singular",
                    b.name,
                    ["x", "y", "z"][k],
                    ["ux", "uy", "uz"][k]
                ));
            }
        }
        Ok(())
    }
}

/// The largest case file read: far more than any hand-written or generated case
/// needs, and a bound on what a wrong path (a mesh given as the case) costs.
pub const MAX_CASE_BYTES: u64 = 16 << 20;

/// The text of a case file, or why it cannot be read.
fn read_text(path: &Path) -> Result<String, CaseError> {
    regular_file(path).map_err(|why| CaseError::new(format!("the case file {why}")))?;
    let size = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    if size > MAX_CASE_BYTES {
        return fail(format!(
            "the case file has {size} bytes, more than the {MAX_CASE_BYTES} a case file may have (is it a mesh?)"
        ));
    }
    let bytes = std::fs::read(path).map_err(|e| CaseError::new(format!("cannot read the case file: {e}")))?;
    String::from_utf8(bytes).map_err(|e| {
        CaseError::new(format!(
            "the case file is not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        ))
    })
}

/// Ok for an existing regular file (symbolic links followed); otherwise why
/// not: "does not exist", "is a directory", "is not a regular file", or the
/// I/O error.
pub fn regular_file(path: &Path) -> Result<(), String> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() => Ok(()),
        Ok(m) if m.is_dir() => Err("is a directory".into()),
        Ok(_) => Err("is not a regular file".into()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err("does not exist".into()),
        Err(e) => Err(format!("cannot be read: {e}")),
    }
}

/// A TOML error as "line L, column C: what": without the quoted source line
/// toml's own message holds (which may be any length).
fn toml_error(text: &str, e: &toml::de::Error) -> CaseError {
    let what = e.message().split_whitespace().collect::<Vec<_>>().join(" ");
    let Some(span) = e.span() else { return CaseError::new(format!("TOML: {what}")) };
    let before = text.get(..span.start).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    CaseError::new(format!("line {line}, column {column}: {what}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(dir: &Path, text: &str) -> Result<Case, CaseError> {
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

    /// GOOD with a third body "side" (c.msh) and `interfaces` appended.
    fn three_bodies(interfaces: &str) -> String {
        GOOD.replace(
            "[[interface]]",
            &format!(
                "[[body]]\nname = \"side\"\nmesh = \"a.msh\"\nyoung = 1.0\npoisson = 0.0\n\n{interfaces}\n\n[[interface]]"
            ),
        )
    }

    #[test]
    fn a_good_case_reads() {
        let tmp = tempfile::tempdir().unwrap();
        let c = case(tmp.path(), GOOD).unwrap();
        assert_eq!(c.bodies.len(), 2);
        assert_eq!(c.interfaces[0].multiplier(false), Multiplier::Dual);
        assert!(!c.is_contact());
        assert_eq!(c.contact.max_iterations, 50);
        let zero = Scalar::Number(0.0);
        assert_eq!(c.dirichlet[0].components(), vec![(0, &zero), (1, &zero), (2, &zero)]);
        assert_eq!(c.resolve(Path::new("a.msh")), tmp.path().join("a.msh"));
        assert_eq!(c.mesh_paths(), [tmp.path().join("a.msh"), tmp.path().join("b.msh")]);
    }

    /// `.inp` in any case is Abaqus, `format` overrides the extension.
    #[test]
    fn mesh_formats_by_extension_or_format() {
        let tmp = tempfile::tempdir().unwrap();
        let c = case(tmp.path(), &GOOD.replace("mesh = \"b.msh\"", "mesh = \"b.msh\"\nformat = \"abaqus\""))
            .unwrap();
        assert_eq!(c.bodies[0].model_format(), seam_io::ModelFormat::Gmsh);
        assert_eq!(c.bodies[1].model_format(), seam_io::ModelFormat::Abaqus);
        std::fs::write(tmp.path().join("b.INP"), "").unwrap();
        let c = case(tmp.path(), &GOOD.replace("mesh = \"b.msh\"", "mesh = \"b.INP\"")).unwrap();
        assert_eq!(c.bodies[1].model_format(), seam_io::ModelFormat::Abaqus);
        let c = case(tmp.path(), &GOOD.replace("mesh = \"b.msh\"", "mesh = \"b.INP\"\nformat = \"gmsh\""))
            .unwrap();
        assert_eq!(c.bodies[1].model_format(), seam_io::ModelFormat::Gmsh);
    }

    #[test]
    fn input_errors_are_named_before_any_work() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::create_dir(tmp.path().join("dir.msh")).unwrap();
        let cases = [
            (GOOD.replace("young = 2.0e3", "young = -1.0"), "body \"upper\": Young's modulus E = -1.0 must be positive"),
            (GOOD.replace("young = 2.0e3", "young = 1e308"), "E = 1e308 is out of range"),
            (GOOD.replace("poisson = 0.25", "poisson = 0.5"), "Poisson's ratio ν = 0.5 must lie in (-1, 0.5)"),
            (GOOD.replace("poisson = 0.25", "poisson = 0.4999999999"), "too close to 0.5 (volumetric locking)"),
            (GOOD.replace("b.msh", "missing.msh"), "missing.msh does not exist"),
            (GOOD.replace("b.msh", "dir.msh"), "dir.msh is a directory"),
            (GOOD.replace("slave = \"upper:bottom\"", "slave = \"middle:bottom\""), "no body named \"middle\""),
            (GOOD.replace("boundary = \"upper:top\"", "boundary = \"upper\""), "is not of the form \"body:surface\""),
            (GOOD.replace("[[interface]]\nmaster = \"lower:top\"\nslave = \"upper:bottom\"\nkind = \"glue\"\nmultiplier = \"dual\"\n", ""), "body \"upper\" can move freely along x"),
            (GOOD.replace("uz = 0.0", ""), "can move freely along z"),
            (GOOD.replace("kind = \"glue\"", "kind = \"weld\""), "unknown variant `weld`"),
            (
                GOOD.replace("mesh = \"b.msh\"", "mesh = \"b.msh\"\nformat = \"vtu\""),
                "body \"upper\": unknown format \"vtu\" (formats: \"gmsh\", \"abaqus\", \"exodus\")",
            ),
            (GOOD.replace("young = 1.0e3", "youngs = 1.0e3"), "unknown field `youngs`"),
            (GOOD.replace("name = \"upper\"", "name = \"lower\""), "body \"lower\" is defined twice"),
            (
                GOOD.replace("kind = \"glue\"\nmultiplier = \"dual\"", "kind = \"contact\"\nmultiplier = \"standard\""),
                "interface 1 (upper:bottom → lower:top): contact needs multiplier \"lumped\" (the default) or \"dual\"",
            ),
            (GOOD.replace("[output]", "[contact]\nmax_iteration = 5\n\n[output]"), "unknown field `max_iteration`"),
            (GOOD.replace("[output]", "[contact]\nmax_iterations = 0\n\n[output]"), "max_iterations must be at least 1"),
            (
                GOOD.replace("kind = \"glue\"", "kind = \"contact\"").replace("ux = 0.0\n", ""),
                "(no Dirichlet condition on ux in it or in a body in contact with it)",
            ),
        ];
        for (text, message) in cases {
            let err = case(tmp.path(), &text).unwrap_err().to_string();
            assert!(err.contains(message), "expected '{message}' in: {err}");
            assert!(
                err.starts_with(&tmp.path().join("case.toml").display().to_string()),
                "names the file: {err}"
            );
            assert!(!err.contains('\n'), "one line: {err}");
        }
    }

    #[test]
    fn the_same_surfaces_coupled_twice_are_refused() {
        let back = "[[interface]]\nmaster = \"upper:bottom\"\nslave = \"lower:top\"\nkind = \"glue\"\n";
        let err =
            Case::from_toml(&GOOD.replace("[[dirichlet]]", &format!("{back}\n[[dirichlet]]")), Path::new(""))
                .unwrap_err()
                .to_string();
        assert_eq!(
            err,
            "interface 2 (lower:top → upper:bottom) couples the same two surfaces as interface 1 \
             (upper:bottom → lower:top): each pair of surfaces is coupled once"
        );
        // The same direction twice is the slave used twice.
        let again = "[[interface]]\nmaster = \"lower:top\"\nslave = \"upper:bottom\"\nkind = \"glue\"\n";
        let err = Case::from_toml(
            &GOOD.replace("[[dirichlet]]", &format!("{again}\n[[dirichlet]]")),
            Path::new(""),
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("upper:bottom is already the slave side of interface 1"), "{err}");
    }

    #[test]
    fn cycles_in_the_coupling_graph_are_refused_and_chains_are_not() {
        // upper → lower (interface 3 after insertion) with lower → side → upper closes a cycle.
        let cycle = three_bodies(
            "[[interface]]\nmaster = \"side:a\"\nslave = \"lower:a\"\nkind = \"glue\"\n\n\
             [[interface]]\nmaster = \"upper:a\"\nslave = \"side:b\"\nkind = \"glue\"",
        );
        let err = Case::from_toml(&cycle, Path::new("")).unwrap_err().to_string();
        assert_eq!(
            err,
            "interfaces 1 (lower:a → side:a), 2 (side:b → upper:a) and 3 (upper:bottom → lower:top) form a \
             cycle lower → side → upper → lower (each body is the slave of the next): a body would be \
             constrained by itself; swap master and slave of one of them"
        );
        // Two bodies, two different interfaces in opposite directions.
        let two = GOOD.replace(
            "[[dirichlet]]",
            "[[interface]]\nmaster = \"upper:side\"\nslave = \"lower:side\"\nkind = \"glue\"\n\n[[dirichlet]]",
        );
        let err = Case::from_toml(&two, Path::new("")).unwrap_err().to_string();
        assert!(err.contains("interfaces 2 (lower:side → upper:side) and 1 (upper:bottom → lower:top) form a cycle lower → upper → lower"), "{err}");
        // A chain and a body with two masters are fine.
        let chain = three_bodies(
            "[[interface]]\nmaster = \"lower:a\"\nslave = \"side:a\"\nkind = \"glue\"\n\n\
             [[interface]]\nmaster = \"side:b\"\nslave = \"upper:b\"\nkind = \"glue\"",
        );
        Case::from_toml(&chain, Path::new("")).unwrap();
    }

    #[test]
    fn toml_errors_give_line_and_column_without_quoting_the_line() {
        let err = Case::from_toml("[[body]\nname = ", Path::new("")).unwrap_err().to_string();
        assert_eq!(err, "line 1, column 8: unclosed array table, expected `]`");
        // A 200 000-deep array: the parser's recursion limit, and a short message.
        let deep = format!("a = {}{}", "[".repeat(200_000), "]".repeat(200_000));
        let err = Case::from_toml(&deep, Path::new("")).unwrap_err().to_string();
        assert!(err.len() < 200 && err.starts_with("line 1, column "), "{}", &err[..err.len().min(300)]);
        let err = Case::from_toml(&GOOD.replace("kind = \"glue\"", "kind = \"weld\""), Path::new(""))
            .unwrap_err()
            .to_string();
        assert_eq!(err, "line 17, column 8: unknown variant `weld`, expected `glue` or `contact`");
    }

    #[test]
    fn case_files_that_are_not_text_or_not_files_are_named() {
        let tmp = tempfile::tempdir().unwrap();
        let err = Case::read(tmp.path()).unwrap_err().to_string();
        assert!(err.ends_with("the case file is a directory"), "{err}");
        let err = Case::read(&tmp.path().join("none.toml")).unwrap_err().to_string();
        assert!(err.ends_with("the case file does not exist"), "{err}");
        std::fs::write(tmp.path().join("bin.toml"), [0xff, 0xfe, 0x00]).unwrap();
        let err = Case::read(&tmp.path().join("bin.toml")).unwrap_err().to_string();
        assert!(err.ends_with("the case file is not UTF-8 text (invalid byte at offset 0)"), "{err}");
        if Path::new("/dev/zero").exists() {
            let err = Case::read(Path::new("/dev/zero")).unwrap_err().to_string();
            assert_eq!(err, "/dev/zero: the case file is not a regular file");
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
        assert_eq!(c.interfaces[0].multiplier(false), Multiplier::Lumped);
        assert_eq!(c.contact.max_iterations, 7);
        // Glue keeps its default.
        let c = case(tmp.path(), &GOOD.replace("multiplier = \"dual\"\n", "")).unwrap();
        assert_eq!(c.interfaces[0].multiplier(false), Multiplier::Standard);
    }
}
