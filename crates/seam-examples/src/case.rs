//! An example's problem written as a case and solved in memory as `seam
//! solve` solves that case.

use crate::{Failure, Options};
use anyhow::anyhow;
use seam_case::solve::{solve_problem, SolveOptions, Solved};
use seam_case::write::{write_problem_case, CaseFiles};
use seam_case::Case;
use seam_fem::Problem;
use std::path::PathBuf;

/// Writes `problem` as a case in the example's output directory (its meshes
/// and `case.toml`, starting with the comment lines `about`), reads that case
/// back as `seam solve` does, solves the problem in memory and writes the
/// results where `seam solve DIR/case.toml` writes them. Before anything is
/// written, it checks that none of the case's files, its results and `extra`
/// (the example's own outputs) exists, unless `force`.
///
/// # Errors
/// As [`write_problem_case`], [`Case::read`], [`solve_problem`] and
/// [`Solved::write`].
pub fn solve_example(
    problem: Problem,
    o: &Options,
    about: &[String],
    extra: &[PathBuf],
) -> Result<Solved, Failure> {
    let files = CaseFiles::of(&problem, &o.output);
    if !o.force {
        if let Some(path) = files.all().chain(extra).find(|p| p.exists()) {
            return Err(anyhow!("{} already exists; pass --force to overwrite it", path.display()).into());
        }
    }
    let case_path = write_problem_case(&problem, &o.output, about, o.force)?;
    let case = Case::read(&case_path).map_err(|e| Failure::case(&e))?;
    let options = SolveOptions::default();
    let mut solved = solve_problem(problem, case, &case_path, &options)?;
    let out_dir = solved.out_dir.clone();
    solved.summary = solved.write(&out_dir, o.force)?;
    Ok(solved)
}

/// An example's own outputs in its directory: `<name>.md` (the comparison),
/// `<name>.csv` (the data behind it) and `<name>.png` (its picture).
pub struct Report {
    /// `<name>.md`.
    pub md: PathBuf,
    /// `<name>.csv`.
    pub csv: PathBuf,
    /// `<name>.png`.
    pub png: PathBuf,
}

impl Report {
    /// The three files of `name` in `dir`.
    pub fn new(dir: &std::path::Path, name: &str) -> Report {
        Report {
            md: dir.join(format!("{name}.md")),
            csv: dir.join(format!("{name}.csv")),
            png: dir.join(format!("{name}.png")),
        }
    }

    /// The three paths, as `extra` of [`solve_example`].
    pub fn paths(&self) -> [PathBuf; 3] {
        [self.md.clone(), self.csv.clone(), self.png.clone()]
    }

    /// Writes the three files (overwriting only if `force`).
    ///
    /// # Errors
    /// As [`write_files`](seam_case::write::write_files), or if the image
    /// cannot be encoded.
    pub fn write(
        self,
        md: String,
        csv: String,
        image: &crate::picture::Image,
        force: bool,
    ) -> Result<(), Failure> {
        let png = image.png().map_err(|e| Failure::error(&e))?;
        seam_case::write::write_files(
            &[(self.csv, csv.into_bytes()), (self.md, md.into_bytes()), (self.png, png)],
            force,
        )?;
        Ok(())
    }
}
