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
