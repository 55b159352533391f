//! `seam assemble MASTER SLAVE -o DIR`: read, search, assemble, write.

use crate::args::{AssembleArgs, CouplingArgs, FacingArg, MultiplierArg};
use crate::Failure;
use anyhow::Context;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use seam::{
    assemble_with_tree, Face, FaceTree, Facing, MaxGap, Mortar, MortarOptions, MortarSummary, Multiplier,
    Point3, Segment, SurfaceMesh,
};
use seam_case::output::Staged;
use seam_io::Field;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// Slave face count from which a progress bar is shown (on a terminal only).
const PROGRESS_FROM: usize = 20_000;

/// What `assemble` did, for callers that report on it (the examples).
pub struct Assembled {
    pub mortar: Mortar,
    pub summary: Summary,
}

/// `summary.json`: the interface totals of the library, the inputs and options,
/// and the timings.
#[derive(Serialize)]
pub struct Summary {
    pub master: String,
    pub slave: String,
    pub master_group: Option<String>,
    pub slave_group: Option<String>,
    #[serde(flatten)]
    pub interface: MortarSummary,
    pub covered_fraction: f64,
    /// 1-based rows (slave file node order) of the uncovered nodes.
    pub uncovered_slave_node_rows: Vec<usize>,
    pub max_gap_limit: String,
    pub max_angle_degrees: f64,
    pub facing: String,
    pub multiplier: String,
    pub quad_order: String,
    pub nnz: Nnz,
    pub threads: usize,
    pub seconds: Seconds,
    pub seam_version: &'static str,
}

#[derive(Serialize)]
pub struct Nnz {
    #[serde(rename = "B")]
    pub b: usize,
    #[serde(rename = "D")]
    pub d: usize,
    #[serde(rename = "T")]
    pub t: Option<usize>,
}

#[derive(Serialize, Default)]
pub struct Seconds {
    pub read: f64,
    pub search: f64,
    pub assemble: f64,
    pub write: f64,
    pub total: f64,
}

pub fn run(args: &AssembleArgs) -> Result<Assembled, Failure> {
    let start = Instant::now();
    let options = MortarOptions { record_segments: args.segments.is_some(), ..options(&args.coupling)? };
    let pool = thread_pool(args.coupling.threads)?;
    let file = |name: &str| args.output.join(name);
    let mut targets = vec![file("B.mtx"), file("D.mtx"), file("T.mtx"), file("summary.json")];
    targets.extend(args.segments.clone());
    let inputs = [args.pair.master.clone(), args.pair.slave.clone()];
    let mut out = Staged::prepare(&targets, &inputs, args.force)?;
    let mut seconds = Seconds::default();

    let t = Instant::now();
    let (master, slave) = pool.install(|| {
        rayon::join(
            || read(&args.pair.master, &args.pair.master_group),
            || read(&args.pair.slave, &args.pair.slave_group),
        )
    });
    let (master, slave) = (master?, slave?);
    seconds.read = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let tree = FaceTree::new(&master);
    seconds.search = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let bar = progress_bar(slave.n_faces());
    let mortar = pool
        .install(|| assemble_with_tree(&master, &tree, &slave, &options, &|n| bar.inc(n as u64)))
        .map_err(|e| Failure::from_coupling(e, &args.pair.slave, &args.pair.master))?;
    bar.finish_and_clear();
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
    if let Some(path) = &args.segments {
        out.write(path, |p| write_segments(p, &mortar.segments))?;
    }
    seconds.write = t.elapsed().as_secs_f64();
    seconds.total = start.elapsed().as_secs_f64();

    let summary =
        summary(args, &options, &mortar, t_matrix.map(|t| t.nnz()), pool.current_num_threads(), seconds);
    let json = serde_json::to_string_pretty(&summary).context("summary")?;
    out.write(&file("summary.json"), |p| std::fs::write(p, json + "\n"))?;
    out.commit(&[file("T.mtx")])?;
    Ok(Assembled { mortar, summary })
}

fn read(path: &Path, group: &Option<String>) -> anyhow::Result<SurfaceMesh> {
    Ok(crate::input::Surface::read(path, group.as_deref())?.mesh)
}

/// The mortar segments as a VTU triangle mesh (three points per triangle), with
/// the cell fields `slave_face` and `master_face` (0-based face indices).
fn write_segments(path: &Path, segments: &[Segment]) -> std::io::Result<()> {
    let points: Vec<Point3> = segments.iter().flat_map(|s| s.corners).collect();
    let faces = (0..segments.len()).map(|k| Face::Tri3([3 * k, 3 * k + 1, 3 * k + 2])).collect();
    let mesh = SurfaceMesh::new(points, faces).map_err(std::io::Error::other)?;
    let ids = |f: fn(&Segment) -> usize| segments.iter().map(|s| f(s) as f64).collect::<Vec<f64>>();
    let cells =
        [Field::scalars("slave_face", ids(|s| s.slave)), Field::scalars("master_face", ids(|s| s.master))];
    seam_io::write_vtu_file(path, &mesh, &[], &cells).map_err(std::io::Error::other)
}

pub fn options(args: &CouplingArgs) -> anyhow::Result<MortarOptions> {
    let max_gap = match args.max_gap {
        Some(g) if !(g.is_finite() && g >= 0.0) => {
            anyhow::bail!("--max-gap must be a non-negative length, got {g}")
        }
        Some(g) => MaxGap::Absolute(g),
        None => MaxGap::DEFAULT,
    };
    Ok(MortarOptions {
        multiplier: match args.multiplier {
            MultiplierArg::Standard => Multiplier::Standard,
            MultiplierArg::Dual => Multiplier::Dual,
            MultiplierArg::Lumped => Multiplier::Lumped,
        },
        facing: match args.facing {
            FacingArg::Any => Facing::Any,
            FacingArg::Opposite => Facing::Opposite,
        },
        max_gap,
        max_angle_degrees: args.max_angle,
        warped_quad_degree: args.quad_order,
        record_segments: false,
    })
}

/// The worker threads of a run: `--threads` checked against the cores
/// ([`seam_case::threads`]), or all cores.
pub fn thread_pool(threads: Option<usize>) -> anyhow::Result<rayon::ThreadPool> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        let n = seam_case::threads::check_threads(n).map_err(|e| anyhow::anyhow!("--threads: {e}"))?;
        builder = builder.num_threads(n);
    }
    builder.build().context("cannot start the worker threads")
}

fn progress_bar(faces: usize) -> ProgressBar {
    if faces < PROGRESS_FROM {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(faces as u64), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} slave faces, {per_sec}, {eta} left")
            .expect("valid template"),
    );
    bar
}

fn summary(
    args: &AssembleArgs,
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
        quad_order: options.warped_quad_degree.map_or("per face".into(), |d| d.to_string()),
        nnz: Nnz { b: mortar.b.nnz(), d: mortar.d.nnz(), t: nnz_t },
        threads,
        seconds,
        seam_version: env!("CARGO_PKG_VERSION"),
    }
}
