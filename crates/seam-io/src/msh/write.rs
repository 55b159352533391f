//! Writing a surface mesh as Gmsh MSH 4.1 ASCII: one surface entity carrying
//! one physical surface, all points as nodes (tags 1..=n in point order).

use seam::{Face, SurfaceMesh};
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// Writes `mesh` as MSH 4.1 ASCII with its faces in the physical surface
/// `group` (tag 1). Node tag i+1 is point i; element tags follow face order.
///
/// # Errors
/// Any I/O error of `w`.
pub fn write_msh<W: Write>(mut w: W, mesh: &SurfaceMesh, group: &str) -> io::Result<()> {
    let (lo, hi) = bounds(mesh);
    writeln!(w, "$MeshFormat\n4.1 0 8\n$EndMeshFormat")?;
    writeln!(w, "$PhysicalNames\n1\n2 1 \"{}\"\n$EndPhysicalNames", group.replace('"', "'"))?;
    writeln!(w, "$Entities\n0 0 1 0")?;
    writeln!(w, "1 {} {} {} {} {} {} 1 1 0", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2])?;
    writeln!(w, "$EndEntities")?;
    let n = mesh.n_points();
    writeln!(w, "$Nodes\n1 {n} 1 {n}\n2 1 0 {n}")?;
    for i in 1..=n {
        writeln!(w, "{i}")?;
    }
    for p in mesh.points() {
        writeln!(w, "{} {} {}", p[0], p[1], p[2])?;
    }
    writeln!(w, "$EndNodes")?;
    let tris: Vec<&Face> = mesh.faces().iter().filter(|f| matches!(f, Face::Tri3(_))).collect();
    let quads: Vec<&Face> = mesh.faces().iter().filter(|f| matches!(f, Face::Quad4(_))).collect();
    let blocks = [(2, &tris), (3, &quads)];
    let n_blocks = blocks.iter().filter(|(_, b)| !b.is_empty()).count();
    let m = mesh.n_faces();
    writeln!(w, "$Elements\n{n_blocks} {m} 1 {m}")?;
    let mut tag = 0;
    for (gmsh_type, faces) in blocks {
        if faces.is_empty() {
            continue;
        }
        writeln!(w, "2 1 {gmsh_type} {}", faces.len())?;
        for f in faces {
            tag += 1;
            write!(w, "{tag}")?;
            for &node in f.nodes() {
                write!(w, " {}", node + 1)?;
            }
            writeln!(w)?;
        }
    }
    writeln!(w, "$EndElements")?;
    w.flush()
}

/// Writes `mesh` to the file `path`; see [`write_msh`].
///
/// # Errors
/// Creating or writing the file.
pub fn write_msh_file(path: impl AsRef<Path>, mesh: &SurfaceMesh, group: &str) -> io::Result<()> {
    write_msh(BufWriter::new(File::create(path)?), mesh, group)
}

fn bounds(mesh: &SurfaceMesh) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in mesh.points() {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}
