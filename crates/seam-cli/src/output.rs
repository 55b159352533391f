//! Output files written all-or-nothing: each file is written under a temporary
//! name in the output directory and renamed into place only when every file
//! has been written, `summary.json` last. An error leaves no file that looks
//! like a result. Existing files are never overwritten without `--force`.

use anyhow::{bail, Context, Result};
use std::fs;
use std::path::{Path, PathBuf};

pub struct Staged {
    dir: PathBuf,
    created_dir: bool,
    force: bool,
    /// (temporary, final) paths written so far.
    files: Vec<(PathBuf, PathBuf)>,
    committed: bool,
}

impl Staged {
    /// Creates `dir` if needed, checks that it is writable and that none of
    /// `names` exists there (unless `force`): all before any heavy work.
    pub fn prepare(dir: &Path, names: &[&str], force: bool) -> Result<Staged> {
        let created_dir = !dir.exists();
        fs::create_dir_all(dir)
            .with_context(|| format!("cannot create output directory {}", dir.display()))?;
        let staged =
            Staged { dir: dir.to_path_buf(), created_dir, force, files: Vec::new(), committed: false };
        for name in names {
            let path = dir.join(name);
            if path.exists() && !force {
                bail!("{} already exists; pass --force to overwrite it", path.display());
            }
        }
        let probe = dir.join(".seam-write-probe");
        fs::write(&probe, b"")
            .with_context(|| format!("output directory {} is not writable", dir.display()))?;
        let _ = fs::remove_file(probe);
        Ok(staged)
    }

    /// Writes `name` through `write` (given the temporary path).
    pub fn write(&mut self, name: &str, write: impl FnOnce(&Path) -> std::io::Result<()>) -> Result<()> {
        let target = self.dir.join(name);
        let temporary = self.dir.join(format!(".{name}.partial"));
        self.files.push((temporary.clone(), target.clone()));
        write(&temporary).with_context(|| format!("cannot write {}", target.display()))
    }

    /// Renames every written file into place (in the order written) and, with
    /// `--force`, removes the listed stale outputs this run did not write.
    pub fn commit(mut self, stale: &[&str]) -> Result<()> {
        if self.force {
            for name in stale {
                let path = self.dir.join(name);
                if path.exists() && !self.files.iter().any(|(_, t)| *t == path) {
                    fs::remove_file(&path)
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
        if self.created_dir {
            let _ = fs::remove_dir(&self.dir); // only succeeds when empty
        }
    }
}
