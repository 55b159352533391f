//! An example solves its problem in memory; `seam solve DIR/case.toml
//! --force` on the case it wrote reads the meshes back and must give the same
//! results: byte-identical VTU files and the same summary.json apart from the
//! timings.

use seam_case::solve::{solve_case_to_output, SolveOptions};
use seam_examples::{Example, Options};
use std::path::Path;

/// The results of the example, then of `seam solve` on its case.
fn example_then_rerun(
    example: Example,
    slave_cells: usize,
    ratio: Option<usize>,
    order: Option<usize>,
    files: &[&str],
) {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("ex");
    let options = Options { output: dir.clone(), force: false, ratio, slave_cells: Some(slave_cells), order };
    seam_examples::run(example, &options).unwrap_or_else(|e| panic!("{e:?}"));
    let read = |name: &str| std::fs::read(dir.join("out").join(name)).unwrap();
    let before: Vec<Vec<u8>> = files.iter().map(|f| read(f)).collect();
    let summary_before = summary(&dir.join("out/summary.json"));

    solve_case_to_output(&dir.join("case.toml"), &SolveOptions::default(), true).unwrap();
    for (file, bytes) in files.iter().zip(&before) {
        assert!(read(file) == *bytes, "{file} differs between the example and seam solve on its case");
    }
    assert_eq!(summary(&dir.join("out/summary.json")), summary_before);
}

/// summary.json without its timings.
fn summary(path: &Path) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v.as_object_mut().unwrap().remove("seconds");
    v
}

#[test]
fn warped_glue_gives_what_seam_solve_gives_on_its_case() {
    example_then_rerun(
        Example::WarpedGlue,
        2,
        Some(2),
        None,
        &["lower.vtu", "upper.vtu", "upper_bottom_interface.vtu"],
    );
}

/// `--order 2`: Hex27 bodies written as Gmsh second-order meshes, read back
/// by `seam solve` (MSH and VTU of quadratic cells round the loop).
#[test]
fn second_order_warped_glue_gives_what_seam_solve_gives_on_its_case() {
    example_then_rerun(
        Example::WarpedGlue,
        2,
        Some(2),
        Some(2),
        &["lower.vtu", "upper.vtu", "upper_bottom_interface.vtu"],
    );
}

#[test]
fn bulging_contact_gives_what_seam_solve_gives_on_its_case() {
    example_then_rerun(
        Example::BulgingContact,
        4,
        None,
        None,
        &["lower.vtu", "upper.vtu", "upper_bottom_interface.vtu"],
    );
}
