//! `seam bench-transfer`: the end-to-end transfer benchmark of BENCHMARKS.md.
//!
//! The cylinder problem of the comparison with preCICE (BENCHMARKS.md, against preCICE): a quarter
//! cylinder (radius 1, height 1), the source n_s × n_s cells of two jittered
//! triangles, the target n × n quads with about 1.19 times fewer faces
//! (238k source triangles for 200k target quads) and 0.3 h² farther out, h
//! the target's arc step. [`write_problem`] writes both as binary VTU, the
//! source with the field `f`; the driver then times `seam transfer` as a
//! user runs it, one process per (mode, multiplier, threads), and reads the
//! seconds per phase from its summary ([`Row`], [`HEADER`]).

use anyhow::Context;
use seam::generate::{cylinder, patch, Pattern};
use seam::SurfaceMesh;
use seam_case::transfer::Phases;
use seam_io::Field;
use std::path::{Path, PathBuf};

/// Source triangles per target quad in the problem compared with preCICE.
const SOURCE_PER_TARGET: f64 = 238.0 / 202.0;

/// The field moved: smooth, not a polynomial.
pub fn field(x: [f64; 3]) -> f64 {
    (2.0 * x[0]).sin() * (3.0 * x[2]).cos() + x[1] * x[1]
}

/// The source and the target of about `faces` target quads: (source, target).
pub fn problem(faces: usize) -> (SurfaceMesh, SurfaceMesh) {
    let quarter = std::f64::consts::FRAC_PI_2;
    let n = ((faces as f64).sqrt().round() as usize).max(1);
    let m = ((n as f64 * (SOURCE_PER_TARGET / 2.0).sqrt()).round() as usize).max(1);
    let h = quarter / n as f64;
    let source =
        patch(m, m, Pattern::JitteredTriangles { amplitude: 0.2, seed: 42 }, cylinder(1.0, quarter, 1.0));
    let target = patch(n, n, Pattern::Quads, cylinder(1.0 + 0.3 * h * h, quarter, 1.0));
    (source, target)
}

/// Writes the problem of about `faces` target quads into `dir` as
/// `source.vtu` (with the point field `f`) and `target.vtu`; returns their
/// paths and face counts.
///
/// # Errors
/// A file that cannot be written.
pub fn write_problem(faces: usize, dir: &Path) -> anyhow::Result<Files> {
    let (source, target) = problem(faces);
    let f: Vec<f64> = source.points().iter().map(|&x| field(x)).collect();
    let files = Files {
        source: dir.join("source.vtu"),
        target: dir.join("target.vtu"),
        source_faces: source.n_faces(),
        target_faces: target.n_faces(),
    };
    seam_io::write_vtu_file(&files.source, &source, &[Field::scalars("f", f)], &[])
        .with_context(|| format!("cannot write {}", files.source.display()))?;
    seam_io::write_vtu_file(&files.target, &target, &[], &[])
        .with_context(|| format!("cannot write {}", files.target.display()))?;
    Ok(files)
}

/// The files of one size.
pub struct Files {
    /// The source, with the field `f`.
    pub source: PathBuf,
    /// The target.
    pub target: PathBuf,
    /// Source triangles.
    pub source_faces: usize,
    /// Target quads.
    pub target_faces: usize,
}

/// The table's header, two lines of Markdown.
pub const HEADER: [&str; 2] = [
    "| target faces | source faces | mode | multiplier | threads | read s | assemble s | operator s | apply s | diagnostics s | write s | all in s | all in / assemble |",
    "|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
];

/// One timed run.
pub struct Row<'a> {
    /// The files.
    pub files: &'a Files,
    /// "consistent" or "conservative".
    pub mode: &'a str,
    /// "standard", "dual" or "lumped".
    pub multiplier: &'a str,
    /// Worker threads.
    pub threads: usize,
    /// From the summary.
    pub phases: Phases,
    /// The process's wall clock, start to exit, as the driver saw it.
    pub all_in: f64,
}

impl Row<'_> {
    /// The row of the table under [`HEADER`].
    pub fn table_line(&self) -> String {
        let p = &self.phases;
        format!(
            "| {} | {} | {} | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2} |",
            self.files.target_faces,
            self.files.source_faces,
            self.mode,
            self.multiplier,
            self.threads,
            p.read,
            p.assemble,
            p.operator,
            p.apply,
            p.diagnostics,
            p.write,
            self.all_in,
            self.all_in / p.assemble
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_problem_has_the_face_ratio_and_gap_of_the_comparison() {
        let (source, target) = problem(20_000);
        let ratio = source.n_faces() as f64 / target.n_faces() as f64;
        assert!((ratio - SOURCE_PER_TARGET).abs() < 0.01, "{ratio}");
        let h = std::f64::consts::FRAC_PI_2 / (target.n_faces() as f64).sqrt();
        let r = |x: [f64; 3]| x[0].hypot(x[1]);
        assert!(target.points().iter().all(|&x| (r(x) - 1.0 - 0.3 * h * h).abs() < 1e-12));
        assert!(source.points().iter().all(|&x| (r(x) - 1.0).abs() < 1e-12));
    }
}
