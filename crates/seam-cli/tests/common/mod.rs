//! Helpers shared by the integration tests: running the binary and reading
//! what it leaves.

use std::path::Path;
use std::process::{Command, Output};

/// Runs `seam ARGS` in `cwd`.
pub fn seam(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_seam"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the seam binary runs")
}

/// Its standard error, as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A JSON file.
#[allow(dead_code)] // not every test crate reads JSON
pub fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Writes an nx × ny × nz hexahedral block mapped by `map` (from the unit cube)
/// as a Gmsh file with the named sides as physical surfaces.
#[allow(dead_code)] // not every test crate writes meshes
pub fn write_block(
    path: &Path,
    n: [usize; 3],
    map: impl Fn(f64, f64, f64) -> [f64; 3],
    sides: &[(&str, seam_fem::generate::Side)],
) {
    write_block_of(path, (n, seam_fem::generate::BlockKind::Hex, false), map, sides);
}

/// [`write_block`] of `kind` cells, raised to (serendipity) second order
/// with `second_order`.
#[allow(dead_code)] // not every test crate writes Tet10 blocks
pub fn write_block_of(
    path: &Path,
    (n, kind, second_order): ([usize; 3], seam_fem::generate::BlockKind, bool),
    map: impl Fn(f64, f64, f64) -> [f64; 3],
    sides: &[(&str, seam_fem::generate::Side)],
) {
    use seam_fem::generate::{block, raise_order, Grid};
    let mut mesh = block(n[0], n[1], n[2], map, kind);
    if second_order {
        mesh = raise_order(&mesh, false).unwrap();
    }
    let grid = Grid::new(n[0], n[1], n[2]);
    let surfaces: Vec<(&str, seam::SurfaceMesh)> =
        sides.iter().map(|&(name, side)| (name, grid.side_faces(&mesh, side).unwrap())).collect();
    let refs: Vec<(&str, &seam::SurfaceMesh)> = surfaces.iter().map(|(n, s)| (*n, s)).collect();
    seam_io::write_volume_msh_file(path, &mesh, "body", &refs).unwrap();
}

/// Points and the named point (or cell) field of a VTU file, or of every
/// piece of a parallel one (`.pvtu`) one after the other, through vtkio.
#[allow(dead_code)] // not every test crate reads VTU files
pub fn vtu_field(path: &Path, name: &str, cell: bool) -> (Vec<[f64; 3]>, Vec<f64>) {
    use vtkio::model::{Attribute, DataSet, Piece};
    let mut vtk = vtkio::Vtk::import(path).unwrap();
    vtk.load_all_pieces().unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else { panic!("not an unstructured grid") };
    let (mut points, mut values) = (Vec::new(), Vec::new());
    for piece in pieces {
        let Piece::Inline(piece) = piece else { panic!("not inline") };
        let xyz: Vec<f64> = piece.points.cast_into().unwrap();
        points.extend(xyz.chunks(3).map(|c| [c[0], c[1], c[2]]));
        let attributes = if cell { &piece.data.cell } else { &piece.data.point };
        values.extend(
            attributes
                .iter()
                .find_map(|a| match a {
                    Attribute::DataArray(d) if d.name == name => {
                        Some(d.data.clone().cast_into::<f64>().unwrap())
                    }
                    _ => None,
                })
                .unwrap_or_else(|| panic!("{} has no field {name}", path.display())),
        );
    }
    (points, values)
}

/// The meshes of [`stacked_case`]: lower.msh, a 3×3×2 block of [0, 1]² ×
/// [0, 1/2] (surfaces bottom, top, xmin, ymin), and upper.msh, a 2×2×2
/// block of [0, 1]² × [1/2, 1] graded in x (bottom, top).
#[allow(dead_code)] // not every test crate solves cases
pub fn write_stacked_blocks(dir: &Path) {
    use seam_fem::generate::Side;
    let lower_sides =
        [("bottom", Side::ZMin), ("top", Side::ZMax), ("xmin", Side::XMin), ("ymin", Side::YMin)];
    write_block(&dir.join("lower.msh"), [3, 3, 2], |u, v, w| [u, v, 0.5 * w], &lower_sides);
    let upper_sides = [("bottom", Side::ZMin), ("top", Side::ZMax)];
    write_block(
        &dir.join("upper.msh"),
        [2, 2, 2],
        |u, v, w| [0.7 * u + 0.3 * u * u, v, 0.5 + 0.5 * w],
        &upper_sides,
    );
}

/// A case file's text for two blocks, "lower" (lower.msh) and "upper"
/// (upper.msh), with materials (E, ν), coupled at lower:top (master) and
/// upper:bottom (slave) by an interface with the keys `interface` (kind,
/// multiplier), the lower block on rollers at lower:bottom (uz), lower:xmin
/// (ux) and lower:ymin (uy), and then `rest`.
#[allow(dead_code)] // not every test crate solves cases
pub fn stacked_case(lower: (f64, f64), upper: (f64, f64), interface: &str, rest: &str) -> String {
    let ((e1, nu1), (e2, nu2)) = (lower, upper);
    format!(
        r#"
[[body]]
name = "lower"
mesh = "lower.msh"
young = {e1:?}
poisson = {nu1:?}

[[body]]
name = "upper"
mesh = "upper.msh"
young = {e2:?}
poisson = {nu2:?}

[[interface]]
master = "lower:top"
slave = "upper:bottom"
{interface}

[[dirichlet]]
boundary = "lower:bottom"
uz = 0.0

[[dirichlet]]
boundary = "lower:xmin"
ux = 0.0

[[dirichlet]]
boundary = "lower:ymin"
uy = 0.0

{rest}"#
    )
}

/// Each (case text, message): `seam solve` on it, as bad.toml in `dir`, exits
/// with code 2 and one line on stderr that names the file and holds the
/// message, and writes no output directory.
#[allow(dead_code)] // not every test crate solves cases
pub fn assert_rejected(dir: &Path, cases: &[(String, &str)]) {
    for (text, problem) in cases {
        std::fs::write(dir.join("bad.toml"), text).unwrap();
        let o = seam(&["solve", "bad.toml"], dir);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{problem}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
        assert!(err.contains("bad.toml"), "names the case file: {err}");
        assert!(err.contains(problem), "expected '{problem}' in: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(!dir.join("out").exists(), "{problem}: nothing written");
    }
}
