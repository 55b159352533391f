//! Output files written all-or-nothing: each file is written under a temporary
//! name beside its target and renamed into place only when every file has been
//! written (in the order written, so a summary written last appears last). An
//! error leaves no file that looks like a result, and removes the directories
//! this run created if they stay empty. Existing files are never overwritten
//! without `--force`.

use anyhow::{bail, Context, Result};
use std::fs;
use std::path::{Path, PathBuf};

pub struct Staged {
    force: bool,
    /// Directories this run created, deepest last.
    created_dirs: Vec<PathBuf>,
    /// (temporary, final) paths written so far.
    files: Vec<(PathBuf, PathBuf)>,
    committed: bool,
}

impl Staged {
    /// Creates the parent directories of `targets` if needed, checks that they
    /// are writable and that no target exists (unless `force`): all before any
    /// heavy work.
    pub fn prepare(targets: &[PathBuf], force: bool) -> Result<Staged> {
        let mut staged = Staged { force, created_dirs: Vec::new(), files: Vec::new(), committed: false };
        for target in targets {
            let dir = parent(target);
            if !dir.exists() {
                let mut missing: Vec<PathBuf> =
                    dir.ancestors().take_while(|d| !d.exists()).map(Path::to_path_buf).collect();
                fs::create_dir_all(dir)
                    .with_context(|| format!("cannot create output directory {}", dir.display()))?;
                missing.reverse();
                staged.created_dirs.extend(missing);
            }
            if target.exists() && !force {
                bail!("{} already exists; pass --force to overwrite it", target.display());
            }
            let probe = dir.join(".seam-write-probe");
            fs::write(&probe, b"")
                .with_context(|| format!("output directory {} is not writable", dir.display()))?;
            let _ = fs::remove_file(probe);
        }
        Ok(staged)
    }

    /// Writes `target` through `write` (given the temporary path).
    pub fn write(&mut self, target: &Path, write: impl FnOnce(&Path) -> std::io::Result<()>) -> Result<()> {
        let name = target.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let temporary = parent(target).join(format!(".{name}.partial"));
        self.files.push((temporary.clone(), target.to_path_buf()));
        write(&temporary).with_context(|| format!("cannot write {}", target.display()))
    }

    /// Renames every written file into place and, with `--force`, removes the
    /// listed stale outputs this run did not write.
    pub fn commit(mut self, stale: &[PathBuf]) -> Result<()> {
        if self.force {
            for path in stale {
                if path.exists() && !self.files.iter().any(|(_, t)| t == path) {
                    fs::remove_file(path)
                        .with_context(|| format!("cannot remove stale {}", path.display()))?;
                }
            }
        }
        for (temporary, target) in &self.files {
            fs::rename(temporary, target).with_context(|| format!("cannot write {}", target.display()))?;
        }
        self.committed = true;
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

/// The directory a path lies in ("." for a bare file name).
fn parent(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}
