//! The pipeline of `seam assemble MASTER SLAVE -o DIR`: read the two
//! surfaces, search, assemble the mortar operator and write `B.mtx`, `D.mtx`,
//! `T.mtx` (when D is diagonal), `Q.mtx` (the slave basis transformation of
//! dual multipliers on second-order faces) and `summary.json` all-or-nothing
//! ([`Staged`]), optionally the mortar segments as VTU.

pub use crate::input::Pair;
use crate::output::Staged;
use crate::Failure;
use anyhow::Context;
use seam::{
    assemble_with_tree, Face, FaceTree, MaxGap, Mortar, MortarOptions, MortarSummary, Point3, Segment,
    SurfaceMesh,
};
use seam_io::Field;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What to assemble and where to write it.
#[derive(Clone, Debug)]
pub struct Assemble {
    /// The two surfaces.
    pub pair: Pair,
    /// The output directory.
    pub output: PathBuf,
    /// The mortar options (`record_segments` is set from `segments`).
    pub options: MortarOptions,
    /// Where to write the mortar segments (VTU), if anywhere.
    pub segments: Option<PathBuf>,
    /// Replace existing outputs.
    pub force: bool,
}

/// Progress of the assembly, reported per batch of slave faces.
pub trait Progress: Sync {
    /// The assembly starts on `slave_faces` faces.
    fn start(&self, slave_faces: usize);
    /// `faces` more slave faces are done.
    fn advance(&self, faces: usize);
    /// The assembly is over.
    fn finish(&self);
}

/// No progress report.
impl Progress for () {
    fn start(&self, _: usize) {}
    fn advance(&self, _: usize) {}
    fn finish(&self) {}
}

/// What the assembly did, for callers that report on it.
pub struct Assembled {
    /// The operator.
    pub mortar: Mortar,
    /// What `summary.json` holds.
    pub summary: Summary,
}

/// `summary.json`: the interface totals of the library, the inputs and options,
/// and the timings.
#[derive(Serialize)]
pub struct Summary {
    /// The master file.
    pub master: String,
    /// The slave file.
    pub slave: String,
    /// The master's physical surface.
    pub master_group: Option<String>,
    /// The slave's physical surface.
    pub slave_group: Option<String>,
    /// The library's interface totals.
    #[serde(flatten)]
    pub interface: MortarSummary,
    /// Covered area over slave area.
    pub covered_fraction: f64,
    /// 1-based rows (slave file node order) of the uncovered nodes.
    pub uncovered_slave_node_rows: Vec<usize>,
    /// The gap limit, as a length or relative to the slave face diameter.
    pub max_gap_limit: String,
    /// The angle limit between facing normals.
    pub max_angle_degrees: f64,
    /// Which faces pair: "any" or "opposite".
    pub facing: String,
    /// The multiplier space.
    pub multiplier: String,
    /// The slave basis D and B are written in: "lagrange" (nodal), or for
    /// dual multipliers on slave surfaces with Tri6 or Quad8 faces "transformed": λ̃ = Q λ
    /// (Popp et al. 2012, α = `seam::BASIS_ALPHA`, or `seam::TRI6_ALPHA` on
    /// surfaces of Tri6 faces), Q in `Q.mtx`, and the
    /// nodal transfer T = Qᵀ D⁻¹ B in `T.mtx`.
    pub slave_basis: &'static str,
    /// The quadrature degree of warped quads, or "per face".
    pub quad_order: String,
    /// Stored entries of B, D and T.
    pub nnz: Nnz,
    /// Worker threads.
    pub threads: usize,
    /// Wall-clock seconds per stage.
    pub seconds: Seconds,
    /// Processes (MPI ranks) the operator was assembled on; absent for one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ranks: Option<usize>,
    /// What each rank did, rank 0 first; absent for one process.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_rank: Option<Vec<RankReport>>,
    /// The version of seam that wrote it.
    pub seam_version: &'static str,
}

/// What one rank did (`summary.json`'s `per_rank`).
#[derive(Serialize, Clone, Debug, Default, PartialEq)]
pub struct RankReport {
    /// Slave faces it assembled.
    pub slave_faces: usize,
    /// Master faces it received for its region (ghosts: it owns none).
    pub ghost_master_faces: usize,
    /// Bytes it received (its part of both surfaces).
    pub bytes_received: u64,
    /// Bytes it sent (its faces' blocks).
    pub bytes_sent: u64,
    /// Seconds it spent assembling its part.
    pub seconds: f64,
    /// Its peak resident memory in MB (10⁶ bytes; rank 0's when it writes
    /// the summary, the others' when they hand their blocks over); absent
    /// where unknown (not Linux).
    pub peak_memory_mb: Option<f64>,
}

/// Where the operator is assembled: in this process ([`Here`]), or by parts
/// on other processes (the binary's MPI ranks, with [`seam::parts`]).
pub trait Assembler {
    /// (A1)–(D5) for `slave` against `master` (searched by `tree`), and
    /// what each rank did when there were several.
    ///
    /// # Errors
    /// The operator's own error (the surfaces do not couple, …), or a process
    /// of the assembly that failed.
    fn assemble(
        &self,
        master: &SurfaceMesh,
        tree: &FaceTree,
        slave: &SurfaceMesh,
        options: &MortarOptions,
        progress: &dyn Progress,
    ) -> Result<(Mortar, Option<Vec<RankReport>>), AssemblerError>;
}

/// Why an [`Assembler`] produced no operator.
#[derive(Debug, thiserror::Error)]
pub enum AssemblerError {
    /// The operator's own error: no overlap, bad options, …
    #[error(transparent)]
    Mortar(#[from] seam::MortarError),
    /// A process of the assembly failed (one line).
    #[error("{0}")]
    Process(String),
}

/// The operator assembled in this process, on the current rayon pool.
pub struct Here;

impl Assembler for Here {
    fn assemble(
        &self,
        master: &SurfaceMesh,
        tree: &FaceTree,
        slave: &SurfaceMesh,
        options: &MortarOptions,
        progress: &dyn Progress,
    ) -> Result<(Mortar, Option<Vec<RankReport>>), AssemblerError> {
        Ok((assemble_with_tree(master, tree, slave, options, &|n| progress.advance(n))?, None))
    }
}

/// Stored entries of the matrices.
#[derive(Serialize)]
pub struct Nnz {
    #[serde(rename = "B")]
    /// Of B.
    pub b: usize,
    #[serde(rename = "D")]
    /// Of D.
    pub d: usize,
    #[serde(rename = "T")]
    /// Of T, when written.
    pub t: Option<usize>,
}

/// Wall-clock seconds per stage.
#[derive(Serialize, Default)]
pub struct Seconds {
    /// Reading the meshes.
    pub read: f64,
    /// Building the search tree.
    pub search: f64,
    /// Assembling B, D and T.
    pub assemble: f64,
    /// Writing the matrices.
    pub write: f64,
    /// The whole run.
    pub total: f64,
}

/// Reads, searches, assembles and writes (module doc) on the current rayon
/// pool; `progress` hears of the assembly.
///
/// # Errors
/// [`Failure::NoCoupling`] when the surfaces do not overlap; anything else
/// (unreadable input, existing output without `force`, a non-finite T) is a
/// [`Failure::Error`] naming the file.
pub fn assemble_files(args: &Assemble, progress: &dyn Progress) -> Result<Assembled, Failure> {
    assemble_files_with(args, progress, &Here)
}

/// [`assemble_files`] with the operator from `assembler`: the same files,
/// byte for byte, wherever it is assembled.
///
/// # Errors
/// See [`assemble_files`].
pub fn assemble_files_with(
    args: &Assemble,
    progress: &dyn Progress,
    assembler: &dyn Assembler,
) -> Result<Assembled, Failure> {
    let start = Instant::now();
    let options = MortarOptions { record_segments: args.segments.is_some(), ..args.options };
    let file = |name: &str| args.output.join(name);
    let mut targets = vec![file("B.mtx"), file("D.mtx"), file("T.mtx"), file("Q.mtx"), file("summary.json")];
    targets.extend(args.segments.clone());
    let inputs = [args.pair.master.clone(), args.pair.slave.clone()];
    let mut out = Staged::prepare(&targets, &inputs, args.force)?;
    let mut seconds = Seconds::default();

    let t = Instant::now();
    let (master, slave) = rayon::join(
        || read(&args.pair.master, &args.pair.master_group),
        || read(&args.pair.slave, &args.pair.slave_group),
    );
    let (master, slave) = (master?, slave?);
    seconds.read = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let tree = FaceTree::new(&master);
    seconds.search = t.elapsed().as_secs_f64();

    let t = Instant::now();
    progress.start(slave.n_faces());
    let (mortar, per_rank) =
        assembler.assemble(&master, &tree, &slave, &options, progress).map_err(|e| match e {
            AssemblerError::Mortar(e) => Failure::from_coupling(e, &args.pair.slave, &args.pair.master),
            AssemblerError::Process(message) => Failure::Error(message),
        })?;
    progress.finish();
    // T is written when D is diagonal (dual, lumped); for standard multipliers it
    // is dense and never formed, so no factorisation is spent on it here.
    let transfer = match mortar.d.is_diagonal() {
        true => Some(mortar.transfer().context("the transfer operator")?),
        false => None,
    };
    let t_matrix = transfer.as_ref().and_then(|t| t.matrix());
    if let Some(row) = t_matrix.and_then(seam::CsrMatrix::first_non_finite_row) {
        let e = anyhow::anyhow!(
            "{}: T = D⁻¹B is not finite in row {} (a vanishing D entry): nothing non-finite is written",
            args.pair.slave.display(),
            row + 1
        );
        return Err(e.into());
    }
    seconds.assemble = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let rows = format!("rows: nodes of {} in file order", args.pair.slave.display());
    let cols = |side: &Path| format!("columns: nodes of {} in file order", side.display());
    out.write(&file("B.mtx"), |p| {
        seam_io::write_matrix_market_file(p, &mortar.b, &[&rows, &cols(&args.pair.master)])
    })?;
    out.write(&file("D.mtx"), |p| {
        seam_io::write_matrix_market_file(p, &mortar.d, &[&rows, &cols(&args.pair.slave)])
    })?;
    if let Some(t) = t_matrix {
        out.write(&file("T.mtx"), |p| {
            seam_io::write_matrix_market_file(p, t, &[&rows, &cols(&args.pair.master)])
        })?;
    }
    if let Some(q) = &mortar.basis {
        let q_rows =
            format!("rows: transformed slave basis functions, by the node of {}", args.pair.slave.display());
        out.write(&file("Q.mtx"), |p| {
            seam_io::write_matrix_market_file(p, q, &[&q_rows, &cols(&args.pair.slave)])
        })?;
    }
    if let Some(path) = &args.segments {
        out.write(path, |p| write_segments(p, &mortar.segments))?;
    }
    seconds.write = t.elapsed().as_secs_f64();
    seconds.total = start.elapsed().as_secs_f64();

    let mut summary =
        summary(args, &options, &mortar, t_matrix.map(|t| t.nnz()), rayon::current_num_threads(), seconds);
    let mut per_rank = per_rank;
    if let Some(rank0) = per_rank.as_mut().and_then(|r| r.first_mut()) {
        rank0.peak_memory_mb = crate::process::peak_memory_mb();
    }
    (summary.ranks, summary.per_rank) = (per_rank.as_ref().map(Vec::len), per_rank);
    let json = serde_json::to_string_pretty(&summary).context("summary")?;
    out.write(&file("summary.json"), |p| std::fs::write(p, json + "\n"))?;
    out.commit(&[file("T.mtx"), file("Q.mtx")])?;
    Ok(Assembled { mortar, summary })
}

fn read(path: &Path, group: &Option<String>) -> anyhow::Result<SurfaceMesh> {
    Ok(crate::input::Surface::read(path, group.as_deref())?.mesh)
}

/// The mortar segments as a VTU triangle mesh (three points per triangle), with
/// the cell fields `slave_face` and `master_face` (0-based face indices).
/// Segments of zero area (slivers of round-off size, which nearly matching
/// meshes make and which carry nothing) are left out.
fn write_segments(path: &Path, segments: &[Segment]) -> std::io::Result<()> {
    let segments: Vec<Segment> =
        segments.iter().copied().filter(|s| seam::is_proper_face(&s.corners)).collect();
    let points: Vec<Point3> = segments.iter().flat_map(|s| s.corners).collect();
    let faces = (0..segments.len()).map(|k| Face::Tri3([3 * k, 3 * k + 1, 3 * k + 2])).collect();
    let mesh = SurfaceMesh::new(points, faces).map_err(std::io::Error::other)?;
    let ids = |f: fn(&Segment) -> usize| segments.iter().map(|s| f(s) as f64).collect::<Vec<f64>>();
    let cells =
        [Field::scalars("slave_face", ids(|s| s.slave)), Field::scalars("master_face", ids(|s| s.master))];
    seam_io::write_vtu_file(path, &mesh, &[], &cells).map_err(std::io::Error::other)
}

fn summary(
    args: &Assemble,
    options: &MortarOptions,
    mortar: &Mortar,
    nnz_t: Option<usize>,
    threads: usize,
    seconds: Seconds,
) -> Summary {
    let s = &mortar.summary;
    Summary {
        master: args.pair.master.display().to_string(),
        slave: args.pair.slave.display().to_string(),
        master_group: args.pair.master_group.clone(),
        slave_group: args.pair.slave_group.clone(),
        interface: s.clone(),
        covered_fraction: s.covered_area / s.slave_area,
        uncovered_slave_node_rows: mortar.uncovered_nodes().iter().map(|p| p + 1).collect(),
        max_gap_limit: match options.max_gap {
            MaxGap::Absolute(g) => format!("{g}"),
            MaxGap::Relative(f) => format!("{f} × slave face diameter"),
        },
        max_angle_degrees: options.max_angle_degrees,
        facing: format!("{:?}", options.facing).to_lowercase(),
        multiplier: format!("{:?}", options.multiplier).to_lowercase(),
        slave_basis: if mortar.basis.is_some() { "transformed" } else { "lagrange" },
        quad_order: options.warped_quad_degree.map_or("per face".into(), |d| d.to_string()),
        nnz: Nnz { b: mortar.b.nnz(), d: mortar.d.nnz(), t: nnz_t },
        threads,
        seconds,
        ranks: None,
        per_rank: None,
        seam_version: env!("CARGO_PKG_VERSION"),
    }
}
