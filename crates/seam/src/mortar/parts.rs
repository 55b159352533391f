//! The operator in parts, for memory that is not shared (MPI ranks; the
//! transport is the caller's): the same B and D, bit for bit, as
//! [`super::assemble`] (I7 extended to parts).
//!
//! 1. [`split`]: the slave faces are cut into parts of equal face counts by
//!    recursive coordinate bisection of their centres ([`bisect`]); each part
//!    also gets the master faces whose boxes meet its *region*: the box of
//!    its faces' search boxes (A1, swept by the gap limit), so every
//!    candidate of every face it owns — a rendezvous by boxes, not a copy of
//!    the whole master.
//! 2. [`PartJob`]: a part's faces as two small meshes (points renumbered,
//!    global numbers kept) and the options, to bytes and back.
//! 3. [`PartJob::assemble`]: (A1)–(D5) for the part's slave faces against
//!    its master faces: each face's block is the one the whole assembly
//!    computes (the kernel sees the same candidates, in the same order), its
//!    columns renumbered to the whole master's points ([`PartBlocks`], to
//!    bytes and back).
//! 4. [`assemble_parts`]: the blocks of all parts, put back in face order,
//!    summed row by row in increasing face order as in the whole assembly.

use super::kernel::search_box;
use super::rows::{Blocks, ChunkedBlocks};
use super::{
    check_inputs, face_blocks, face_blocks_of, into_operator, multiplier, BasisTransformation, Facing, MaxGap,
};
use super::{Mortar, MortarError, MortarOptions, Multiplier};
use crate::catalogue::FaceKind;
use crate::mesh::{Face, Point3, SurfaceMesh};
use crate::search::FaceTree;
use crate::wire::{Reader, WireError, Writer};
use rayon::prelude::*;

/// The part of each of the points `centres`, by recursive coordinate
/// bisection into `parts` parts: the longest side of the current set's box is
/// cut at the point that leaves each side a share of the points proportional
/// to its parts (ties broken by index, so the result depends on nothing
/// else). Part sizes differ by at most one point per level of cutting.
pub fn bisect(centres: &[Point3], parts: usize) -> Vec<usize> {
    let mut part = vec![0; centres.len()];
    let mut items: Vec<usize> = (0..centres.len()).collect();
    cut(centres, &mut items, 0, parts.max(1), &mut part);
    part
}

fn cut(centres: &[Point3], items: &mut [usize], first: usize, parts: usize, part: &mut [usize]) {
    if parts == 1 || items.len() <= 1 {
        items.iter().for_each(|&i| part[i] = first);
        return;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for &i in items.iter() {
        for k in 0..3 {
            lo[k] = lo[k].min(centres[i][k]);
            hi[k] = hi[k].max(centres[i][k]);
        }
    }
    let axis = (0..3).fold(0, |a, k| if hi[k] - lo[k] > hi[a] - lo[a] { k } else { a });
    let left = parts / 2;
    let at = items.len() * left / parts;
    let key = |&i: &usize| (centres[i][axis], i);
    items.select_nth_unstable_by(at, |a, b| {
        let (ka, kb) = (key(a), key(b));
        ka.0.total_cmp(&kb.0).then(ka.1.cmp(&kb.1))
    });
    let (l, r) = items.split_at_mut(at);
    cut(centres, l, first, left, part);
    cut(centres, r, first + left, parts - left, part);
}

/// One part: its slave faces and the master faces its region needs, both
/// ascending.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Part {
    /// The slave faces it owns.
    pub slave_faces: Vec<usize>,
    /// The master faces whose boxes meet its region (its ghosts).
    pub master_faces: Vec<usize>,
}

/// Cuts the slave faces into `parts` parts ([`bisect`] of the face centres)
/// and gives each the master faces of its region (module doc). A part may be
/// empty when there are fewer faces than parts.
pub fn split(tree: &FaceTree, slave: &SurfaceMesh, options: &MortarOptions, parts: usize) -> Vec<Part> {
    let centres: Vec<Point3> = (0..slave.n_faces())
        .map(|f| {
            let c = slave.corners(f);
            let n = slave.faces()[f].n_corners() as f64;
            std::array::from_fn(|k| c[..slave.faces()[f].n_corners()].iter().map(|x| x[k]).sum::<f64>() / n)
        })
        .collect();
    let owner = bisect(&centres, parts);
    let mut out: Vec<Part> =
        (0..parts.max(1)).map(|_| Part { slave_faces: Vec::new(), master_faces: Vec::new() }).collect();
    for (f, &p) in owner.iter().enumerate() {
        out[p].slave_faces.push(f);
    }
    for part in &mut out {
        if part.slave_faces.is_empty() {
            continue;
        }
        let empty = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let union = |(a, b): (Point3, Point3), (c, d): (Point3, Point3)| {
            (std::array::from_fn(|k| a[k].min(c[k])), std::array::from_fn(|k| b[k].max(d[k])))
        };
        let (lo, hi): (Point3, Point3) =
            part.slave_faces.par_iter().map(|&f| search_box(slave, f, options)).reduce(|| empty, union);
        // A margin far above the round-off of the kernel's own boxes: a superset
        // of the candidates is harmless, a missing one is not.
        let margin = 1e-9 * (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max) + 1e-300;
        let lo = lo.map(|x| x - margin - 1e-9 * x.abs());
        let hi = hi.map(|x| x + margin + 1e-9 * x.abs());
        tree.faces_meeting_box_into(lo, hi, &mut part.master_faces);
    }
    out
}

/// Some faces of a surface as a mesh of their own: the points they use,
/// renumbered in increasing order, and the global numbers of both.
#[derive(Clone, Debug, PartialEq)]
struct SubSurface {
    mesh: SurfaceMesh,
    /// Global face numbers, ascending.
    faces: Vec<usize>,
    /// Global point numbers, ascending.
    points: Vec<usize>,
}

impl SubSurface {
    fn of(mesh: &SurfaceMesh, faces: &[usize]) -> Option<SubSurface> {
        if faces.is_empty() {
            return None;
        }
        // The points used, ascending; a face's nodes found by binary search
        // (no array over the whole mesh per part).
        let mut points: Vec<usize> =
            faces.iter().flat_map(|&f| mesh.faces()[f].nodes().iter().copied()).collect();
        points.par_sort_unstable();
        points.dedup();
        let local = |n: &usize| points.binary_search(n).expect("a node of the faces");
        let renumbered = faces
            .par_iter()
            .map(|&f| {
                let mut nodes = [0; 9];
                let face = mesh.faces()[f].nodes();
                face.iter().zip(&mut nodes).for_each(|(n, l)| *l = local(n));
                Face::from_nodes(&nodes[..face.len()])
            })
            .collect();
        let xs = points.iter().map(|&n| mesh.points()[n]).collect();
        let mesh = SurfaceMesh::from_valid_faces(xs, renumbered).expect("faces of a valid mesh");
        Some(SubSurface { mesh, faces: faces.to_vec(), points })
    }

    fn encode(&self, w: &mut Writer) {
        w.usizes(&self.faces);
        w.usizes(&self.points);
        w.f64s(self.mesh.points().as_flattened());
        let nodes: Vec<usize> = self.mesh.faces().iter().flat_map(|f| f.nodes().iter().copied()).collect();
        let lens: Vec<usize> = self.mesh.faces().iter().map(|f| f.len()).collect();
        w.usizes(&lens);
        w.usizes(&nodes);
    }

    fn decode(r: &mut Reader) -> Result<SubSurface, WireError> {
        let (faces, points, xs) = (r.usizes()?, r.usizes()?, r.f64s()?);
        let (lens, nodes) = (r.usizes()?, r.usizes()?);
        let xs: Vec<Point3> = xs.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        if xs.len() != points.len()
            || lens.len() != faces.len()
            || lens.iter().any(|&l| FaceKind::with_nodes(l).is_none())
            || lens.iter().sum::<usize>() != nodes.len()
        {
            return Err(WireError);
        }
        let mut at = 0;
        let faces_local = lens
            .iter()
            .map(|&l| {
                at += l;
                Face::from_nodes(&nodes[at - l..at])
            })
            .collect();
        // Faces of rank 0's checked mesh: their node indices are checked here.
        let mesh = SurfaceMesh::from_valid_faces(xs, faces_local).map_err(|_| WireError)?;
        Ok(SubSurface { mesh, faces, points })
    }
}

/// What one part assembles: its faces of both surfaces and the options.
#[derive(Clone, Debug, PartialEq)]
pub struct PartJob {
    options: MortarOptions,
    /// The weight of the basis transformation of the *whole* slave surface, if any.
    transform: Option<f64>,
    /// `None` when the part has no slave faces.
    faces: Option<(SubSurface, SubSurface)>,
}

impl PartJob {
    /// The job of `part` of the surfaces.
    pub fn new(master: &SurfaceMesh, slave: &SurfaceMesh, options: &MortarOptions, part: &Part) -> PartJob {
        let transform = multiplier::transformation_weight(slave, options.transformation);
        // A region that no master face meets still gets one (which its faces'
        // own searches do not return): the kernel needs a surface to search.
        let ghosts = match part.master_faces.is_empty() {
            true => &[0][..],
            false => &part.master_faces,
        };
        let faces = SubSurface::of(master, ghosts).zip(SubSurface::of(slave, &part.slave_faces));
        PartJob { options: *options, transform, faces }
    }

    /// Slave faces of the part.
    pub fn slave_faces(&self) -> usize {
        self.faces.as_ref().map_or(0, |(_, s)| s.faces.len())
    }

    /// Master faces of the part (its ghosts).
    pub fn master_faces(&self) -> usize {
        self.faces.as_ref().map_or(0, |(m, _)| m.faces.len())
    }

    /// (A1)–(D5) for the part's slave faces, on the current rayon pool: every
    /// face's block, numbered as in the whole surfaces.
    pub fn assemble(&self) -> PartBlocks {
        let Some((master, slave)) = &self.faces else {
            return PartBlocks { faces: Vec::new(), blocks: Vec::new() };
        };
        let tree = FaceTree::new(&master.mesh);
        let mut chunks =
            face_blocks(&master.mesh, &tree, &slave.mesh, &self.options, self.transform, &|_| {});
        for c in &mut chunks {
            c.renumber(&master.points, &slave.faces, &master.faces);
        }
        PartBlocks { faces: slave.faces.clone(), blocks: chunks }
    }

    /// The job as bytes ([`PartJob::from_bytes`] reads them).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = Writer::default();
        let o = &self.options;
        w.u64(o.multiplier as u64);
        w.u64(o.facing as u64);
        match o.max_gap {
            MaxGap::Relative(v) => (w.u64(0), w.f64(v)),
            MaxGap::Absolute(v) => (w.u64(1), w.f64(v)),
        };
        w.f64(o.max_angle_degrees);
        w.usize(o.warped_quad_degree.map_or(0, |d| d + 1));
        w.u64(u64::from(o.record_segments));
        w.u64(o.transformation as u64);
        w.u64(u64::from(self.transform.is_some()));
        w.f64(self.transform.unwrap_or(0.0));
        w.u64(u64::from(self.faces.is_some()));
        if let Some((master, slave)) = &self.faces {
            master.encode(&mut w);
            slave.encode(&mut w);
        }
        w.0
    }

    /// Reads [`PartJob::to_bytes`].
    ///
    /// # Errors
    /// [`WireError`] when the bytes are not a job.
    pub fn from_bytes(bytes: &[u8]) -> Result<PartJob, WireError> {
        let mut r = Reader(bytes);
        let pick = |v: u64, n: u64| if v < n { Ok(v) } else { Err(WireError) };
        let multiplier =
            [Multiplier::Standard, Multiplier::Dual, Multiplier::Lumped][pick(r.u64()?, 3)? as usize];
        let facing = [Facing::Any, Facing::Opposite][pick(r.u64()?, 2)? as usize];
        let max_gap = match (pick(r.u64()?, 2)?, r.f64()?) {
            (0, v) => MaxGap::Relative(v),
            (_, v) => MaxGap::Absolute(v),
        };
        let max_angle_degrees = r.f64()?;
        let warped_quad_degree = r.usize()?.checked_sub(1);
        let record_segments = pick(r.u64()?, 2)? == 1;
        let transformation =
            [BasisTransformation::Needed, BasisTransformation::All][pick(r.u64()?, 2)? as usize];
        let transform = (pick(r.u64()?, 2)?, r.f64()?);
        let transform = (transform.0 == 1).then_some(transform.1);
        let faces = match pick(r.u64()?, 2)? {
            1 => Some((SubSurface::decode(&mut r)?, SubSurface::decode(&mut r)?)),
            _ => None,
        };
        r.done()?;
        let options = MortarOptions {
            multiplier,
            facing,
            max_gap,
            max_angle_degrees,
            warped_quad_degree,
            record_segments,
            transformation,
        };
        Ok(PartJob { options, transform, faces })
    }
}

/// (A1)–(D5) for the slave faces of `part` where the whole surfaces are at
/// hand (rank 0's own part): the blocks [`PartJob::assemble`] would give,
/// without the copy of the faces.
pub fn assemble_here(
    master: &SurfaceMesh,
    tree: &FaceTree,
    slave: &SurfaceMesh,
    options: &MortarOptions,
    part: &Part,
) -> PartBlocks {
    let transform = multiplier::transformation_weight(slave, options.transformation);
    let blocks = face_blocks_of(master, tree, slave, options, transform, &part.slave_faces);
    PartBlocks { faces: part.slave_faces.clone(), blocks }
}

/// The blocks of a part's slave faces, numbered as in the whole surfaces.
pub struct PartBlocks {
    /// Global slave faces, ascending.
    faces: Vec<usize>,
    /// Their blocks, in that order, in chunks.
    blocks: Vec<Blocks>,
}

impl PartBlocks {
    /// The blocks as bytes ([`PartBlocks::from_bytes`] reads them).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = Writer::default();
        w.usizes(&self.faces);
        w.usize(self.blocks.len());
        self.blocks.iter().for_each(|b| b.encode(&mut w));
        w.0
    }

    /// Reads [`PartBlocks::to_bytes`].
    ///
    /// # Errors
    /// [`WireError`] when the bytes are not a part's blocks.
    pub fn from_bytes(bytes: &[u8]) -> Result<PartBlocks, WireError> {
        let mut r = Reader(bytes);
        let faces = r.usizes()?;
        let n = r.usize()?;
        let blocks =
            (0..n.min(bytes.len())).map(|_| Blocks::decode(&mut r)).collect::<Result<Vec<_>, _>>()?;
        r.done()?;
        match blocks.iter().map(Blocks::len).sum::<usize>() == faces.len() {
            true => Ok(PartBlocks { faces, blocks }),
            false => Err(WireError),
        }
    }

    /// Slave faces held.
    pub fn len(&self) -> usize {
        self.faces.len()
    }

    /// Whether it holds no face.
    pub fn is_empty(&self) -> bool {
        self.faces.is_empty()
    }
}

/// The operator from the blocks of parts that together hold every slave face
/// once: the same B, D and totals, bit for bit, as [`super::assemble`].
///
/// # Errors
/// As [`super::assemble`]; [`MortarError::InvalidOption`] when the parts do not
/// hold every face of `slave` exactly once or a column lies beyond `master`.
pub fn assemble_parts(
    master: &SurfaceMesh,
    tree: &FaceTree,
    slave: &SurfaceMesh,
    options: &MortarOptions,
    parts: Vec<PartBlocks>,
) -> Result<Mortar, MortarError> {
    check_inputs(master, slave, options)?;
    let n = slave.n_faces();
    let bad = |what: &str| Err(MortarError::InvalidOption(format!("the parts' blocks {what}")));
    let mut index = vec![(u32::MAX, 0u32); n];
    let mut chunks = Vec::new();
    for part in parts {
        let mut faces = part.faces.iter();
        for chunk in part.blocks {
            if !chunk.columns_below(master.n_points()) {
                return bad("name master points beyond the master surface");
            }
            for k in 0..chunk.len() {
                let f = *faces.next().expect("as many faces as blocks (checked when read)");
                match index.get_mut(f) {
                    Some(slot) if slot.0 == u32::MAX => *slot = (chunks.len() as u32, k as u32),
                    _ => return bad("hold a slave face twice or one beyond the slave surface"),
                }
            }
            chunks.push(chunk);
        }
    }
    if index.iter().any(|slot| slot.0 == u32::MAX) {
        return bad("miss a slave face");
    }
    let chunks = chunks.into_iter().map(std::borrow::Cow::Owned).collect();
    let blocks = ChunkedBlocks { chunks, chunk: n.max(1), index: Some(index) };
    into_operator(master, tree, slave, options, blocks)
}
