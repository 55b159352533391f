//! Command-line definitions (clap derive); help texts live on the flags.

use clap::{Args, Parser, Subcommand, ValueEnum};
use seam::{Facing, Multiplier};
use seam_case::solve::LinearSolver;
use seam_case::transfer::Mode;
use seam_examples::bench::Shape;
use std::path::PathBuf;

/// Mortar coupling between non-matching warped interfaces: the operators
/// D_pq = ∫ψ_p λ^s_q, B_pq = ∫ψ_p (λ^m_q∘Φ) and T = D⁻¹B, after Dickopf & Krause.
#[derive(Parser)]
#[command(name = "seam", version, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    /// Assemble B, D (and T) between a master and a slave surface mesh.
    Assemble(AssembleArgs),
    /// Move a field (or a load) from one surface mesh to the other.
    Transfer(TransferArgs),
    /// Report on how two surfaces meet: coverage, gaps, orientation, face
    /// quality and the invariants of the assembled operator.
    Check(CheckArgs),
    /// Solve a linear-elasticity problem described by a case file (TOML):
    /// bodies glued or in contact through their interfaces (frictionless, or
    /// with Coulomb friction over load steps), Dirichlet conditions and
    /// tractions.
    Solve(SolveArgs),
    /// Run a built-in example that makes its own meshes.
    Example(ExampleArgs),
    /// Benchmark the assembly on generated meshes and print a Markdown table
    /// (build with --release).
    Bench(BenchArgs),
    /// One benchmark case as a JSON line (used by `bench`, one process per case).
    #[command(hide = true)]
    BenchCase(BenchCaseArgs),
    /// Benchmark `seam transfer` end to end on the cylinder problem (binary
    /// VTU files) and print seconds per phase as a Markdown table (build with
    /// --release).
    BenchTransfer(BenchTransferArgs),
}

/// How the two surfaces are coupled: the options `assemble`, `transfer` and
/// `check` share.
#[derive(Args, Debug, Clone)]
pub struct CouplingArgs {
    /// Lagrange multiplier basis.
    #[arg(long, value_enum, default_value_t)]
    pub multiplier: Multiplier,
    /// Largest normal distance between paired points, as a length
    /// [default: half the diameter of each slave face].
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    pub max_gap: Option<f64>,
    /// Which normal orientations may be paired.
    #[arg(long, value_enum, default_value_t)]
    pub facing: Facing,
    /// Largest angle between slave and master face normals, in degrees.
    #[arg(long, value_name = "DEG", default_value_t = 45.0, allow_negative_numbers = true)]
    pub max_angle: f64,
    /// Triangle-rule degree on warped slave quads (1..=20) [default: chosen per
    /// face so that its integrals agree with degree 20 to 1e-13]. Triangles and
    /// planar quads always use exact rules.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub quad_order: Option<usize>,
    /// Worker threads, at most 4 per core [default: all cores].
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub threads: Option<usize>,
}

/// The two surfaces to couple.
#[derive(Args, Debug, Clone)]
pub struct PairArgs {
    /// Master (mortar) surface: a Gmsh MSH file (2.2 or 4.1, ASCII or binary), an
    /// Abaqus/CalculiX input file (.inp) or a VTU file.
    pub master: PathBuf,
    /// Slave (non-mortar) surface, MSH, .inp or VTU; rows of B and D follow its nodes.
    pub slave: PathBuf,
    /// Physical surface of the master file (MSH), by name or number, or its
    /// *SURFACE (.inp) (default: all surface elements, or the boundary of the
    /// volume mesh).
    #[arg(long, value_name = "G")]
    pub master_group: Option<String>,
    /// Physical surface of the slave file (MSH) or its *SURFACE (.inp).
    #[arg(long, value_name = "G")]
    pub slave_group: Option<String>,
}

#[derive(Args, Debug)]
pub struct AssembleArgs {
    #[command(flatten)]
    pub pair: PairArgs,
    /// Output directory for B.mtx, D.mtx, T.mtx (dual, lumped) and summary.json.
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    #[command(flatten)]
    pub coupling: CouplingArgs,
    /// Also write the intersection triangles (mortar segments) on the slave
    /// side, with their slave and master face ids, as a VTU file.
    #[arg(long, value_name = "FILE.vtu")]
    pub segments: Option<PathBuf>,
    /// Overwrite output files that already exist.
    #[arg(long)]
    pub force: bool,
}

#[derive(Args, Debug)]
#[command(group(clap::ArgGroup::new("values").required(true).args(["field", "expr"])))]
pub struct TransferArgs {
    /// The surface that carries the field: a Gmsh MSH file (fields from its
    /// $NodeData), an Abaqus .inp file (--expr only) or a VTU file (fields
    /// from its point data).
    pub source: PathBuf,
    /// The surface that receives it: a Gmsh MSH, .inp or VTU file.
    pub target: PathBuf,
    /// Output: the target surface with the transferred field, `coverage` and
    /// `normal_gap`, as VTU; a summary is written beside it as OUT.json.
    #[arg(short, long, value_name = "OUT.vtu")]
    pub output: PathBuf,
    /// The field of SOURCE to transfer (scalar or vector).
    #[arg(long, value_name = "NAME")]
    pub field: Option<String>,
    /// Instead of a field: an expression in x, y, z evaluated at the source
    /// nodes, e.g. "sin(x)*y + z"; the summary reports the L2 error on the
    /// target against the same expression.
    #[arg(long, value_name = "EXPR")]
    pub expr: Option<String>,
    /// Name of the transferred field given by --expr.
    #[arg(long, value_name = "NAME", default_value = "f")]
    pub name: String,
    /// Consistent (values) or conservative (loads) transfer.
    #[arg(long, value_enum, default_value_t)]
    pub mode: Mode,
    /// Physical surface of SOURCE (MSH), by name or number, or its *SURFACE (.inp).
    #[arg(long, value_name = "G")]
    pub source_group: Option<String>,
    /// Physical surface of TARGET (MSH), by name or number, or its *SURFACE (.inp).
    #[arg(long, value_name = "G")]
    pub target_group: Option<String>,
    #[command(flatten)]
    pub coupling: CouplingArgs,
    /// Overwrite output files that already exist.
    #[arg(long)]
    pub force: bool,
}

#[derive(Args, Debug)]
pub struct CheckArgs {
    #[command(flatten)]
    pub pair: PairArgs,
    #[command(flatten)]
    pub coupling: CouplingArgs,
    /// Write the per-node coverage and normal gap on the slave surface as VTU.
    #[arg(long, value_name = "FILE.vtu")]
    pub vtu: Option<PathBuf>,
    /// Write the report as JSON.
    #[arg(long, value_name = "FILE.json")]
    pub json: Option<PathBuf>,
    /// Exit with code 3 when the coverage is incomplete or an invariant is violated.
    #[arg(long)]
    pub strict: bool,
    /// Overwrite output files that already exist.
    #[arg(long)]
    pub force: bool,
}

#[derive(Args, Debug, Clone)]
pub struct SolveArgs {
    /// The case file (TOML; schema in the README). Meshes and the output
    /// directory are relative to its directory.
    pub case: PathBuf,
    /// How the linear systems (glued, or each active-set step of contact) are solved.
    #[arg(long, value_enum, default_value_t)]
    pub solver: LinearSolver,
    /// PCG and PETSc: stop when ‖r‖₂ ≤ RTOL ‖b‖₂ (PETSc: in its KSP's norm).
    #[arg(long, default_value_t = 1e-10, value_name = "RTOL", allow_negative_numbers = true)]
    pub rtol: f64,
    /// PETSc options, as on PETSc's command line (after those of
    /// PETSC_OPTIONS), e.g. "-pc_type hypre -ksp_monitor" or "-log_view".
    #[arg(long, value_name = "OPTIONS", allow_hyphen_values = true)]
    pub petsc_options: Option<String>,
    /// Overwrite output files that already exist.
    #[arg(long)]
    pub force: bool,
    /// Worker threads, at most 4 per core [default: all cores].
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub threads: Option<usize>,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ExampleName {
    /// A quad patch on a twisted barrel (warped quads) against an
    /// unstructured triangle patch 0.2 % farther out: writes both meshes,
    /// assembles B, D, T and reports coverage, invariants and timings.
    Operator,
    /// Two hexahedral blocks glued at a warped interface z = 1/2 + 0.1 sin 2πx
    /// sin πy, the upper (slave) side 8× coarser than the lower (master) side
    /// (the paper's Fig. 2): writes the meshes and a case file, solves it as
    /// `seam solve` does, and draws the result as a PNG picture.
    WarpedGlue,
    /// Two hexahedral blocks with Gaussian bulges on their facing sides,
    /// touching at one point, pressed together and sheared by a prescribed
    /// displacement of the upper top: frictionless contact with lumped
    /// multipliers (the paper's Fig. 3). Writes the meshes and a case file,
    /// solves it as `seam solve` does, and draws the initial geometry, von
    /// Mises stress on two cuts and the contact pressure as a PNG picture.
    BulgingContact,
    /// A quarter model of an elastic indenter with a spherical face (R = 1)
    /// pressed by a force on an elastic block: solves the contact case as
    /// `seam solve` does and compares the contact radius, peak pressure and
    /// force with Hertz's solution (hertz.md, hertz.csv, hertz.png).
    Hertz,
    /// A half model of the Hertz indenter and block (equal materials,
    /// friction μ = 0.3) pressed by P, then pushed sideways by Q = 0.5 μP in
    /// load steps: compares the stick radius and the tangential traction with
    /// Cattaneo and Mindlin's solution (cattaneo-mindlin.md, .csv, .png).
    CattaneoMindlin,
    /// Finite deformation with large sliding (after Puso & Laursen 2004): a
    /// neo-Hookean indenter with a cylindrical face pressed into a softer
    /// neo-Hookean slab and slid three times its width along it, frictionless
    /// and with μ = 0.3: both cases and their results (frictionless/,
    /// friction/), the contact forces over the load steps (ironing.md,
    /// ironing.csv) and a picture of them and of the deformed bodies
    /// (ironing.png).
    Ironing,
}

#[derive(Args, Debug)]
pub struct ExampleArgs {
    /// Which example.
    #[arg(value_enum)]
    pub name: ExampleName,
    /// Output directory.
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Overwrite output files that already exist in DIR.
    #[arg(long)]
    pub force: bool,
    /// Worker threads, at most 4 per core [default: all cores].
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub threads: Option<usize>,
    /// warped-glue: h_s/h_m, the master (lower) side's refinement over the
    /// slave (upper) side's (for tests and quick runs).
    #[arg(long, hide = true, value_name = "N")]
    pub ratio: Option<usize>,
    /// warped-glue, bulging-contact: slave cells across x and y; hertz:
    /// slave cells across the uniform zone [0, 1.5a], cattaneo-mindlin
    /// across [0, 1.1a]; ironing: indenter cells across (for tests and quick
    /// runs).
    #[arg(long, hide = true, value_name = "N")]
    pub slave_cells: Option<usize>,
    /// warped-glue: element order, 1 (Hex8) or 2 (Hex27 bodies with curved
    /// Quad9 interface faces, at the same numbers of nodes).
    #[arg(long, value_name = "1|2")]
    pub order: Option<usize>,
}

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Surfaces.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [Shape::Flat, Shape::Cylinder])]
    pub shapes: Vec<Shape>,
    /// Approximate numbers of slave faces (of master faces for coarse-slave).
    #[arg(long, value_delimiter = ',', default_values_t = [10_000, 100_000, 1_000_000])]
    pub sizes: Vec<usize>,
    /// Thread counts.
    #[arg(long, value_delimiter = ',', default_values_t = [1, 2])]
    pub threads: Vec<usize>,
}

#[derive(Args, Debug)]
pub struct BenchCaseArgs {
    #[arg(long, value_enum)]
    pub shape: Shape,
    #[arg(long)]
    pub faces: usize,
    #[arg(long)]
    pub threads: usize,
}

#[derive(Args, Debug)]
pub struct BenchTransferArgs {
    /// Approximate numbers of target faces.
    #[arg(long, value_delimiter = ',', default_values_t = [10_000, 100_000, 200_000])]
    pub sizes: Vec<usize>,
    /// Modes.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [Mode::Consistent, Mode::Conservative])]
    pub modes: Vec<Mode>,
    /// Multipliers.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [Multiplier::Standard, Multiplier::Dual])]
    pub multipliers: Vec<Multiplier>,
    /// Thread counts.
    #[arg(long, value_delimiter = ',', default_values_t = [1, 2])]
    pub threads: Vec<usize>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use seam::Named;

    /// One name per value: clap's (the command line), serde's (case files,
    /// where the enum is read) and `Named::name` (summaries, Python) agree.
    fn names_agree<T: Named + ValueEnum + PartialEq + std::fmt::Debug>() {
        for &v in T::ALL {
            let clap = v.to_possible_value().map(|p| p.get_name().to_string());
            assert_eq!(clap.as_deref(), Some(v.name()), "{v:?}");
            assert_eq!(T::from_name(v.name()), Ok(v));
            assert_eq!(<T as ValueEnum>::from_str(v.name(), false), Ok(v));
        }
        assert_eq!(T::value_variants().len(), T::ALL.len());
        let e = T::from_name("nonsense").unwrap_err().to_string();
        assert!(e.starts_with(&format!("unknown {} \"nonsense\": expected \"", T::WHAT)), "{e}");
    }

    #[test]
    fn option_names_are_one_vocabulary() {
        names_agree::<Multiplier>();
        names_agree::<Facing>();
        names_agree::<Mode>();
        names_agree::<LinearSolver>();
        for &m in Multiplier::ALL {
            let read: Multiplier = serde_json::from_str(&format!("\"{}\"", m.name())).unwrap();
            assert_eq!(read, m);
        }
        for &f in Facing::ALL {
            let read: Facing = serde_json::from_str(&format!("\"{}\"", f.name())).unwrap();
            assert_eq!(read, f);
        }
        assert_eq!(
            Multiplier::from_name("mortar").unwrap_err().to_string(),
            r#"unknown multiplier "mortar": expected "standard", "dual" or "lumped""#
        );
    }
}
