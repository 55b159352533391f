//! Replays the fuzz seeds and every input the fuzzer once failed on
//! (`fuzz/seeds`, `fuzz/regressions`, see `scripts/fuzz`) through the readers
//! as the fuzz targets do: each must return, without a panic, a mesh or an
//! error of one short line.

use std::path::{Path, PathBuf};

fn inputs(target: &str) -> Vec<PathBuf> {
    let fuzz = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz");
    let mut files: Vec<PathBuf> = ["seeds", "regressions"]
        .iter()
        .filter_map(|dir| std::fs::read_dir(fuzz.join(dir).join(target)).ok())
        .flatten()
        .map(|entry| entry.unwrap().path())
        .filter(|p| p.is_file() && p.file_name().is_some_and(|n| n != ".gitkeep"))
        .collect();
    files.sort();
    files
}

fn assert_one_line(e: &dyn std::fmt::Display, path: &Path) {
    let text = e.to_string();
    assert!(!text.is_empty() && !text.contains('\n') && text.len() < 1000, "{}: {text}", path.display());
}

/// A read file's whole surface and volume are built or refused in one line;
/// a refused file is one line.
fn read_or_refused<E: std::fmt::Display>(read: Result<seam_io::Msh, E>, path: &Path) {
    match read {
        Ok(msh) => {
            for e in [msh.surface(None).err(), msh.volume(None).err()].into_iter().flatten() {
                assert_one_line(&e, path);
            }
        }
        Err(e) => assert_one_line(&e, path),
    }
}

#[test]
fn msh_inputs_that_once_failed_are_read_or_refused() {
    for path in inputs("msh") {
        let bytes = std::fs::read(&path).unwrap();
        read_or_refused(seam_io::read_msh(&bytes), &path);
    }
}

#[test]
fn vtu_inputs_that_once_failed_are_read_or_refused() {
    for path in inputs("vtu") {
        let bytes = std::fs::read(&path).unwrap();
        if let Err(e) = seam_io::read_vtu(&bytes[..]) {
            assert_one_line(&e, &path);
        }
    }
}

/// Exodus II inputs, each read after a valid NetCDF-4 file in the same
/// process (the netCDF C library once crashed on a damaged file there; the
/// reader is pure Rust now), and the seeds.
#[test]
fn exodus_inputs_that_once_failed_are_read_or_refused() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/exodus");
    let valid = std::fs::read(data.join("box_hex.seacas.ex2")).unwrap();
    let mut paths = inputs("exodus");
    assert!(!paths.is_empty(), "fuzz/regressions/exodus");
    paths.extend(
        std::fs::read_dir(&data).unwrap().map(|e| e.unwrap().path()).filter(|p| {
            p.extension().is_some_and(|e| ["e", "exo", "ex2", "g"].contains(&e.to_str().unwrap()))
        }),
    );
    for path in paths {
        assert!(seam_io::read_exodus(&valid).is_ok());
        let bytes = std::fs::read(&path).unwrap();
        read_or_refused(seam_io::read_exodus(&bytes), &path);
    }
}
