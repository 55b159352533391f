//! `seam bench`: the assembly benchmark of BENCHMARKS.md.
//!
//! Slave bilinear quads against master triangles whose legs are ≈ 1.41× the quad
//! edge (about as many faces on both sides, as in the dune-grid-glue peer's
//! meshes), on a flat square and on a cylinder patch; and the cylinder with
//! second-order faces (Quad9 slaves, Tri6 masters). Every (case, size, threads) runs in a fresh
//! process (`seam bench-case`, [`measure`]) so that its peak memory is its own; the driver
//! prints one Markdown table ([`HEADER`], [`Row::table_line`]).

use anyhow::Context;
use seam::generate::{cylinder, flat, patch, quadratic_patch, Pattern};
use seam::{assemble_with_tree, FaceKind, FaceTree, MaxGap, MortarOptions, SurfaceMesh};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The surfaces of the benchmark.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Shape {
    /// The unit square.
    Flat,
    /// A quarter cylinder (radius 1, height 1), the master at radius 1.001.
    Cylinder,
    /// The quarter cylinder with second-order faces: Quad9 slaves against
    /// jittered Tri6 masters, at the face counts of `Cylinder`.
    #[value(name = "cylinder-o2")]
    CylinderQuadratic,
    /// 30 × 30 slave quads on the unit square over a fine master of jittered
    /// triangles; the size is the number of master faces (the sweep of the
    /// cost per master face against the faces behind each slave face).
    CoarseSlave,
}

impl Shape {
    /// Its name on the command line and in the table.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Flat => "flat",
            Shape::Cylinder => "cylinder",
            Shape::CylinderQuadratic => "cylinder-o2",
            Shape::CoarseSlave => "coarse-slave",
        }
    }
}

/// The table's header, two lines of Markdown.
pub const HEADER: [&str; 2] = [
    "| shape | slave faces | master faces | threads | candidate pairs | segments | covered | search s | assemble s | search+assemble s | slave faces/s | µs/master face | peak MB | extra B/face |",
    "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
];

/// One measured run (`seam bench-case` prints it as JSON).
#[derive(Serialize, Deserialize)]
pub struct Row {
    /// The surface.
    pub shape: String,
    /// Slave faces.
    pub slave_faces: usize,
    /// Master faces.
    pub master_faces: usize,
    /// Worker threads.
    pub threads: usize,
    /// Face pairs the search proposed.
    pub candidate_pairs: usize,
    /// Mortar segments.
    pub segments: usize,
    /// Covered fraction of the slave area: a benchmark of a wrong answer is worthless.
    pub covered: f64,
    /// Seconds to generate the meshes.
    pub generate: f64,
    /// Seconds to build the search tree.
    pub search: f64,
    /// Seconds to assemble.
    pub assemble: f64,
    /// Peak resident memory, MB.
    pub peak_mb: f64,
    /// Peak memory beyond the input meshes and the output B, D, per slave face.
    pub extra_bytes_per_face: f64,
}

impl Row {
    /// The row of the table under [`HEADER`].
    pub fn table_line(&self) -> String {
        let r = self;
        let work = r.search + r.assemble;
        format!(
            "| {} | {} | {} | {} | {} | {} | {:.6} | {:.3} | {:.3} | {:.3} | {:.0} | {:.3} | {:.0} | {:.0} |",
            r.shape,
            r.slave_faces,
            r.master_faces,
            r.threads,
            r.candidate_pairs,
            r.segments,
            r.covered,
            r.search,
            r.assemble,
            work,
            r.slave_faces as f64 / work,
            1e6 * work / r.master_faces as f64,
            r.peak_mb,
            r.extra_bytes_per_face
        )
    }
}

const QUARTER: f64 = std::f64::consts::FRAC_PI_2;

/// The meshes of one case: n × n slave quads (n² ≈ `faces`) and m × m cells of
/// two jittered master triangles with m = n/√2, so h_m/h_s ≈ 1.41 and the face
/// counts match; for [`Shape::CoarseSlave`] 30 × 30 slave quads and about
/// `faces` master triangles.
fn meshes(shape: Shape, faces: usize) -> (SurfaceMesh, SurfaceMesh) {
    let n = ((faces as f64).sqrt().round() as usize).max(1);
    let m = ((n as f64 / std::f64::consts::SQRT_2).round() as usize).max(1);
    let master = Pattern::JitteredTriangles { amplitude: 0.2, seed: 42 };
    match shape {
        Shape::Flat => (patch(m, m, master, flat(1.0, 1.0)), patch(n, n, Pattern::Quads, flat(1.0, 1.0))),
        Shape::Cylinder => (
            patch(m, m, master, cylinder(1.001, QUARTER, 1.0)),
            patch(n, n, Pattern::Quads, cylinder(1.0, QUARTER, 1.0)),
        ),
        Shape::CylinderQuadratic => (
            quadratic_patch(m, m, FaceKind::Tri6, Some((0.2, 42)), cylinder(1.001, QUARTER, 1.0)),
            quadratic_patch(n, n, FaceKind::Quad9, None, cylinder(1.0, QUARTER, 1.0)),
        ),
        Shape::CoarseSlave => {
            let m = (((faces / 2) as f64).sqrt().round() as usize).max(1);
            (patch(m, m, master, flat(1.0, 1.0)), patch(30, 30, Pattern::Quads, flat(1.0, 1.0)))
        }
    }
}

/// Generates, searches and assembles one case of about `faces` slave faces
/// on the current rayon pool (of `threads` threads, as recorded), measuring
/// times and peak memory (Linux).
///
/// # Errors
/// An assembly error, or no readable `/proc/self/status`.
pub fn measure(shape: Shape, faces: usize, threads: usize) -> anyhow::Result<Row> {
    let t = Instant::now();
    let (master, slave) = meshes(shape, faces);
    let generate = t.elapsed().as_secs_f64();
    let input_rss = rss_bytes("VmRSS")?;
    let t = Instant::now();
    let tree = FaceTree::new(&master);
    let search = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let options = match shape {
        Shape::Flat | Shape::CoarseSlave => MortarOptions::default(),
        // The gap of 0.001 is more than half a face at 1M faces: an absolute limit of
        // twice the gap.
        Shape::Cylinder | Shape::CylinderQuadratic => {
            MortarOptions { max_gap: MaxGap::Absolute(0.002), ..Default::default() }
        }
    };
    let mortar = assemble_with_tree(&master, &tree, &slave, &options, &|_| {})?;
    let assemble = t.elapsed().as_secs_f64();
    let peak = rss_bytes("VmHWM")?;
    let csr_bytes = |m: &seam::CsrMatrix| (m.indptr.len() + m.indices.len() + m.values.len()) * 8;
    let output = csr_bytes(&mortar.b) + csr_bytes(&mortar.d);
    let row = Row {
        shape: shape.name().to_string(),
        slave_faces: slave.n_faces(),
        master_faces: master.n_faces(),
        threads,
        candidate_pairs: mortar.summary.candidate_pairs,
        segments: mortar.summary.segments,
        covered: mortar.summary.covered_area / mortar.summary.slave_area,
        generate,
        search,
        assemble,
        peak_mb: peak as f64 / 1e6,
        extra_bytes_per_face: (peak as f64 - input_rss as f64 - output as f64) / slave.n_faces() as f64,
    };
    Ok(row)
}

/// A memory figure of this process from /proc/self/status (Linux), in bytes.
fn rss_bytes(key: &str) -> anyhow::Result<u64> {
    seam_case::process::memory_bytes(key).with_context(|| format!("no {key} in /proc/self/status"))
}
