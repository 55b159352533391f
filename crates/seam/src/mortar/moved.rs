//! The operator again after a few points move, from the faces they touch.
//!
//! [`assemble_keeping`] keeps the per-face blocks of an assembly;
//! [`reassemble`] computes (A1)–(D5) afresh for the slave faces it is given
//! only, takes every other face's block from the kept ones and sums the rows
//! as [`super::assemble`] does (I7). That is the whole assembly on the moved
//! surfaces when the faces given are all those whose blocks the move can
//! change: the slave faces of the moved slave points, and those whose search
//! boxes meet a moved master face ([`slave_faces_near`]). Finite differences
//! of B and D in the points move a few points at a time, and each evaluation
//! then costs the faces they touch instead of the whole surface.

use super::kernel::search_box;
use super::rows::{Blocks, ChunkedBlocks};
use super::{check_inputs, face_blocks, face_blocks_of, into_operator, multiplier, CHUNK};
use super::{Mortar, MortarError, MortarOptions};
use crate::mesh::SurfaceMesh;
use crate::search::FaceTree;
use rayon::prelude::*;
use std::borrow::Cow;

/// The blocks of every slave face of one assembly ([`assemble_keeping`]).
pub struct FaceBlocks {
    chunks: Vec<Blocks>,
    faces: usize,
}

/// [`super::assemble`], keeping the per-face blocks for [`reassemble`].
///
/// # Errors
/// As [`super::assemble`].
pub fn assemble_keeping(
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    options: &MortarOptions,
) -> Result<(Mortar, FaceBlocks), MortarError> {
    check_inputs(master, slave, options)?;
    let tree = FaceTree::new(master);
    let transform = multiplier::transformation_weight(slave, options.transformation);
    let chunks = face_blocks(master, &tree, slave, options, transform, &|_| {});
    let view =
        ChunkedBlocks { chunks: chunks.iter().map(Cow::Borrowed).collect(), chunk: CHUNK, index: None };
    let mortar = into_operator(master, &tree, slave, options, view)?;
    Ok((mortar, FaceBlocks { chunks, faces: slave.n_faces() }))
}

/// The operator between `master` and `slave` with the blocks of the slave
/// faces `moved` (ascending) computed on these surfaces and every other
/// face's taken from `kept` (an assembly of the same faces, `options` and
/// master faces): bit for bit [`super::assemble`] when `moved` holds every
/// face whose block differs (module doc).
///
/// # Errors
/// As [`super::assemble`]; [`MortarError::InvalidOption`] when `kept` holds
/// another number of faces or `moved` is not ascending within the slave.
pub fn reassemble(
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    options: &MortarOptions,
    kept: &FaceBlocks,
    moved: &[usize],
) -> Result<Mortar, MortarError> {
    check_inputs(master, slave, options)?;
    let n = slave.n_faces();
    if kept.faces != n || !moved.windows(2).all(|w| w[0] < w[1]) || moved.last().is_some_and(|&f| f >= n) {
        return Err(MortarError::InvalidOption(format!(
            "reassembly: {} kept faces for a slave of {n}, or moved faces not ascending below {n}",
            kept.faces
        )));
    }
    let tree = FaceTree::new(master);
    let transform = multiplier::transformation_weight(slave, options.transformation);
    let fresh = face_blocks_of(master, &tree, slave, options, transform, moved);
    let mut index: Vec<(u32, u32)> = (0..n).map(|f| ((f / CHUNK) as u32, (f % CHUNK) as u32)).collect();
    for (i, &f) in moved.iter().enumerate() {
        index[f] = ((kept.chunks.len() + i / CHUNK) as u32, (i % CHUNK) as u32);
    }
    let chunks = kept.chunks.iter().map(Cow::Borrowed).chain(fresh.into_iter().map(Cow::Owned)).collect();
    into_operator(
        master,
        &tree,
        slave,
        options,
        ChunkedBlocks { chunks, chunk: n.max(1), index: Some(index) },
    )
}

/// Per master face, the slave faces (ascending) whose search box (A1) meets
/// its box grown by `margin` on every side: the slave faces whose blocks can
/// change when that master face moves by less than `margin`.
pub fn slave_faces_near(
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    options: &MortarOptions,
    margin: f64,
) -> Vec<Vec<usize>> {
    let tree = FaceTree::new(master);
    let meeting: Vec<Vec<usize>> = (0..slave.n_faces())
        .into_par_iter()
        .map(|f| {
            let (lo, hi) = search_box(slave, f, options);
            // Beyond `margin`, the round-off of the kernel's own boxes (as `parts::split`).
            let grow = margin + 1e-9 * (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max) + 1e-300;
            let mut out = Vec::new();
            tree.faces_meeting_box_into(
                lo.map(|x| x - grow - 1e-9 * x.abs()),
                hi.map(|x| x + grow + 1e-9 * x.abs()),
                &mut out,
            );
            out
        })
        .collect();
    let mut near = vec![Vec::new(); master.n_faces()];
    for (f, faces) in meeting.iter().enumerate() {
        faces.iter().for_each(|&g| near[g].push(f));
    }
    near
}
