//! Writing Gmsh MSH 4.1 ASCII: a surface mesh as one physical surface
//! ([`write_msh`]), or a volume mesh as one physical volume with named physical
//! surfaces on its boundary ([`write_volume_msh`]). All points are nodes, tags
//! 1..=n in point order; elements keep their order, with tags from 1.
//! Coordinates are printed in Rust's shortest round-trip form, so a mesh read
//! back has bit-for-bit the same points.

use seam::{Cell, Face, Point3, SurfaceMesh, VolumeMesh};
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// Writes `mesh` as MSH 4.1 ASCII with its faces in the physical surface
/// `group` (tag 1). Node tag i+1 is point i; element tags follow face order.
///
/// # Errors
/// Any I/O error of `w`; [`io::ErrorKind::InvalidInput`] for a face kind Gmsh
/// does not have (Tri7).
pub fn write_msh<W: Write>(w: W, mesh: &SurfaceMesh, group: &str) -> io::Result<()> {
    let surface = Entity { dim: 2, name: group.to_string(), blocks: face_blocks(mesh.faces())? };
    write_entities(w, mesh.points(), &[surface])
}

/// Writes `mesh` to the file `path`; see [`write_msh`].
///
/// # Errors
/// Creating or writing the file.
pub fn write_msh_file(path: impl AsRef<Path>, mesh: &SurfaceMesh, group: &str) -> io::Result<()> {
    write_msh(BufWriter::new(File::create(path)?), mesh, group)
}

/// Writes a volume mesh as MSH 4.1 ASCII: its cells in the physical volume
/// `volume`, and each of `surfaces` (faces indexing the mesh's points, e.g. from
/// [`VolumeMesh::boundary`] or [`VolumeMesh::orient_outward`]) in a physical
/// surface of that name. Surface `k` is elementary surface `k + 1` with
/// physical tag `k + 1`; the volume is elementary volume 1 with physical tag
/// `surfaces.len() + 1`. Node tag i+1 is point i. Reading the file back with
/// [`Msh::volume`](super::Msh::volume) and [`Msh::surface`](super::Msh::surface)
/// gives the same points, cells and faces.
///
/// # Errors
/// Any I/O error of `w`; [`io::ErrorKind::InvalidInput`] when a surface does
/// not index the mesh's points (another point count) or has a face kind Gmsh
/// does not have (Tri7).
pub fn write_volume_msh<W: Write>(
    w: W,
    mesh: &VolumeMesh,
    volume: &str,
    surfaces: &[(&str, &SurfaceMesh)],
) -> io::Result<()> {
    let n = mesh.points().len();
    let mut entities = Vec::with_capacity(surfaces.len() + 1);
    for (name, surface) in surfaces {
        if surface.n_points() != n {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("surface \"{name}\" has {} points, the volume mesh {n}", surface.n_points()),
            ));
        }
        entities.push(Entity { dim: 2, name: name.to_string(), blocks: face_blocks(surface.faces())? });
    }
    entities.push(Entity { dim: 3, name: volume.to_string(), blocks: cell_blocks(mesh.cells())? });
    write_entities(w, mesh.points(), &entities)
}

/// Writes a volume mesh to the file `path`; see [`write_volume_msh`].
///
/// # Errors
/// Creating or writing the file.
pub fn write_volume_msh_file(
    path: impl AsRef<Path>,
    mesh: &VolumeMesh,
    volume: &str,
    surfaces: &[(&str, &SurfaceMesh)],
) -> io::Result<()> {
    write_volume_msh(BufWriter::new(File::create(path)?), mesh, volume, surfaces)
}

/// One elementary entity carrying one physical group of the same name: its
/// elements as (Gmsh type, node lists) blocks.
struct Entity<'a> {
    dim: u8,
    name: String,
    blocks: Vec<Block<'a>>,
}

/// A Gmsh element type and the node lists of its elements.
type Block<'a> = (u32, Vec<&'a [usize]>);

/// The Gmsh element type number of a face ([`seam::FaceType::gmsh_type`]),
/// if Gmsh has its kind.
pub fn face_type(face: &Face) -> Option<u32> {
    face.kind().info().gmsh_type
}

/// The Gmsh element type number of a cell ([`seam::CellType::gmsh_type`];
/// seam's node order is Gmsh's), if Gmsh has its kind.
pub fn cell_type(cell: &Cell) -> Option<u32> {
    cell.kind().info().gmsh_type
}

/// Faces as blocks of consecutive faces of one Gmsh type, keeping their order.
fn face_blocks(faces: &[Face]) -> io::Result<Vec<Block<'_>>> {
    blocks(faces.iter().map(|f| (face_type(f), f.nodes(), f.kind().name())), "faces")
}

/// Cells as blocks of consecutive cells of one Gmsh type, keeping their order.
fn cell_blocks(cells: &[Cell]) -> io::Result<Vec<Block<'_>>> {
    blocks(cells.iter().map(|c| (cell_type(c), c.nodes(), c.kind().name())), "cells")
}

/// Elements (Gmsh type if any, nodes, kind name) as [`runs`]; an error names
/// the first kind Gmsh does not have.
fn blocks<'a>(
    elements: impl Iterator<Item = (Option<u32>, &'a [usize], &'static str)>,
    what: &str,
) -> io::Result<Vec<Block<'a>>> {
    let typed: io::Result<Vec<_>> = elements
        .map(|(t, nodes, name)| match t {
            Some(t) => Ok((t, nodes)),
            None => Err(io::Error::new(io::ErrorKind::InvalidInput, format!("Gmsh has no {name} {what}"))),
        })
        .collect();
    Ok(runs(typed?.into_iter()))
}

/// Maximal runs of elements of the same type.
fn runs<'a>(elements: impl Iterator<Item = (u32, &'a [usize])>) -> Vec<Block<'a>> {
    let mut blocks: Vec<Block<'a>> = Vec::new();
    for (t, nodes) in elements {
        match blocks.last_mut() {
            Some((last, block)) if *last == t => block.push(nodes),
            _ => blocks.push((t, vec![nodes])),
        }
    }
    blocks
}

/// Writes the file: physical names, entities (entity k+1 of its dimension has
/// physical tag k+1, counting all entities), all points as nodes of the last
/// entity, then the non-empty element blocks.
fn write_entities<W: Write>(mut w: W, points: &[Point3], entities: &[Entity]) -> io::Result<()> {
    let (lo, hi) = bounds(points);
    let bbox = format!("{} {} {} {} {} {}", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    // Elementary tags are numbered per dimension, physical tags over all.
    let mut elementary = Vec::with_capacity(entities.len());
    let mut count = [0usize; 4];
    for e in entities {
        count[e.dim as usize] += 1;
        elementary.push(count[e.dim as usize]);
    }
    writeln!(w, "$MeshFormat\n4.1 0 8\n$EndMeshFormat")?;
    writeln!(w, "$PhysicalNames\n{}", entities.len())?;
    for (k, e) in entities.iter().enumerate() {
        writeln!(w, "{} {} \"{}\"", e.dim, k + 1, e.name.replace('"', "'"))?;
    }
    writeln!(w, "$EndPhysicalNames")?;
    writeln!(w, "$Entities\n0 0 {} {}", count[2], count[3])?;
    for dim in [2, 3] {
        for (k, _) in entities.iter().enumerate().filter(|(_, e)| e.dim == dim) {
            // Surfaces bound no curves, volumes list no surfaces.
            writeln!(w, "{} {bbox} 1 {} 0", elementary[k], k + 1)?;
        }
    }
    writeln!(w, "$EndEntities")?;
    let n = points.len();
    let last = entities.last().map_or((2, 1), |e| (e.dim, count[e.dim as usize]));
    writeln!(w, "$Nodes\n1 {n} 1 {n}\n{} {} 0 {n}", last.0, last.1)?;
    for i in 1..=n {
        writeln!(w, "{i}")?;
    }
    for p in points {
        writeln!(w, "{} {} {}", p[0], p[1], p[2])?;
    }
    writeln!(w, "$EndNodes")?;
    let blocks: Vec<(usize, u32, &Vec<&[usize]>)> = entities
        .iter()
        .enumerate()
        .flat_map(|(k, e)| e.blocks.iter().map(move |(t, b)| (k, *t, b)))
        .filter(|(_, _, b)| !b.is_empty())
        .collect();
    let m: usize = blocks.iter().map(|(_, _, b)| b.len()).sum();
    writeln!(w, "$Elements\n{} {m} 1 {m}", blocks.len())?;
    let mut tag = 0;
    for (k, gmsh_type, elements) in blocks {
        writeln!(w, "{} {} {gmsh_type} {}", entities[k].dim, elementary[k], elements.len())?;
        for nodes in elements {
            tag += 1;
            write!(w, "{tag}")?;
            for &node in nodes.iter() {
                write!(w, " {}", node + 1)?;
            }
            writeln!(w)?;
        }
    }
    writeln!(w, "$EndElements")?;
    w.flush()
}

fn bounds(points: &[Point3]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}
