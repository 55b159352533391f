//! Replays the fuzz seeds and every input the fuzzer once failed on
//! (`fuzz/seeds`, `fuzz/regressions`, see `scripts/fuzz`) as the fuzz targets
//! do: each case file and expression must be accepted or refused with one
//! short line, without a panic; the seeds are valid and must be accepted.

use std::path::{Path, PathBuf};

fn inputs(dir: &str, target: &str) -> Vec<PathBuf> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz").join(dir).join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(path)
        .map(|entries| entries.map(|e| e.unwrap().path()).collect())
        .unwrap_or_default();
    files.retain(|p| p.is_file() && p.file_name().is_some_and(|n| n != ".gitkeep"));
    files.sort();
    files
}

fn assert_one_line(e: &dyn std::fmt::Display, path: &Path) {
    let text = e.to_string();
    assert!(!text.is_empty() && !text.contains('\n') && text.len() < 2000, "{}: {text}", path.display());
}

#[test]
fn case_files_that_once_failed_are_read_or_refused() {
    for path in inputs("seeds", "case") {
        let text = std::fs::read_to_string(&path).unwrap();
        seam_case::Case::from_toml(&text, Path::new(""))
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
    for path in inputs("regressions", "case") {
        let Ok(text) = String::from_utf8(std::fs::read(&path).unwrap()) else { continue };
        if let Err(e) = seam_case::Case::from_toml(&text, Path::new("")) {
            assert_one_line(&e, &path);
        }
    }
}

#[test]
fn expressions_that_once_failed_are_evaluated_or_refused() {
    let seeds = inputs("seeds", "expression");
    assert!(!seeds.is_empty());
    for path in seeds.iter().chain(&inputs("regressions", "expression")) {
        let Ok(text) = String::from_utf8(std::fs::read(path).unwrap()) else { continue };
        match seam_case::Expression::parse(&text) {
            Ok(e) => {
                for p in [[0.0, 0.0, 0.0], [0.5, -1.0, 2.0], [1e30, -1e-30, 3.0]] {
                    if let Err(err) = e.at(p) {
                        assert_one_line(&err, path);
                    }
                }
            }
            Err(err) => assert_one_line(&err, path),
        }
    }
}
