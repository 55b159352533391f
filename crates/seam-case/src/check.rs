//! How two surfaces meet, before anyone trusts their coupling: the report of
//! `seam check` and `seam.check`.
//!
//! [`check`] assembles the mortar operator with the given options and measures
//! coverage, normal gaps, orientation, face quality and invariants on it: I1
//! and I2 of docs/verification.md (invariants), and the bounds that catch D and B wrong together
//! (the covered area and D's row sums at most the slave and nodal areas,
//! linear fields reproduced on flat parts; see the `invariants` module), each
//! with the slave faces where it fails. The [`CheckReport`] serializes to the
//! JSON of `seam check --json`; its field order is the key order of that
//! file, which scripts rely on. [`check_files`] is the file-level pipeline of
//! `seam check`: read the two surfaces, check, write the fields and the
//! report.

mod invariants;

use crate::input::{Pair, Surface};
use crate::output::Staged;
use crate::Failure;
use anyhow::Context;
use seam::{
    assemble, face_quality, normal_gaps, orientation_conflicts, Mortar, MortarError, MortarOptions,
    SurfaceMesh, Transfer,
};
use seam_io::Field;
use serde::Serialize;
use std::path::PathBuf;

/// Uncovered slave nodes named in [`CheckReport::uncovered_examples`].
const EXAMPLES: usize = 5;

/// Bins of [`CheckReport::gap_histogram`].
const GAP_BINS: usize = 10;

/// [`CheckReport::face_ids`] when the slave faces are named by their Gmsh
/// element tags.
pub const GMSH_ELEMENT_TAGS: &str = "gmsh element tags";

/// [`CheckReport::face_ids`] when the slave faces are element faces of an
/// Abaqus `.inp` or Exodus II file (`*SURFACE`, side set), named by the tag
/// [`seam_io::abaqus::face_tag`] gives them.
pub const ELEMENT_FACE_TAGS: &str = "element face tags (10^18 + 10 E + k: element E, face Sk)";

/// [`CheckReport::face_ids`] when the slave faces are named by their 1-based
/// index in the slave surface.
pub const FACE_INDICES: &str = "1-based face indices";

/// A check of two surfaces: the report and the per-node fields behind it.
#[derive(Clone, Debug)]
pub struct Check {
    /// The report (the JSON of `seam check --json`).
    pub report: CheckReport,
    /// Per slave point, the covered fraction of ∫ λ_p (0 off the surface):
    /// [`Mortar::node_coverage`].
    pub coverage: Vec<f64>,
    /// Per slave point, the signed normal gap to the master surface
    /// ([`normal_gaps`]; NaN where uncovered or off the surface).
    pub normal_gaps: Vec<f64>,
}

/// What `seam check` reports on a pair of surfaces.
///
/// Non-finite numbers (the gap range when no slave node is covered)
/// serialize as JSON `null`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CheckReport {
    /// The master surface as the caller names it (a path for the CLI).
    pub master: String,
    /// The slave surface as the caller names it.
    pub slave: String,
    /// Slave faces.
    pub slave_faces: usize,
    /// Master faces.
    pub master_faces: usize,
    /// Area of the slave surface.
    pub slave_area: f64,
    /// Area of the master surface (each face integrated as the assembly would
    /// integrate a slave face, curved faces with a rule of degree 20).
    pub master_area: f64,
    /// Slave area with a master face behind it.
    pub covered_area: f64,
    /// `covered_area / slave_area`.
    pub covered_fraction: f64,
    /// Slave points on the surface with no master behind them.
    pub uncovered_slave_nodes: usize,
    /// Up to five uncovered slave nodes: (1-based row, coordinates).
    pub uncovered_examples: Vec<(usize, [f64; 3])>,
    /// Ten equal bins from `min_normal_gap` to `max_normal_gap` counting the
    /// covered slave nodes (empty if none is covered).
    pub gap_histogram: Vec<GapBin>,
    /// Smallest signed normal gap over the covered slave nodes (negative: an
    /// overlap).
    pub min_normal_gap: f64,
    /// Largest signed normal gap over the covered slave nodes.
    pub max_normal_gap: f64,
    /// Slave edges whose two faces run them the same way (flipped neighbours).
    pub slave_orientation_conflicts: usize,
    /// Master edges whose two faces run them the same way.
    pub master_orientation_conflicts: usize,
    /// Shape of the slave faces.
    pub slave_quality: Quality,
    /// Shape of the master faces.
    pub master_quality: Quality,
    /// The invariants measured on the assembled operator: I1 (D·1 = B·1),
    /// I2, I1 on T (T·1 = 1), the covered area at most the slave area, D's
    /// row sums at most the nodal areas, and (standard and dual multipliers)
    /// I4, linear fields reproduced on flat parts.
    pub invariants: Vec<Invariant>,
    /// Every slave node covered and every invariant within its tolerance.
    pub ok: bool,
    /// How [`Invariant::offending_faces`] names slave faces:
    /// [`GMSH_ELEMENT_TAGS`] for a surface of elements of an MSH file,
    /// [`ELEMENT_FACE_TAGS`] for element faces of an `.inp` or Exodus file,
    /// else [`FACE_INDICES`].
    pub face_ids: &'static str,
}

/// One bin of the normal-gap histogram, `[from, to)` (the last one closed).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GapBin {
    /// Lower end.
    pub from: f64,
    /// Upper end.
    pub to: f64,
    /// Covered slave nodes whose gap falls in the bin.
    pub nodes: usize,
}

/// The worst faces of a surface.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Quality {
    /// Smallest interior angle of any face, in degrees.
    pub min_angle_degrees: f64,
    /// Largest interior angle of any face, in degrees.
    pub max_angle_degrees: f64,
    /// Largest relative warp of a quad (0 for triangles).
    pub max_warp: f64,
}

/// An invariant measured on the operator.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Invariant {
    /// What is measured, for example "I1 max |T·1 − 1| on covered nodes".
    pub name: &'static str,
    /// The measured relative defect.
    pub value: f64,
    /// The largest defect that passes.
    pub tolerance: f64,
    /// `value <= tolerance`.
    pub ok: bool,
    /// Where it fails: up to five slave faces, worst first, named as
    /// [`CheckReport::face_ids`] says: the faces covered beyond their own
    /// area, or for an invariant per node the faces around the nodes where it
    /// fails (only those covered beyond their own area, if any is). Empty
    /// when ok, and for I2, a sum over the whole surface.
    pub offending_faces: Vec<u64>,
    /// Up to five slave nodes where a per-node invariant fails, worst first,
    /// as 1-based rows of B and D (like [`CheckReport::uncovered_examples`]).
    /// Empty when ok and for invariants of the whole surface.
    pub offending_nodes: Vec<usize>,
}

/// Why a check produced no report.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CheckError {
    /// The assembly failed: no overlap within the limits, an option out of
    /// range, a non-finite entry.
    #[error(transparent)]
    Assembly(MortarError),
    /// The transfer operator T = D⁻¹B could not be formed (D not positive
    /// definite on the covered nodes).
    #[error("the transfer operator: {0}")]
    Transfer(MortarError),
}

impl CheckError {
    /// The mortar error behind it, whichever stage failed.
    pub fn mortar_error(&self) -> &MortarError {
        match self {
            CheckError::Assembly(e) | CheckError::Transfer(e) => e,
        }
    }
}

/// Assembles the operator between `master` and `slave` with `options` and
/// reports how the surfaces meet; `names` are (master, slave) as the report
/// shows them, `slave_face_tags` the Gmsh element tag of each slave face if
/// it has them (the report then names faces by them, else by 1-based index).
///
/// Runs on the current rayon pool (`pool.install` to bound the threads).
///
/// # Errors
/// [`CheckError::Assembly`] as [`assemble`]; [`CheckError::Transfer`] as
/// [`Mortar::transfer`].
pub fn check(
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    options: &MortarOptions,
    names: (&str, &str),
    slave_face_tags: Option<&[u64]>,
) -> Result<Check, CheckError> {
    let mortar = assemble(master, slave, options).map_err(CheckError::Assembly)?;
    let transfer = mortar.transfer().map_err(CheckError::Transfer)?;
    let gaps = normal_gaps(slave, master, &transfer, &mortar.covered);
    let tags = slave_face_tags.filter(|t| t.len() == slave.n_faces());
    let report = report(master, slave, &mortar, &transfer, &gaps, names, tags);
    Ok(Check { report, coverage: mortar.node_coverage, normal_gaps: gaps })
}

fn report(
    master: &SurfaceMesh,
    slave: &SurfaceMesh,
    m: &Mortar,
    t: &Transfer,
    gaps: &[f64],
    (master_name, slave_name): (&str, &str),
    tags: Option<&[u64]>,
) -> CheckReport {
    let s = &m.summary;
    let uncovered = m.uncovered_nodes();
    let face_id = |f: usize| tags.map_or(f as u64 + 1, |t| t[f]);
    let invariants: Vec<Invariant> = invariants::measure(m, t, master, slave)
        .into_iter()
        .map(|i| Invariant {
            name: i.name,
            value: i.value,
            tolerance: i.tolerance,
            ok: i.value <= i.tolerance,
            offending_faces: i.faces.into_iter().map(face_id).collect(),
            offending_nodes: i.nodes.into_iter().map(|p| p + 1).collect(),
        })
        .collect();
    let finite: Vec<f64> = gaps.iter().copied().filter(|g| g.is_finite()).collect();
    let (lo, hi) = finite.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &g| (a.min(g), b.max(g)));
    CheckReport {
        master: master_name.to_string(),
        slave: slave_name.to_string(),
        slave_faces: s.slave_faces,
        master_faces: s.master_faces,
        slave_area: s.slave_area,
        master_area: area(master),
        covered_area: s.covered_area,
        covered_fraction: s.covered_area / s.slave_area,
        uncovered_slave_nodes: uncovered.len(),
        uncovered_examples: uncovered.iter().take(EXAMPLES).map(|&p| (p + 1, slave.points()[p])).collect(),
        gap_histogram: histogram(&finite, lo, hi, GAP_BINS),
        min_normal_gap: lo,
        max_normal_gap: hi,
        slave_orientation_conflicts: orientation_conflicts(slave),
        master_orientation_conflicts: orientation_conflicts(master),
        slave_quality: quality(slave),
        master_quality: quality(master),
        ok: uncovered.is_empty() && invariants.iter().all(|i| i.ok),
        invariants,
        face_ids: match tags {
            Some(t) if t.iter().any(|&t| seam_io::abaqus::split_face_tag(t).is_some()) => ELEMENT_FACE_TAGS,
            Some(_) => GMSH_ELEMENT_TAGS,
            None => FACE_INDICES,
        },
    }
}

/// The area of `mesh`, curved faces included (not their chords').
fn area(mesh: &SurfaceMesh) -> f64 {
    (0..mesh.n_faces()).map(|f| invariants::face_moments(mesh, f).iter().sum::<f64>()).sum()
}

fn quality(mesh: &SurfaceMesh) -> Quality {
    let q = face_quality(mesh);
    Quality {
        min_angle_degrees: q.iter().map(|f| f.min_angle_degrees).fold(f64::INFINITY, f64::min),
        max_angle_degrees: q.iter().map(|f| f.max_angle_degrees).fold(0.0, f64::max),
        max_warp: q.iter().map(|f| f.warp).fold(0.0, f64::max),
    }
}

fn histogram(values: &[f64], lo: f64, hi: f64, bins: usize) -> Vec<GapBin> {
    if values.is_empty() {
        return Vec::new();
    }
    let width = if hi > lo { (hi - lo) / bins as f64 } else { 1.0 };
    let mut counts = vec![0usize; bins];
    for &v in values {
        counts[(((v - lo) / width) as usize).min(bins - 1)] += 1;
    }
    counts
        .into_iter()
        .enumerate()
        .map(|(i, n)| GapBin { from: lo + i as f64 * width, to: lo + (i + 1) as f64 * width, nodes: n })
        .collect()
}

/// `seam check MASTER SLAVE`: the two files, the options, and where to write
/// the per-node fields (VTU) and the report (JSON).
#[derive(Clone, Debug)]
pub struct CheckFiles {
    /// The two surfaces.
    pub pair: Pair,
    /// The mortar options.
    pub options: MortarOptions,
    /// The slave surface with `coverage` and `normal_gap`, as VTU.
    pub vtu: Option<PathBuf>,
    /// The report as JSON.
    pub json: Option<PathBuf>,
    /// Replace existing outputs.
    pub force: bool,
}

/// A check of two files, its outputs staged but not yet written
/// ([`Checked::write`]).
pub struct Checked {
    /// The report.
    pub report: CheckReport,
    slave: SurfaceMesh,
    coverage: Vec<f64>,
    normal_gaps: Vec<f64>,
    vtu: Option<PathBuf>,
    json: Option<PathBuf>,
    out: Staged,
}

/// Checks the outputs (none exists unless `force`), reads the two surfaces
/// and [`check`]s them on the current rayon pool; the outputs are written by
/// [`Checked::write`].
///
/// # Errors
/// [`Failure::NoCoupling`] when the surfaces do not overlap; anything else
/// (an unreadable file, an existing output without `force`) is a
/// [`Failure::Error`] naming the file.
pub fn check_files(c: &CheckFiles) -> Result<Checked, Failure> {
    let targets: Vec<PathBuf> = c.vtu.iter().chain(&c.json).cloned().collect();
    let pair = &c.pair;
    let inputs = [pair.master.clone(), pair.slave.clone()];
    let out = Staged::prepare(&targets, &inputs, c.force)?;
    let master = Surface::read(&pair.master, pair.master_group.as_deref())?.mesh;
    let slave = Surface::read(&pair.slave, pair.slave_group.as_deref())?;
    let names = (pair.master.display().to_string(), pair.slave.display().to_string());
    let tags = slave.face_tags();
    let Check { report, coverage, normal_gaps } =
        check(&master, &slave.mesh, &c.options, (&names.0, &names.1), tags).map_err(|e| match e {
            CheckError::Assembly(e) => Failure::from_coupling(e, &pair.slave, &pair.master),
            e => Failure::error(&e),
        })?;
    let slave = slave.mesh;
    Ok(Checked { report, slave, coverage, normal_gaps, vtu: c.vtu.clone(), json: c.json.clone(), out })
}

impl Checked {
    /// Writes the outputs all-or-nothing; returns the report.
    ///
    /// # Errors
    /// An output that cannot be written.
    pub fn write(self) -> Result<CheckReport, Failure> {
        let Checked { report, slave, coverage, normal_gaps, vtu, json, mut out } = self;
        if let Some(path) = &vtu {
            let fields = [Field::scalars("coverage", coverage), Field::scalars("normal_gap", normal_gaps)];
            out.write(path, |p| {
                seam_io::write_vtu_file(p, &slave, &fields, &[]).map_err(std::io::Error::other)
            })?;
        }
        if let Some(path) = &json {
            let text = serde_json::to_string_pretty(&report).context("report")?;
            out.write(path, |p| std::fs::write(p, text + "\n"))?;
        }
        out.commit(&[])?;
        Ok(report)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use seam::generate::{flat, patch, quadratic_patch, Pattern};
    use seam::FaceKind;
    use seam::Multiplier;

    fn run(master: &SurfaceMesh, slave: &SurfaceMesh) -> Check {
        check(master, slave, &MortarOptions::default(), ("m.msh", "s.msh"), None).unwrap()
    }

    #[test]
    fn full_inclusion_is_covered_and_keeps_the_invariants() {
        let master = patch(5, 3, Pattern::Triangles, flat(1.0, 1.0));
        let slave = patch(4, 4, Pattern::Quads, flat(1.0, 1.0));
        let Check { report: r, coverage, normal_gaps } = run(&master, &slave);
        assert_eq!((r.master.as_str(), r.slave.as_str()), ("m.msh", "s.msh"));
        assert_eq!((r.slave_faces, r.master_faces), (16, 30));
        assert!((r.covered_fraction - 1.0).abs() < 1e-14, "{}", r.covered_fraction);
        assert!((r.master_area - 1.0).abs() < 1e-14, "{}", r.master_area);
        assert_eq!(r.uncovered_slave_nodes, 0);
        assert!(r.uncovered_examples.is_empty());
        assert_eq!(r.invariants.len(), 6);
        assert!(r.invariants.iter().all(|i| i.offending_faces.is_empty() && i.offending_nodes.is_empty()));
        assert_eq!(r.face_ids, FACE_INDICES);
        assert!(r.invariants.iter().all(|i| i.ok && i.value <= i.tolerance), "{:?}", r.invariants);
        assert!(r.ok);
        // Coplanar: every gap is 0, all in one bin of the histogram.
        assert!(r.min_normal_gap.abs() < 1e-14 && r.max_normal_gap.abs() < 1e-14);
        assert_eq!(r.gap_histogram.len(), GAP_BINS);
        assert_eq!(r.gap_histogram.iter().map(|b| b.nodes).sum::<usize>(), 25);
        assert_eq!((r.slave_orientation_conflicts, r.master_orientation_conflicts), (0, 0));
        let q = r.slave_quality;
        assert!(
            (q.min_angle_degrees - 90.0).abs() < 1e-12 && (q.max_angle_degrees - 90.0).abs() < 1e-12,
            "{q:?}"
        );
        assert_eq!(q.max_warp, 0.0);
        assert_eq!((coverage.len(), normal_gaps.len()), (25, 25));
        assert!(coverage.iter().all(|&c| (c - 1.0).abs() < 1e-12));
    }

    #[test]
    fn partial_overlap_names_the_uncovered_nodes() {
        // A 2 × 1 slave rectangle on the unit-square master: the slave points
        // at x = 2 (rows 3 and 6) have no master behind them.
        let master = patch(3, 3, Pattern::Triangles, flat(1.0, 1.0));
        let slave = patch(2, 1, Pattern::Quads, flat(2.0, 1.0));
        let Check { report: r, normal_gaps, .. } = run(&master, &slave);
        assert!((r.covered_fraction - 0.5).abs() < 1e-14, "{}", r.covered_fraction);
        assert_eq!(r.uncovered_slave_nodes, 2);
        assert_eq!(r.uncovered_examples, vec![(3, [2.0, 0.0, 0.0]), (6, [2.0, 1.0, 0.0])]);
        assert!(normal_gaps[2].is_nan() && normal_gaps[5].is_nan());
        assert_eq!(r.gap_histogram.iter().map(|b| b.nodes).sum::<usize>(), 4);
        assert!(r.invariants.iter().all(|i| i.ok), "{:?}", r.invariants);
        assert!(!r.ok);
    }

    #[test]
    fn json_keys_are_those_of_seam_check() {
        let master = patch(2, 2, Pattern::Triangles, flat(1.0, 1.0));
        let slave = patch(2, 2, Pattern::Quads, flat(1.0, 1.0));
        let json = serde_json::to_string(&run(&master, &slave).report).unwrap();
        let keys = [
            "master",
            "slave",
            "slave_faces",
            "master_faces",
            "slave_area",
            "master_area",
            "covered_area",
            "covered_fraction",
            "uncovered_slave_nodes",
            "uncovered_examples",
            "gap_histogram",
            "min_normal_gap",
            "max_normal_gap",
            "slave_orientation_conflicts",
            "master_orientation_conflicts",
            "slave_quality",
            "master_quality",
            "invariants",
            "ok",
            "face_ids",
        ];
        let at: Vec<usize> = keys.iter().map(|k| json.find(&format!("\"{k}\":")).unwrap()).collect();
        assert!(at.windows(2).all(|w| w[0] < w[1]), "keys out of order: {json}");
        for k in [
            "\"from\":",
            "\"to\":",
            "\"nodes\":",
            "\"min_angle_degrees\":",
            "\"max_warp\":",
            "\"tolerance\":",
            "\"offending_faces\":[]",
            "\"offending_nodes\":[]",
        ] {
            assert!(json.contains(k), "{k} missing: {json}");
        }
        // An invariant's keys, in order, new ones last.
        let first = &json[json.find("\"invariants\":[{").unwrap()..];
        let first = &first[..first.find('}').unwrap()];
        let keys = ["name", "value", "tolerance", "ok", "offending_faces", "offending_nodes"];
        let at: Vec<usize> = keys.iter().map(|k| first.find(&format!("\"{k}\":")).unwrap()).collect();
        assert!(at.windows(2).all(|w| w[0] < w[1]), "invariant keys out of order: {first}");
    }

    /// The unit square as 2 × 2 quads, the top right one (face 3) listed
    /// twice: a master that covers a quarter of the slave twice.
    fn master_with_a_duplicated_face() -> SurfaceMesh {
        let (points, mut faces) = patch(2, 2, Pattern::Quads, flat(1.0, 1.0)).into_parts();
        faces.push(faces[3]);
        SurfaceMesh::new(points, faces).unwrap()
    }

    #[test]
    fn a_doubly_covered_slave_is_not_ok_and_its_faces_are_named() {
        // Slave faces 10, 11, 14 and 15 (0-based) of the 4 × 4 quads lie
        // behind the duplicated master face.
        let behind = [11, 12, 15, 16];
        let master = master_with_a_duplicated_face();
        let slave = patch(4, 4, Pattern::Quads, flat(1.0, 1.0));
        for multiplier in [Multiplier::Standard, Multiplier::Dual, Multiplier::Lumped] {
            let options = MortarOptions { multiplier, ..Default::default() };
            let r = check(&master, &slave, &options, ("m", "s"), None).unwrap().report;
            let what = format!("{multiplier:?}: {:?}", r.invariants);
            assert!(!r.ok, "{what}");
            assert_eq!(r.uncovered_slave_nodes, 0);
            assert!((r.covered_fraction - 1.25).abs() < 1e-14, "{}", r.covered_fraction);
            assert_eq!(r.face_ids, FACE_INDICES);
            let find = |prefix: &str| r.invariants.iter().find(|i| i.name.starts_with(prefix)).unwrap();
            // I1, I2 and T·1 = 1 hold: D and B are wrong together.
            for i in &r.invariants[..3] {
                assert!(i.ok && i.offending_faces.is_empty(), "{what}");
            }
            let covered = find("covered area");
            assert!(!covered.ok && (covered.value - 0.25).abs() < 1e-14, "{what}");
            assert_eq!(covered.offending_faces, behind, "{what}");
            assert!(covered.offending_nodes.is_empty());
            let rows = find("D·1");
            assert!(!rows.ok, "{what}");
            let sorted = |v: &[u64]| {
                let mut v = v.to_vec();
                v.sort_unstable();
                v
            };
            assert_eq!(sorted(&rows.offending_faces), behind, "{what}");
            // The nodes whose faces are all behind the duplicate (grid points
            // (3..=4, 3..=4), rows 19, 20, 24, 25) have twice their nodal area,
            // a quarter of their support above it; then come those with half
            // of their faces behind it (rows 14, 15, 18, 23), an eighth.
            assert!((rows.value - 0.25).abs() < 1e-12, "{what}");
            let nodes = &rows.offending_nodes;
            assert_eq!(nodes.len(), 5, "{what}");
            let mut first: Vec<usize> = nodes[..4].to_vec();
            first.sort_unstable();
            assert_eq!(first, [19, 20, 24, 25], "{what}");
            assert!([14, 15, 18, 23].contains(&nodes[4]), "{what}");
            // Linear fields are still reproduced (B and D agree on the
            // doubled quarter): only the bounds catch it.
            if multiplier != Multiplier::Lumped {
                assert!(find("I4").ok, "{what}");
            }
        }
        // Second order: the top right Quad9 of the master twice, under Tri6
        // and Quad8 slaves (dual: transformed bases).
        let (points, mut faces) = quadratic_patch(2, 2, FaceKind::Quad9, None, flat(1.0, 1.0)).into_parts();
        faces.push(faces[3]);
        let quad9_master = SurfaceMesh::new(points, faces).unwrap();
        for kind in [FaceKind::Tri6, FaceKind::Quad8] {
            let slave = quadratic_patch(4, 4, kind, None, flat(1.0, 1.0));
            for multiplier in [Multiplier::Standard, Multiplier::Dual] {
                let options = MortarOptions { multiplier, ..Default::default() };
                let r = check(&quad9_master, &slave, &options, ("m", "s"), None).unwrap().report;
                let what = format!("{kind:?} {multiplier:?}: {:?}", r.invariants);
                let failed: Vec<&str> = r.invariants.iter().filter(|i| !i.ok).map(|i| i.name).collect();
                assert_eq!(failed.len(), 2, "{what}");
                assert!(failed[0].starts_with("covered area") && failed[1].starts_with("D·1"), "{what}");
                // The slave faces behind the duplicate: cells (2..4, 2..4).
                let behind: Vec<u64> = (0..slave.n_faces() as u64)
                    .filter(|&f| {
                        let c = slave.corners(f as usize);
                        let n = slave.faces()[f as usize].n_corners() as f64;
                        let centre: [f64; 2] =
                            [0, 1].map(|k| c.iter().take(n as usize).map(|x| x[k]).sum::<f64>() / n);
                        centre[0] > 0.5 && centre[1] > 0.5
                    })
                    .map(|f| f + 1)
                    .collect();
                for i in r.invariants.iter().filter(|i| !i.ok) {
                    assert!(i.offending_faces.iter().all(|f| behind.contains(f)), "{what}: {behind:?}");
                }
            }
        }
        // Named by their Gmsh element tags when the caller has them.
        let tags: Vec<u64> = (0..16).map(|f| 1000 + f).collect();
        let r = check(&master, &slave, &MortarOptions::default(), ("m", "s"), Some(&tags)).unwrap().report;
        assert_eq!(r.face_ids, GMSH_ELEMENT_TAGS);
        let covered = r.invariants.iter().find(|i| i.name.starts_with("covered area")).unwrap();
        assert_eq!(covered.offending_faces, [1010, 1011, 1014, 1015]);
    }

    #[test]
    fn the_master_area_of_curved_faces_is_that_of_the_faces() {
        // A quarter of a cylinder of radius 1, height 1, in 3 × 2 Quad9 faces.
        let quarter = seam::generate::cylinder(1.0, std::f64::consts::FRAC_PI_2, 1.0);
        let mesh = seam::generate::quadratic_patch(3, 2, seam::FaceKind::Quad9, None, quarter);
        let r = run(&mesh, &mesh).report;
        // The slave area is the assembly's, by a rule of lower degree.
        assert!((r.master_area - r.slave_area).abs() < 1e-10, "{} against {}", r.master_area, r.slave_area);
        // The quadratic arcs of 30° are within 2e-4 of the circle's π/2.
        assert!((r.master_area - std::f64::consts::FRAC_PI_2).abs() < 2e-4, "{}", r.master_area);
        assert!(r.ok, "{:?}", r.invariants);
    }

    #[test]
    fn an_assembly_failure_says_which_stage() {
        let master = patch(1, 1, Pattern::Quads, |u, v| [u + 5.0, v, 0.0]);
        let slave = patch(1, 1, Pattern::Quads, flat(1.0, 1.0));
        let e = check(&master, &slave, &MortarOptions::default(), ("m", "s"), None).unwrap_err();
        assert!(matches!(e, CheckError::Assembly(MortarError::NoOverlap { .. })), "{e:?}");
        assert_eq!(e.to_string(), e.mortar_error().to_string());
    }
}
