//! `seam solve CASE.toml`: linear-elastic bodies glued by mortar across
//! non-matching interfaces (the case schema is in [`crate::case`]).
//!
//! Order of work: the case is read and checked ([`Case::read`]); the output
//! files are checked (none exists unless `--force`, the directory is
//! writable); the meshes are read and every named surface is looked up; only
//! then is anything assembled. Results are written all-or-nothing
//! ([`Staged`]):
//!
//! - `<dir>/<body>.vtu` per body: point data `displacement` (3), nodal
//!   `stress` (6, Voigt xx yy zz yz xz xy; volume-weighted average of the
//!   cells around the point) and `von_mises`; cell data `stress` (6, at the
//!   cell centre) and `von_mises`.
//! - `<dir>/<slave body>_<surface>_interface.vtu` per interface: the slave
//!   surface (its own points only) with point data `traction` (3, force per
//!   area exerted by the master on the slave, −λ), `normal_traction` (t·n with
//!   n the slave's outward nodal normal: negative is compression),
//!   `tangential_traction` (3, t − (t·n)n), `normal` (3), `displacement` (3),
//!   `constrained` (1 where the interface constrains the point, else 0) and
//!   `body_point` (the point's 0-based index in the body's mesh).
//! - `<dir>/summary.json` (written last).
//!
//! Names in file names keep letters, digits, `-`, `_` and `.`; any other
//! character becomes `_`.

use crate::args::{SolveArgs, SolverArg};
use crate::case::{Case, CaseMultiplier, SurfaceRef};
use crate::output::Staged;
use crate::Failure;
use anyhow::{anyhow, Context};
use rayon::prelude::*;
use seam::{Face, Facing, MaxGap, MortarOptions, MortarSummary, Multiplier, Point3, SurfaceMesh};
use seam_fem::pcg::PcgOptions;
use seam_fem::{
    recover_stresses, GlueError, GluedSolution, Load, Material, Problem, ProblemBody, ProblemInterface,
    Solver, Stresses, Support, SurfaceId,
};
use seam_io::Field;
use serde::Serialize;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A solved case, for callers that report on it or draw it (the example).
pub struct Solved {
    /// The output directory.
    pub out_dir: PathBuf,
    /// The bodies, interfaces, supports and loads, as read.
    pub problem: Problem,
    /// Displacements, multipliers and the solver's report.
    pub solution: GluedSolution,
    /// Per interface: the slave surface and its tractions.
    pub interfaces: Vec<InterfaceResult>,
    /// What `summary.json` holds.
    pub summary: Summary,
}

/// One interface's result on its slave surface, on the surface's own points.
pub struct InterfaceResult {
    /// The slave surface, compacted to the points its faces use.
    pub mesh: SurfaceMesh,
    /// Index of each compacted point in the slave body's mesh.
    pub body_point: Vec<usize>,
    /// Per point: traction exerted by the master on the slave (−λ).
    pub traction: Vec<[f64; 3]>,
    /// Per point: the slave's outward unit normal.
    pub normal: Vec<Point3>,
    /// Per point: t·n.
    pub normal_traction: Vec<f64>,
    /// Per point: t − (t·n) n.
    pub tangential_traction: Vec<[f64; 3]>,
    /// Per point: the slave body's displacement.
    pub displacement: Vec<[f64; 3]>,
    /// Per point: 1 when this interface constrains it, else 0.
    pub constrained: Vec<f64>,
}

/// `summary.json`.
#[derive(Serialize)]
pub struct Summary {
    pub case: String,
    pub output_dir: String,
    pub solver: &'static str,
    /// The method the solver used, e.g. "saddle-point LU".
    pub method: &'static str,
    /// The interfaces' multiplier when they share one, "mixed" otherwise,
    /// "none" without interfaces.
    pub multiplier: String,
    pub dofs: usize,
    pub constraints: usize,
    pub iterations: usize,
    pub residual: f64,
    /// Sum of all applied loads (tractions and body forces).
    pub applied_load: [f64; 3],
    pub bodies: Vec<BodySummary>,
    pub interfaces: Vec<InterfaceSummary>,
    pub seconds: Seconds,
    pub threads: usize,
    pub seam_version: &'static str,
}

#[derive(Serialize)]
pub struct BodySummary {
    pub name: String,
    pub mesh: String,
    pub file: String,
    pub points: usize,
    pub cells: usize,
    pub dofs: usize,
    pub young: f64,
    pub poisson: f64,
    /// Has a Dirichlet condition of its own.
    pub supported: bool,
    /// Tractions and body force on the body.
    pub applied_load: [f64; 3],
    /// Sum of the interface forces on the body (as slave +force, as master −force);
    /// for a body without supports, −applied_load.
    pub interface_force: [f64; 3],
    pub max_displacement: f64,
    pub max_von_mises: f64,
}

#[derive(Serialize)]
pub struct InterfaceSummary {
    pub master: String,
    pub slave: String,
    pub file: String,
    pub multiplier: String,
    /// Slave points with at least one constrained component.
    pub constrained_nodes: usize,
    /// Resultant force exerted by the master on the slave, −Σ_p (Dλ)_p.
    pub force: [f64; 3],
    pub covered_fraction: f64,
    /// The mortar operator's summary (as `seam assemble` reports it).
    pub mortar: MortarSummary,
}

#[derive(Serialize, Default, Clone, Copy)]
pub struct Seconds {
    pub read: f64,
    pub assembly: f64,
    pub mortar: f64,
    pub setup: f64,
    pub factorization: f64,
    pub solve: f64,
    pub stresses: f64,
    pub output: f64,
    pub total: f64,
}

pub fn run(args: &SolveArgs) -> Result<(), Failure> {
    let solved = solve(args)?;
    println!("seam solve {} → {}", args.case.display(), solved.out_dir.display());
    for line in report(&solved) {
        println!("  {line}");
    }
    Ok(())
}

/// Reads, checks, solves and writes the case (module doc).
pub fn solve(args: &SolveArgs) -> Result<Solved, Failure> {
    let start = Instant::now();
    let case = Case::read(&args.case)?;
    let pool = crate::assemble::thread_pool(args.threads)?;
    let out_dir = case.resolve(&case.output.dir);
    let names = OutputNames::new(&case, &out_dir).map_err(|e| anyhow!("{}: {e}", args.case.display()))?;
    let mut out = Staged::prepare(&names.all(), args.force)?;
    let mut seconds = Seconds::default();

    let clock = Instant::now();
    let problem =
        pool.install(|| build_problem(&case)).map_err(|e| anyhow!("{}: {e:#}", args.case.display()))?;
    seconds.read = clock.elapsed().as_secs_f64();

    if !(args.rtol > 0.0 && args.rtol < 1.0) {
        return Err(anyhow!("--rtol {} must lie in (0, 1)", args.rtol).into());
    }
    let solver = match args.solver {
        SolverArg::Direct => Solver::Direct,
        SolverArg::Pcg => Solver::Pcg(PcgOptions { rtol: args.rtol, ..PcgOptions::default() }),
    };
    let solution = pool.install(|| problem.solve(solver)).map_err(|e| glue_failure(e, &case, &args.case))?;
    let t = solution.report.seconds;
    (seconds.assembly, seconds.mortar, seconds.setup, seconds.factorization, seconds.solve) =
        (t.assembly, t.mortar, t.setup, t.factorization, t.solve);

    let clock = Instant::now();
    let stresses = pool
        .install(|| {
            problem
                .bodies
                .par_iter()
                .zip(&solution.displacement)
                .map(|(b, u)| {
                    recover_stresses(&b.mesh, &b.material, u).map_err(|e| anyhow!("body \"{}\": {e}", b.name))
                })
                .collect::<anyhow::Result<Vec<_>>>()
        })
        .context("stress recovery")?;
    let interfaces: Vec<InterfaceResult> =
        (0..problem.interfaces.len()).map(|i| interface_result(&problem, &solution, i)).collect();
    seconds.stresses = clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    for (b, body) in problem.bodies.iter().enumerate() {
        let (point, cell) = body_fields(&solution.displacement[b], &stresses[b]);
        out.write(&names.bodies[b], |p| {
            seam_io::write_volume_vtu_file(p, &body.mesh, &point, &cell).map_err(std::io::Error::other)
        })?;
    }
    for (i, r) in interfaces.iter().enumerate() {
        out.write(&names.interfaces[i], |p| {
            seam_io::write_vtu_file(p, &r.mesh, &interface_fields(r), &[]).map_err(std::io::Error::other)
        })?;
    }
    seconds.output = clock.elapsed().as_secs_f64();
    seconds.total = start.elapsed().as_secs_f64();
    let summary = summary(&case, args, &names, &problem, &solution, &stresses, seconds, &pool)?;
    let json = serde_json::to_string_pretty(&summary).context("summary")?;
    out.write(&names.summary, |p| std::fs::write(p, json + "\n"))?;
    out.commit(&[])?;
    Ok(Solved { out_dir, problem, solution, interfaces, summary })
}

/// The output files of a case.
struct OutputNames {
    bodies: Vec<PathBuf>,
    interfaces: Vec<PathBuf>,
    summary: PathBuf,
}

impl OutputNames {
    fn new(case: &Case, dir: &Path) -> anyhow::Result<OutputNames> {
        let bodies = case.bodies.iter().map(|b| dir.join(format!("{}.vtu", file_part(&b.name)))).collect();
        let interfaces = case
            .interfaces
            .iter()
            .map(|f| {
                let s = SurfaceRef::parse(&f.slave, "")?;
                Ok(dir.join(format!("{}_{}_interface.vtu", file_part(&s.body), file_part(&s.surface))))
            })
            .collect::<anyhow::Result<_>>()?;
        let names = OutputNames { bodies, interfaces, summary: dir.join("summary.json") };
        let mut seen = BTreeSet::new();
        for path in names.all() {
            if !seen.insert(path.clone()) {
                anyhow::bail!(
                    "two outputs would be written to {}: rename a body or a surface",
                    path.display()
                );
            }
        }
        Ok(names)
    }

    fn all(&self) -> Vec<PathBuf> {
        let mut all = self.bodies.clone();
        all.extend(self.interfaces.iter().cloned());
        all.push(self.summary.clone());
        all
    }
}

/// `name` with every character other than a letter, digit, `-`, `_` or `.`
/// replaced by `_`.
fn file_part(name: &str) -> String {
    name.chars().map(|c| if c.is_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect()
}

/// The surfaces of body `name` the case refers to, in order of first mention.
fn referenced_surfaces(case: &Case, name: &str) -> Vec<String> {
    let refs = case
        .interfaces
        .iter()
        .flat_map(|f| [&f.master, &f.slave])
        .chain(case.dirichlet.iter().map(|d| &d.boundary))
        .chain(case.traction.iter().map(|t| &t.boundary));
    let mut surfaces: Vec<String> = Vec::new();
    for r in refs.filter_map(|r| SurfaceRef::parse(r, "").ok()) {
        if r.body == name && !surfaces.contains(&r.surface) {
            surfaces.push(r.surface);
        }
    }
    surfaces
}

/// Reads one body's mesh and the surfaces the case names on it.
fn read_body(case: &Case, b: &crate::case::Body) -> anyhow::Result<ProblemBody> {
    let what = || format!("body \"{}\"", b.name);
    let path = case.resolve(&b.mesh);
    let msh = seam_io::read_msh_file(&path).with_context(what)?;
    let mesh = msh.volume(b.volume.as_deref()).map_err(|e| e.with_path(&path)).with_context(what)?;
    let surfaces = referenced_surfaces(case, &b.name)
        .into_iter()
        .map(|s| {
            let surface = msh.surface(Some(&s)).map_err(|e| e.with_path(&path)).with_context(what)?;
            Ok((s, surface))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let material = Material::new(b.young, b.poisson).map_err(|e| anyhow!("{}: {e}", what()))?;
    Ok(ProblemBody { name: b.name.clone(), mesh, material, body_force: b.body_force, surfaces })
}

/// The in-memory problem of a checked case: meshes read, surfaces looked up.
fn build_problem(case: &Case) -> anyhow::Result<Problem> {
    let read: Vec<anyhow::Result<ProblemBody>> = case.bodies.par_iter().map(|b| read_body(case, b)).collect();
    let mut problem =
        Problem { bodies: read.into_iter().collect::<anyhow::Result<_>>()?, ..Problem::default() };
    let id = |problem: &Problem, text: &str| -> anyhow::Result<SurfaceId> {
        let r = SurfaceRef::parse(text, "")?;
        problem.find_surface(&format!("{}:{}", r.body, r.surface)).ok_or_else(|| anyhow!("no surface {text}"))
    };
    for f in &case.interfaces {
        let max_gap = f.max_gap.map_or(MaxGap::DEFAULT, MaxGap::Absolute);
        let options = MortarOptions {
            multiplier: multiplier(f.multiplier),
            facing: Facing::Opposite,
            max_gap,
            ..MortarOptions::default()
        };
        let (master, slave) = (id(&problem, &f.master)?, id(&problem, &f.slave)?);
        problem.interfaces.push(ProblemInterface { master, slave, options });
    }
    for d in &case.dirichlet {
        let boundary = id(&problem, &d.boundary)?;
        problem.supports.push(Support { boundary, values: [d.ux, d.uy, d.uz] });
    }
    for t in &case.traction {
        let boundary = id(&problem, &t.boundary)?;
        problem.loads.push(Load { boundary, t: t.t });
    }
    Ok(problem)
}

fn multiplier(m: CaseMultiplier) -> Multiplier {
    match m {
        CaseMultiplier::Standard => Multiplier::Standard,
        CaseMultiplier::Dual => Multiplier::Dual,
        CaseMultiplier::Lumped => Multiplier::Lumped,
    }
}

/// A solver error in the case's terms: bodies and interfaces by name. An
/// interface whose surfaces do not overlap is "nothing to couple" (exit 1).
fn glue_failure(e: GlueError, case: &Case, path: &Path) -> Failure {
    let file = path.display();
    match e {
        GlueError::Mortar { interface, source } => {
            let what = case.interfaces[interface].describe(interface);
            match source {
                e @ seam::MortarError::NoOverlap { .. } => {
                    Failure::NoCoupling(anyhow!("{file}: {what}: {e} (check the surfaces, or max_gap)"))
                }
                e => Failure::Error(anyhow!("{file}: {what}: {e}")),
            }
        }
        GlueError::Assembly { body, source } => {
            let b = &case.bodies[body];
            Failure::Error(anyhow!(
                "{file}: body \"{}\" ({}): {source}",
                b.name,
                case.resolve(&b.mesh).display()
            ))
        }
        e => Failure::Error(anyhow!("{file}: {e}")),
    }
}

/// Interface `i`'s tractions on its slave surface's points.
fn interface_result(problem: &Problem, solution: &GluedSolution, i: usize) -> InterfaceResult {
    let f = &problem.interfaces[i];
    let s = &solution.interfaces[i];
    let surface = problem.surface(f.slave);
    let used = surface.used_points();
    let body_point: Vec<usize> = (0..used.len()).filter(|&p| used[p]).collect();
    let mut index = vec![usize::MAX; used.len()];
    for (k, &p) in body_point.iter().enumerate() {
        index[p] = k;
    }
    let points = body_point.iter().map(|&p| surface.points()[p]).collect();
    let faces = surface
        .faces()
        .iter()
        .map(|face| Face::from_nodes(&face.nodes().iter().map(|&p| index[p]).collect::<Vec<_>>()))
        .collect();
    let mesh = SurfaceMesh::new(points, faces).expect("a valid surface stays valid on its own points");
    let normals = seam::nodal_normals(surface);
    let u = &solution.displacement[f.slave.body];
    let mut r = InterfaceResult {
        mesh,
        traction: Vec::with_capacity(body_point.len()),
        normal: Vec::with_capacity(body_point.len()),
        normal_traction: Vec::with_capacity(body_point.len()),
        tangential_traction: Vec::with_capacity(body_point.len()),
        displacement: Vec::with_capacity(body_point.len()),
        constrained: Vec::with_capacity(body_point.len()),
        body_point: Vec::new(),
    };
    for &p in &body_point {
        let (t, n) = (s.traction[p], normals[p]);
        let tn = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
        r.traction.push(t);
        r.normal.push(n);
        r.normal_traction.push(tn);
        r.tangential_traction.push([t[0] - tn * n[0], t[1] - tn * n[1], t[2] - tn * n[2]]);
        r.displacement.push([u[3 * p], u[3 * p + 1], u[3 * p + 2]]);
        r.constrained.push(if s.constrained[p].iter().any(|&c| c) { 1.0 } else { 0.0 });
    }
    r.body_point = body_point;
    r
}

/// Point and cell fields of a body's VTU file.
fn body_fields(u: &[f64], s: &Stresses) -> (Vec<Field>, Vec<Field>) {
    let six = |v: &[[f64; 6]]| v.iter().flatten().copied().collect::<Vec<f64>>();
    let point = vec![
        Field::new("displacement", 3, u.to_vec()),
        Field::new("stress", 6, six(&s.nodal)),
        Field::scalars("von_mises", s.nodal_von_mises.clone()),
    ];
    let cell =
        vec![Field::new("stress", 6, six(&s.cell)), Field::scalars("von_mises", s.cell_von_mises.clone())];
    (point, cell)
}

/// Point fields of an interface's VTU file.
fn interface_fields(r: &InterfaceResult) -> Vec<Field> {
    vec![
        Field::vectors("traction", &r.traction),
        Field::scalars("normal_traction", r.normal_traction.clone()),
        Field::vectors("tangential_traction", &r.tangential_traction),
        Field::vectors("normal", &r.normal),
        Field::vectors("displacement", &r.displacement),
        Field::scalars("constrained", r.constrained.clone()),
        Field::scalars("body_point", r.body_point.iter().map(|&p| p as f64).collect()),
    ]
}

fn sum3(v: &[f64]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for (k, x) in v.iter().enumerate() {
        s[k % 3] += x;
    }
    s
}

fn norm3(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn max_norm(u: &[f64]) -> f64 {
    u.chunks_exact(3).map(|c| norm3([c[0], c[1], c[2]])).fold(0.0, f64::max)
}

fn multiplier_name(m: Multiplier) -> String {
    format!("{m:?}").to_lowercase()
}

fn summary(
    case: &Case,
    args: &SolveArgs,
    names: &OutputNames,
    problem: &Problem,
    solution: &GluedSolution,
    stresses: &[Stresses],
    seconds: Seconds,
    pool: &rayon::ThreadPool,
) -> anyhow::Result<Summary> {
    let path = args.case.as_path();
    let loads = problem.loads_and_supports().map_err(|e| anyhow!("{}: {e}", path.display()))?;
    let file_name = |p: &Path| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let mut applied_load = [0.0; 3];
    let bodies = problem
        .bodies
        .iter()
        .enumerate()
        .map(|(b, body)| {
            let load = sum3(&loads[b].0);
            let mut interface_force = [0.0; 3];
            for (f, s) in problem.interfaces.iter().zip(&solution.interfaces) {
                for k in 0..3 {
                    if f.slave.body == b {
                        interface_force[k] += s.force[k];
                    }
                    if f.master.body == b {
                        interface_force[k] -= s.force[k];
                    }
                }
            }
            for k in 0..3 {
                applied_load[k] += load[k];
            }
            BodySummary {
                name: body.name.clone(),
                mesh: case.resolve(&case.bodies[b].mesh).display().to_string(),
                file: file_name(&names.bodies[b]),
                points: body.mesh.points().len(),
                cells: body.mesh.cells().len(),
                dofs: 3 * body.mesh.points().len(),
                young: body.material.young(),
                poisson: body.material.poisson(),
                supported: problem.supports.iter().any(|s| s.boundary.body == b),
                applied_load: load,
                interface_force,
                max_displacement: max_norm(&solution.displacement[b]),
                max_von_mises: stresses[b].cell_von_mises.iter().copied().fold(0.0, f64::max),
            }
        })
        .collect();
    let interfaces: Vec<InterfaceSummary> = problem
        .interfaces
        .iter()
        .zip(&solution.interfaces)
        .enumerate()
        .map(|(i, (f, s))| InterfaceSummary {
            master: problem.surface_name(f.master),
            slave: problem.surface_name(f.slave),
            file: file_name(&names.interfaces[i]),
            multiplier: multiplier_name(f.options.multiplier),
            constrained_nodes: s.constrained.iter().filter(|c| c.iter().any(|&x| x)).count(),
            force: s.force,
            covered_fraction: s.mortar.summary.covered_area / s.mortar.summary.slave_area,
            mortar: s.mortar.summary.clone(),
        })
        .collect();
    let kinds: BTreeSet<&str> = interfaces.iter().map(|f| f.multiplier.as_str()).collect();
    let multiplier = match kinds.len() {
        0 => "none".to_string(),
        1 => kinds.first().map(|k| k.to_string()).unwrap_or_default(),
        _ => "mixed".to_string(),
    };
    let r = &solution.report;
    Ok(Summary {
        case: path.display().to_string(),
        output_dir: case.resolve(&case.output.dir).display().to_string(),
        solver: args.solver.name(),
        method: r.method,
        multiplier,
        dofs: r.dofs,
        constraints: r.constraints,
        iterations: r.iterations,
        residual: r.residual,
        applied_load,
        bodies,
        interfaces,
        seconds,
        threads: pool.current_num_threads(),
        seam_version: env!("CARGO_PKG_VERSION"),
    })
}

/// A vector as "(x, y, z)", 4 significant digits.
pub fn vector(v: [f64; 3]) -> String {
    format!("({})", v.map(crate::render::label).join(", "))
}

/// The human report of a solved case, one line per item (without indent).
pub fn report(s: &Solved) -> Vec<String> {
    let m = &s.summary;
    let mut lines = Vec::new();
    for (b, body) in m.bodies.iter().enumerate() {
        let mesh =
            Path::new(&body.mesh).file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        lines.push(format!(
            "{:<10} {:<8} {mesh}: {} cells, {} points; E = {}, ν = {}",
            if b == 0 { "bodies" } else { "" },
            body.name,
            body.cells,
            body.points,
            body.young,
            body.poisson
        ));
    }
    for f in &m.interfaces {
        lines.push(format!(
            "interface  {} (slave: {} faces, {} nodes) → {} (master: {} faces, {} nodes)",
            f.slave,
            f.mortar.slave_faces,
            f.mortar.slave_nodes,
            f.master,
            f.mortar.master_faces,
            f.mortar.master_nodes
        ));
        lines.push(format!(
            "           {} multipliers, covered {:.3} %, {} segments, max gap {:.1e}, max overlap {:.1e}",
            f.multiplier,
            100.0 * f.covered_fraction,
            f.mortar.segments,
            f.mortar.max_gap,
            f.mortar.max_overlap
        ));
    }
    let steps = if m.method.contains("CG") { "iterations" } else { "refinement steps" };
    lines.push(format!(
        "system     {} dofs, {} constraints; {}, {} {steps}, residual {:.1e}",
        m.dofs, m.constraints, m.method, m.iterations, m.residual
    ));
    for body in m.bodies.iter().filter(|b| !b.supported && norm3(b.applied_load) > 0.0) {
        let balance: [f64; 3] = std::array::from_fn(|k| body.applied_load[k] + body.interface_force[k]);
        lines.push(format!(
            "balance    {}: applied load {}, interface force {}, |sum| / |load| {:.1e}",
            body.name,
            vector(body.applied_load),
            vector(body.interface_force),
            norm3(balance) / norm3(body.applied_load)
        ));
    }
    let (b, body) = m
        .bodies
        .iter()
        .enumerate()
        .max_by(|x, y| x.1.max_displacement.total_cmp(&y.1.max_displacement))
        .expect("at least one body");
    let vm = m.bodies.iter().map(|b| b.max_von_mises).fold(0.0, f64::max);
    lines.push(format!(
        "results    max |u| {:.4e} (in {}), max von Mises {:.4e}",
        body.max_displacement, s.problem.bodies[b].name, vm
    ));
    let t = &m.seconds;
    lines.push(format!(
        "seconds    read {:.2}, assembly {:.2}, mortar {:.2}, setup {:.2}, factorization {:.2}, solve {:.2}, \
         stresses {:.2}, output {:.2}, total {:.2} on {} threads",
        t.read, t.assembly, t.mortar, t.setup, t.factorization, t.solve, t.stresses, t.output, t.total, m.threads
    ));
    let mut files: Vec<String> = m.bodies.iter().map(|b| b.file.clone()).collect();
    files.extend(m.interfaces.iter().map(|f| f.file.clone()));
    files.push("summary.json".into());
    lines.push(format!("wrote      {}", files.join(" ")));
    lines
}
