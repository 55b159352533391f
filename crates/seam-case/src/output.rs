//! Output files written all-or-nothing.
//!
//! [`Staged::prepare`] checks every output of a run before any heavy work: no
//! two outputs are the same file, none is a directory or a device, none is one
//! of the run's inputs (the same file, compared by device and inode, not by
//! name), none exists unless `--force`, and every directory is writable
//! (missing ones are created, and removed again if the run fails).
//!
//! [`Staged::write`] writes each file under a temporary name beside its target.
//! [`Staged::commit`] then swaps them in as one transaction: every existing
//! target (and, with `--force`, every stale output to remove) is first moved
//! aside under a backup name, then the new files are renamed into place, in
//! the order written (so a summary written last appears last), and only then
//! are the backups deleted. If any step fails, what was placed is removed and
//! the backups are renamed back: the user has either the complete new set or
//! exactly the old files, never a mix. Nothing is overwritten without
//! `--force`, and an input never.

use anyhow::{bail, Context, Result};

use std::fs;
use std::path::{Path, PathBuf};

/// Output files of one run, written all-or-nothing (module doc).
pub struct Staged {
    force: bool,
    /// Directories this run created, deepest last.
    created_dirs: Vec<PathBuf>,
    /// (temporary, final) paths written so far.
    files: Vec<(PathBuf, PathBuf)>,
    committed: bool,
}

impl Staged {
    /// Checks the outputs `targets` of a run that reads `inputs` (module doc)
    /// and creates their missing parent directories: all before any heavy work.
    pub fn prepare(targets: &[PathBuf], inputs: &[PathBuf], force: bool) -> Result<Staged> {
        let mut staged = Staged { force, created_dirs: Vec::new(), files: Vec::new(), committed: false };
        for target in targets {
            let dir = parent(target);
            match fs::metadata(dir) {
                Ok(m) if !m.is_dir() => {
                    bail!("cannot write {}: {} is not a directory", target.display(), dir.display())
                }
                Ok(_) => {}
                Err(_) => {
                    let mut missing: Vec<PathBuf> =
                        dir.ancestors().take_while(|d| !d.exists()).map(Path::to_path_buf).collect();
                    fs::create_dir_all(dir)
                        .with_context(|| format!("cannot create output directory {}", dir.display()))?;
                    missing.reverse();
                    staged.created_dirs.extend(missing);
                }
            }
            check_target(target, inputs, force)?;
        }
        let mut seen: Vec<(PathBuf, &PathBuf)> = Vec::new();
        for target in targets {
            let identity = identity(target);
            if let Some((_, first)) = seen.iter().find(|(id, _)| *id == identity) {
                bail!(
                    "two outputs of this run would be written to the same file: {} and {}",
                    first.display(),
                    target.display()
                );
            }
            seen.push((identity, target));
        }
        let mut probed: Vec<&Path> = Vec::new();
        for target in targets {
            let dir = parent(target);
            if !probed.contains(&dir) {
                let probe = dir.join(format!(".seam-write-probe-{}", std::process::id()));
                fs::write(&probe, b"")
                    .with_context(|| format!("output directory {} is not writable", dir.display()))?;
                let _ = fs::remove_file(probe);
                probed.push(dir);
            }
        }
        Ok(staged)
    }

    /// Writes `target` through `write` (given the temporary path).
    pub fn write(&mut self, target: &Path, write: impl FnOnce(&Path) -> std::io::Result<()>) -> Result<()> {
        let temporary = sibling(target, "partial");
        self.files.push((temporary.clone(), target.to_path_buf()));
        write(&temporary).with_context(|| format!("cannot write {}", target.display()))
    }

    /// Swaps every written file into place and, with `--force`, removes the
    /// listed stale outputs this run did not write: all or nothing (module doc).
    pub fn commit(mut self, stale: &[PathBuf]) -> Result<()> {
        let mut replaced: Vec<&Path> = self.files.iter().map(|(_, t)| t.as_path()).collect();
        if self.force {
            replaced.extend(
                stale.iter().map(PathBuf::as_path).filter(|p| !self.files.iter().any(|(_, t)| t == p)),
            );
        }
        let mut aside: Vec<(PathBuf, PathBuf)> = Vec::new();
        let mut placed: Vec<&Path> = Vec::new();
        let swapped = (|| -> Result<()> {
            for &path in &replaced {
                match fs::symlink_metadata(path) {
                    Err(_) => continue, // nothing to replace
                    Ok(m) if m.is_dir() => bail!("cannot replace {}: it is a directory", path.display()),
                    Ok(_) if !self.force => {
                        bail!("{} already exists; pass --force to overwrite it", path.display())
                    }
                    Ok(_) => {}
                }
                let backup = sibling(path, "old");
                fs::rename(path, &backup).with_context(|| format!("cannot replace {}", path.display()))?;
                aside.push((path.to_path_buf(), backup));
            }
            for (temporary, target) in &self.files {
                fs::rename(temporary, target)
                    .with_context(|| format!("cannot write {}", target.display()))?;
                placed.push(target);
            }
            Ok(())
        })();
        if let Err(e) = swapped {
            for path in placed {
                let _ = fs::remove_file(path);
            }
            let mut lost = Vec::new();
            for (path, backup) in aside.iter().rev() {
                if fs::rename(backup, path).is_err() {
                    lost.push(format!("{} is kept as {}", path.display(), backup.display()));
                }
            }
            return Err(match lost.is_empty() {
                true => e.context("nothing was written and no file was changed"),
                false => e.context(format!("nothing was written, but {}", lost.join(", "))),
            });
        }
        self.committed = true;
        for (_, backup) in aside {
            let _ = fs::remove_file(backup);
        }
        Ok(())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if self.committed {
            return;
        }
        for (temporary, _) in &self.files {
            let _ = fs::remove_file(temporary);
        }
        for dir in self.created_dirs.iter().rev() {
            let _ = fs::remove_dir(dir); // only succeeds when empty
        }
    }
}

/// An output may be created, or replaced with `--force`; never a directory, a
/// device or pipe, or an input of the run.
fn check_target(target: &Path, inputs: &[PathBuf], force: bool) -> Result<()> {
    let Ok(meta) = fs::metadata(target) else { return Ok(()) };
    if meta.is_dir() {
        bail!("cannot write {}: it is a directory", target.display());
    }
    if let Some(input) = inputs.iter().find(|input| same_file(target, input)) {
        bail!(
            "cannot write {}: it is the input {} of this run (an input is never overwritten)",
            target.display(),
            input.display()
        );
    }
    if !meta.is_file() {
        bail!("cannot write {}: it is not a regular file", target.display());
    }
    if !force {
        bail!("{} already exists; pass --force to overwrite it", target.display());
    }
    Ok(())
}

/// Whether `a` and `b` are the same existing file (symbolic links followed;
/// hard links and other names of one file included).
fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (fs::metadata(a), fs::metadata(b)) else { return false };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        matches!((fs::canonicalize(a), fs::canonicalize(b)), (Ok(x), Ok(y)) if x == y)
    }
}

/// The file `path` names, for comparing outputs: its directory resolved (it
/// exists once [`Staged::prepare`] has created it) and its file name.
fn identity(path: &Path) -> PathBuf {
    let dir = fs::canonicalize(parent(path)).unwrap_or_else(|_| parent(path).to_path_buf());
    match path.file_name() {
        Some(name) => dir.join(name),
        None => dir,
    }
}

/// A hidden name beside `path` for this process: `.NAME.seam-PID.SUFFIX`.
fn sibling(path: &Path, suffix: &str) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    parent(path).join(format!(".{name}.seam-{}.{suffix}", std::process::id()))
}

/// The directory a path lies in ("." for a bare file name).
fn parent(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_failed_swap_restores_every_old_file_and_leaves_no_temporary() {
        let tmp = tempfile::tempdir().unwrap();
        let (a, b) = (tmp.path().join("a.txt"), tmp.path().join("b.txt"));
        fs::write(&a, "old a").unwrap();
        fs::write(&b, "old b").unwrap();
        let mut out = Staged::prepare(&[a.clone(), b.clone()], &[], true).unwrap();
        out.write(&a, |p| fs::write(p, "new a")).unwrap();
        out.write(&b, |p| fs::write(p, "new b")).unwrap();
        // b becomes a directory after the checks: the second rename fails.
        fs::remove_file(&b).unwrap();
        fs::create_dir(&b).unwrap();
        fs::write(b.join("keep"), "x").unwrap();
        let e = format!("{:#}", out.commit(&[]).unwrap_err());
        assert!(e.contains("nothing was written and no file was changed"), "{e}");
        assert!(e.contains("b.txt") && e.contains("is a directory"), "{e}");
        assert_eq!(fs::read_to_string(&a).unwrap(), "old a");
        assert_eq!(names(tmp.path()), ["a.txt", "b.txt"]);
        assert_eq!(names(&b), ["keep"]);
    }

    #[test]
    fn a_failed_rename_into_place_rolls_back_what_was_placed() {
        let tmp = tempfile::tempdir().unwrap();
        let (a, b, c) = (tmp.path().join("a"), tmp.path().join("b"), tmp.path().join("c"));
        fs::write(&a, "old a").unwrap();
        let mut out = Staged::prepare(&[a.clone(), b.clone(), c.clone()], &[], true).unwrap();
        out.write(&a, |p| fs::write(p, "new a")).unwrap();
        out.write(&b, |p| fs::write(p, "new b")).unwrap();
        out.write(&c, |p| fs::write(p, "new c")).unwrap();
        // The temporary of c disappears: its rename fails after a and b are placed.
        fs::remove_file(sibling(&c, "partial")).unwrap();
        assert!(out.commit(&[]).is_err());
        assert_eq!(fs::read_to_string(&a).unwrap(), "old a");
        assert_eq!(names(tmp.path()), ["a"]);
    }

    #[test]
    fn a_commit_replaces_all_and_removes_stale_outputs() {
        let tmp = tempfile::tempdir().unwrap();
        let (a, stale) = (tmp.path().join("a"), tmp.path().join("T.mtx"));
        fs::write(&a, "old").unwrap();
        fs::write(&stale, "old T").unwrap();
        let mut out = Staged::prepare(std::slice::from_ref(&a), &[], true).unwrap();
        out.write(&a, |p| fs::write(p, "new")).unwrap();
        out.commit(&[stale]).unwrap();
        assert_eq!(fs::read_to_string(&a).unwrap(), "new");
        assert_eq!(names(tmp.path()), ["a"]);
    }

    #[test]
    fn outputs_that_are_inputs_directories_or_twice_the_same_are_refused_even_with_force() {
        let tmp = tempfile::tempdir().unwrap();
        let input = tmp.path().join("mesh.msh");
        fs::write(&input, "mesh").unwrap();
        let link = tmp.path().join("link.vtu");
        fs::hard_link(&input, &link).unwrap();
        let sub = tmp.path().join("sub");
        fs::create_dir(&sub).unwrap();
        let inputs = [input.clone()];
        let refused =
            |targets: &[PathBuf]| format!("{:#}", Staged::prepare(targets, &inputs, true).err().unwrap());
        let e = refused(std::slice::from_ref(&link));
        assert!(e.contains("it is the input") && e.contains("mesh.msh"), "{e}");
        assert!(refused(std::slice::from_ref(&sub)).contains("it is a directory"));
        let twice = refused(&[tmp.path().join("x.json"), sub.join("../x.json")]);
        assert!(twice.contains("two outputs of this run would be written to the same file"), "{twice}");
        let not_dir = refused(&[input.join("B.mtx")]);
        assert!(not_dir.contains("is not a directory"), "{not_dir}");
        assert_eq!(fs::read_to_string(&input).unwrap(), "mesh");
        if Path::new("/dev/null").exists() {
            let e = format!("{:#}", Staged::prepare(&[PathBuf::from("/dev/null")], &[], true).err().unwrap());
            assert!(e.contains("is not a regular file"), "{e}");
        }
    }
}
