//! Output files written all-or-nothing, safe under kills and concurrent runs.
//!
//! [`Staged::prepare`] checks every output of a run before any heavy work: no
//! two outputs are the same file, none is a directory or a device, none is one
//! of the run's inputs (the same file, compared by device and inode, not by
//! name), none exists unless `--force`, and every directory is writable
//! (missing ones are created, and removed again if the run fails).
//!
//! **One run at a time per directory.** Before those checks, `prepare` takes
//! an advisory lock (`flock`) on the file `.seam.lock` in each output
//! directory, in the order of their resolved paths, and holds it until the
//! outputs are committed or dropped. A second run writing into the same
//! directory waits for the first to finish, after one notice ("waiting for
//! another seam run (pid N) …"); it then sees the first run's files as they
//! are (so without `--force` it refuses to replace them). The operating
//! system releases the lock of a killed run; the lock file itself is removed
//! by whoever releases the lock normally (or by the next run, on Unix).
//!
//! **Recovery.** Still under the lock, `prepare` finishes what an interrupted
//! run (killed, or its machine stopped) left in those directories: a
//! transaction that had reached its commit point is rolled forward (its new
//! files put in place), any other is rolled back (the old files kept or put
//! back); then its journal and every hidden leftover (`.NAME.seam-PID.partial`,
//! `.NAME.seam-PID.old`, `.seam-write-probe-PID`, journals and markers) is
//! removed. A transaction spanning several directories is recovered in all
//! of them together (their locks are taken too). What was recovered is said
//! in one notice line. Notices go to the handler set with
//! [`set_notice_handler`] (the CLI prints them on stderr, Python turns them
//! into warnings) and are kept by [`Staged::notices`].
//!
//! [`Staged::write`] writes each file under a temporary name beside its target
//! and flushes it to disk. [`Staged::commit`] then swaps them in as one
//! transaction:
//!
//! 1. a journal `.seam-ID.journal` is written (and flushed) into every
//!    directory involved, naming every target, its temporary file and the
//!    backup name of the file it replaces;
//! 2. the commit point: the marker `.seam-ID.commit` is created in the first
//!    of those directories;
//! 3. every existing target (and, with `--force`, every stale output to
//!    remove) is moved aside under its backup name, then the new files are
//!    renamed into place in the order written (so a summary written last
//!    appears last);
//! 4. the backups, the journals and last the marker are removed.
//!
//! A kill before step 2 leaves the old files untouched (the next run removes
//! the temporary files); a kill after it leaves a set the next run completes.
//! If a step of 3 fails (not a kill), the marker is removed first, then what
//! was placed is removed and the backups are renamed back: the user has either
//! the complete new set or exactly the old files, never a mix. Nothing is
//! overwritten without `--force`, and an input never.

use anyhow::{anyhow, bail, Context, Result};
use fs4::{FileExt, TryLockError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use std::ffi::{OsStr, OsString};
use std::fs::{self, File, OpenOptions};
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, PoisonError, RwLock};

/// The lock file of an output directory (module doc).
const LOCK: &str = ".seam.lock";

/// A notice handler (module doc).
type Handler = Arc<dyn Fn(&str) + Send + Sync>;

static HANDLER: RwLock<Option<Handler>> = RwLock::new(None);

/// Sets where the one-line notices of output directories go for the whole
/// process: that a run waits for another one writing into the same directory,
/// and what was recovered from an interrupted run (module doc). Without a
/// handler they are only kept by [`Staged::notices`].
pub fn set_notice_handler(handler: impl Fn(&str) + Send + Sync + 'static) {
    *HANDLER.write().unwrap_or_else(PoisonError::into_inner) = Some(Arc::new(handler));
}

/// Passes `line` to the notice handler, if any, and keeps it in `kept`.
fn notify(kept: &mut Vec<String>, line: String) {
    let handler = HANDLER.read().unwrap_or_else(PoisonError::into_inner).clone();
    if let Some(handler) = handler {
        handler(&line);
    }
    kept.push(line);
}

/// Output files of one run, written all-or-nothing (module doc).
pub struct Staged {
    force: bool,
    /// Directories this run created, deepest last.
    created_dirs: Vec<PathBuf>,
    /// (temporary, final) paths written so far.
    files: Vec<(PathBuf, PathBuf)>,
    /// The locks of the output directories, in the order taken.
    locks: Vec<DirLock>,
    notices: Vec<String>,
    steps: Steps,
    committed: bool,
}

impl Staged {
    /// Locks the directories of the outputs `targets` of a run that reads
    /// `inputs`, recovers what an interrupted run left there, checks the
    /// outputs (module doc) and creates their missing parent directories: all
    /// before any heavy work.
    pub fn prepare(targets: &[PathBuf], inputs: &[PathBuf], force: bool) -> Result<Staged> {
        Staged::prepare_with(targets, inputs, force, Steps::default())
    }

    fn prepare_with(targets: &[PathBuf], inputs: &[PathBuf], force: bool, steps: Steps) -> Result<Staged> {
        let mut staged = Staged {
            force,
            created_dirs: Vec::new(),
            files: Vec::new(),
            locks: Vec::new(),
            notices: Vec::new(),
            steps,
            committed: false,
        };
        let mut dirs: Vec<(PathBuf, PathBuf)> = Vec::new(); // (resolved, as given)
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
            let resolved = fs::canonicalize(dir)
                .with_context(|| format!("cannot resolve output directory {}", dir.display()))?;
            if !dirs.iter().any(|(d, _)| *d == resolved) {
                dirs.push((resolved, dir.to_path_buf()));
            }
        }
        staged.lock_and_recover(dirs)?;
        for target in targets {
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
        // Under the lock: a probe a kill leaves behind is removed by the next run.
        for lock in &staged.locks {
            let probe = lock.dir.join(format!(".seam-write-probe-{}", std::process::id()));
            fs::write(&probe, b"")
                .with_context(|| format!("output directory {} is not writable", lock.shown.display()))?;
            let _ = fs::remove_file(probe);
        }
        Ok(staged)
    }

    /// Writes `target` through `write` (given the temporary path), then
    /// flushes the file to disk. `target` must lie in a directory of the
    /// outputs given to [`Staged::prepare`].
    pub fn write(&mut self, target: &Path, write: impl FnOnce(&Path) -> std::io::Result<()>) -> Result<()> {
        self.lock_of(target)?;
        let temporary = sibling(target, "partial");
        self.files.push((temporary.clone(), target.to_path_buf()));
        write(&temporary)
            .and_then(|()| OpenOptions::new().write(true).open(&temporary)?.sync_all())
            .with_context(|| format!("cannot write {}", target.display()))
    }

    /// The notices of this run so far: waiting for another run, what was
    /// recovered (module doc).
    pub fn notices(&self) -> &[String] {
        &self.notices
    }

    /// Swaps every written file into place and, with `--force`, removes the
    /// listed stale outputs this run did not write: all or nothing (module doc).
    /// The stale outputs must lie in the directories of the outputs.
    pub fn commit(mut self, stale: &[PathBuf]) -> Result<()> {
        let journal = self.journal(stale).context("nothing was written and no file was changed")?;
        if journal.files.is_empty() {
            self.committed = true;
            return Ok(());
        }
        let id = format!("{}-{}", std::process::id(), NEXT_ID.fetch_add(1, Ordering::Relaxed));
        let dirs: Vec<PathBuf> = journal.dirs.iter().map(|d| PathBuf::from(d.os())).collect();
        let marker = dirs[0].join(format!(".seam-{id}.commit"));
        if let Err(e) = self.begin(&journal, &id, &dirs, &marker) {
            if !self.steps.killed() {
                let _ = fs::remove_file(&marker);
                for dir in &dirs {
                    let _ = fs::remove_file(dir.join(journal_name(&id)));
                }
            }
            return Err(e.context("nothing was written and no file was changed"));
        }
        if let Err(e) = self.swap(&journal, &dirs) {
            if self.steps.killed() {
                return Err(e);
            }
            // Undone in the order a recovery would: the decision first.
            let undone = fs::remove_file(&marker)
                .context("cannot remove the commit marker")
                .and_then(|()| roll_back(&journal, &mut self.steps))
                .and_then(|()| remove_journals(&dirs, &id, &mut self.steps));
            return Err(match undone {
                Ok(()) => e.context("nothing was written and no file was changed"),
                Err(u) => e.context(format!(
                    "the old files could not all be put back ({}): the next seam run writing into {} recovers a whole set",
                    crate::one_line(u.as_ref()),
                    dirs[0].display()
                )),
            });
        }
        self.committed = true;
        // The new set is in place: a failure from here on leaves only hidden
        // leftovers, which the next run removes (module doc).
        let _ = finish(&journal, &id, &dirs, &marker, &mut self.steps);
        Ok(())
    }

    /// The journal of a commit: every written file and, with `--force`, every
    /// stale output that exists; checked (module doc).
    fn journal(&self, stale: &[PathBuf]) -> Result<Journal> {
        let mut replaced: Vec<(&Path, Option<&Path>)> = self
            .files
            .iter()
            .map(|(temporary, target)| (target.as_path(), Some(temporary.as_path())))
            .collect();
        if self.force {
            replaced.extend(
                stale
                    .iter()
                    .filter(|p| !self.files.iter().any(|(_, t)| t == *p))
                    .map(|p| (p.as_path(), None)),
            );
        }
        let mut journal =
            Journal { version: 1, pid: std::process::id(), dirs: Vec::new(), files: Vec::new() };
        for (target, temporary) in replaced {
            let exists = match fs::symlink_metadata(target) {
                Err(_) => false,
                Ok(m) if m.is_dir() => bail!("cannot replace {}: it is a directory", target.display()),
                Ok(_) if !self.force => {
                    bail!("{} already exists; pass --force to overwrite it", target.display())
                }
                Ok(_) => true,
            };
            if temporary.is_none() && !exists {
                continue; // a stale output that is not there
            }
            let dir = Name::of(self.lock_of(target)?.dir.as_os_str());
            let index = match journal.dirs.iter().position(|d| *d == dir) {
                Some(i) => i,
                None => {
                    journal.dirs.push(dir);
                    journal.dirs.len() - 1
                }
            };
            let name = |p: &Path| Name::of(p.file_name().unwrap_or_default());
            journal.files.push(Entry {
                dir: index,
                name: name(target),
                partial: temporary.map(name),
                backup: exists.then(|| name(&sibling(target, "old"))),
            });
        }
        Ok(journal)
    }

    /// Steps 1 and 2 of the commit (module doc): the journals, then the marker.
    fn begin(&mut self, journal: &Journal, id: &str, dirs: &[PathBuf], marker: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(journal).context("the journal")? + "\n";
        for dir in dirs {
            self.steps.next()?;
            let path = dir.join(journal_name(id));
            let mut file = OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
                .with_context(|| format!("cannot write {}", path.display()))?;
            file.write_all(text.as_bytes())
                .and_then(|()| file.sync_all())
                .with_context(|| format!("cannot write {}", path.display()))?;
        }
        dirs.iter().for_each(|d| sync_dir(d));
        self.steps.next()?;
        File::create_new(marker)
            .and_then(|f| f.sync_all())
            .with_context(|| format!("cannot write {}", marker.display()))?;
        sync_dir(&dirs[0]);
        Ok(())
    }

    /// Step 3 of the commit (module doc): the old files aside, the new ones in.
    fn swap(&mut self, journal: &Journal, dirs: &[PathBuf]) -> Result<()> {
        for (target, backup) in journal.files.iter().filter_map(|f| Some((f.target(dirs), f.backup(dirs)?))) {
            self.steps.next()?;
            fs::rename(&target, backup).with_context(|| format!("cannot replace {}", target.display()))?;
        }
        for (target, partial) in journal.files.iter().filter_map(|f| Some((f.target(dirs), f.partial(dirs)?)))
        {
            self.steps.next()?;
            fs::rename(partial, &target).with_context(|| format!("cannot write {}", target.display()))?;
        }
        dirs.iter().for_each(|d| sync_dir(d));
        Ok(())
    }

    /// The lock of the directory `path` lies in.
    fn lock_of(&self, path: &Path) -> Result<&DirLock> {
        let dir = fs::canonicalize(parent(path)).unwrap_or_default();
        self.locks.iter().find(|l| l.dir == dir).ok_or_else(|| {
            anyhow!("cannot write {}: its directory is not among the outputs of this run", path.display())
        })
    }

    /// Locks `dirs` (resolved, as given), and the other directories of any
    /// interrupted transaction found in them, and recovers (module doc).
    fn lock_and_recover(&mut self, mut dirs: Vec<(PathBuf, PathBuf)>) -> Result<()> {
        let found = loop {
            dirs.sort();
            self.locks.clear();
            for (dir, shown) in &dirs {
                let lock = DirLock::acquire(dir, shown, &mut self.notices)?;
                self.locks.push(lock);
            }
            let found = Found::scan(&self.locks)?;
            let more: BTreeSet<PathBuf> = found
                .journals
                .iter()
                .flat_map(|(_, j)| j.dirs.iter().map(|d| PathBuf::from(d.os())))
                .filter(|d| d.is_dir() && !dirs.iter().any(|(known, _)| known == d))
                .collect();
            if more.is_empty() {
                break found;
            }
            dirs.extend(more.into_iter().map(|d| (d.clone(), d)));
        };
        let mut recovered = Recovered::default();
        for (id, journal) in &found.journals {
            let dirs: Vec<PathBuf> = journal.dirs.iter().map(|d| PathBuf::from(d.os())).collect();
            let marker = dirs[0].join(format!(".seam-{id}.commit"));
            let done = match marker.exists() {
                true => finish(journal, id, &dirs, &marker, &mut self.steps)
                    .map(|()| "completed, its new files put in place"),
                false => roll_back(journal, &mut self.steps)
                    .and_then(|()| remove_journals(&dirs, id, &mut self.steps))
                    .map(|()| "rolled back, the old files kept"),
            };
            let done = done.with_context(|| {
                format!(
                    "cannot recover the interrupted write of seam (pid {}) into {}",
                    journal.pid,
                    self.shown(&dirs[0])
                )
            })?;
            dirs.iter().for_each(|d| recovered.touched(self.shown(d)));
            recovered.runs.push(format!("an interrupted write (seam pid {}) was {done}", journal.pid));
        }
        for path in &found.unreadable {
            self.steps.next()?;
            fs::remove_file(path).with_context(|| format!("cannot remove {}", path.display()))?;
            recovered.touched(self.shown(parent(path)));
            recovered.files += 1;
        }
        for lock in &self.locks {
            let before = (recovered.files, recovered.restored.len());
            remove_leftovers(&lock.dir, &mut self.steps, &mut recovered)
                .with_context(|| format!("cannot clean the output directory {}", lock.shown.display()))?;
            if (recovered.files, recovered.restored.len()) != before {
                recovered.touched(lock.shown.display().to_string());
            }
        }
        if let Some(line) = recovered.line() {
            notify(&mut self.notices, line);
        }
        Ok(())
    }

    /// How the user named the resolved directory `dir`.
    fn shown(&self, dir: &Path) -> String {
        let lock = self.locks.iter().find(|l| l.dir == dir);
        lock.map_or(dir, |l| &l.shown).display().to_string()
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if self.steps.killed() {
            // A simulated kill: the system releases the locks, nothing else happens.
            self.locks.iter_mut().for_each(|l| l.keep = true);
            return;
        }
        if !self.committed {
            for (temporary, _) in &self.files {
                let _ = fs::remove_file(temporary);
            }
        }
        self.locks.clear();
        if !self.committed {
            for dir in self.created_dirs.iter().rev() {
                let _ = fs::remove_dir(dir); // only succeeds when empty
            }
        }
    }
}

/// Ids of the transactions of this process (module doc).
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

/// The journal of a transaction (module doc), one copy in each of its
/// directories.
#[derive(Serialize, Deserialize)]
struct Journal {
    /// The format, 1.
    #[serde(rename = "seam_output_journal")]
    version: u32,
    /// The process that wrote it.
    pid: u32,
    /// The resolved directories; the first holds the commit marker.
    dirs: Vec<Name>,
    /// In the order the files are placed.
    files: Vec<Entry>,
}

/// A target of a transaction.
#[derive(Serialize, Deserialize)]
struct Entry {
    /// Index into the journal's directories.
    dir: usize,
    /// The file name of the target.
    name: Name,
    /// Its new file's temporary name; none for a stale output to remove.
    partial: Option<Name>,
    /// The name the existing file is moved aside to; none if there is none.
    backup: Option<Name>,
}

impl Entry {
    fn in_dir(&self, dirs: &[PathBuf], name: &Name) -> PathBuf {
        dirs.get(self.dir).map_or_else(PathBuf::new, |d| d.join(name.os()))
    }

    fn target(&self, dirs: &[PathBuf]) -> PathBuf {
        self.in_dir(dirs, &self.name)
    }

    fn partial(&self, dirs: &[PathBuf]) -> Option<PathBuf> {
        self.partial.as_ref().map(|n| self.in_dir(dirs, n))
    }

    fn backup(&self, dirs: &[PathBuf]) -> Option<PathBuf> {
        self.backup.as_ref().map(|n| self.in_dir(dirs, n))
    }
}

/// A file or directory name in a journal: text when it is UTF-8, else the
/// operating system's encoding as serde writes it.
#[derive(Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
enum Name {
    Text(String),
    Raw(OsString),
}

impl Name {
    fn of(name: &OsStr) -> Name {
        match name.to_str() {
            Some(s) => Name::Text(s.to_string()),
            None => Name::Raw(name.to_os_string()),
        }
    }

    fn os(&self) -> OsString {
        match self {
            Name::Text(s) => s.into(),
            Name::Raw(s) => s.clone(),
        }
    }
}

/// The journal file of the transaction `id`.
fn journal_name(id: &str) -> String {
    format!(".seam-{id}.journal")
}

/// Rolls a transaction back (module doc): every backup renamed back, every
/// new file placed where no old one was removed, every temporary removed.
/// Idempotent, so an interrupted roll-back can be repeated.
fn roll_back(journal: &Journal, steps: &mut Steps) -> Result<()> {
    let dirs: Vec<PathBuf> = journal.dirs.iter().map(|d| PathBuf::from(d.os())).collect();
    for f in journal.files.iter().rev() {
        let (target, partial) = (f.target(&dirs), f.partial(&dirs));
        match f.backup(&dirs) {
            Some(backup) if exists(&backup) => {
                steps.next()?;
                fs::rename(&backup, &target)
                    .with_context(|| format!("cannot restore {}", target.display()))?;
            }
            Some(_) => {} // the old file never left
            None if partial.as_ref().is_some_and(|p| !exists(p)) && exists(&target) => {
                steps.next()?; // a new file placed where there was none
                fs::remove_file(&target).with_context(|| format!("cannot remove {}", target.display()))?;
            }
            None => {}
        }
        if let Some(partial) = partial.filter(|p| exists(p)) {
            steps.next()?;
            fs::remove_file(&partial).with_context(|| format!("cannot remove {}", partial.display()))?;
        }
    }
    dirs.iter().for_each(|d| sync_dir(d));
    Ok(())
}

/// Rolls a committed transaction forward (module doc): every new file still
/// under its temporary name renamed into place, every stale output removed;
/// then the backups, the journals and the marker. Idempotent.
fn finish(journal: &Journal, id: &str, dirs: &[PathBuf], marker: &Path, steps: &mut Steps) -> Result<()> {
    for f in &journal.files {
        let target = f.target(dirs);
        match f.partial(dirs) {
            Some(partial) if exists(&partial) => {
                steps.next()?;
                fs::rename(&partial, &target)
                    .with_context(|| format!("cannot write {}", target.display()))?;
            }
            Some(_) => {} // in place
            None if exists(&target) => {
                steps.next()?;
                fs::remove_file(&target).with_context(|| format!("cannot remove {}", target.display()))?;
            }
            None => {}
        }
    }
    dirs.iter().for_each(|d| sync_dir(d));
    for backup in journal.files.iter().filter_map(|f| f.backup(dirs)).filter(|b| exists(b)) {
        steps.next()?;
        fs::remove_file(&backup).with_context(|| format!("cannot remove {}", backup.display()))?;
    }
    remove_journals(dirs, id, steps)?;
    steps.next()?;
    match fs::remove_file(marker) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(e).with_context(|| format!("cannot remove {}", marker.display()))
        }
        _ => Ok(()),
    }
}

/// Removes the journals of the transaction `id`, the first directory's last
/// (while it is there with the marker, a recovery rolls forward).
fn remove_journals(dirs: &[PathBuf], id: &str, steps: &mut Steps) -> Result<()> {
    for dir in dirs.iter().skip(1).chain(dirs.first()) {
        let path = dir.join(journal_name(id));
        if exists(&path) {
            steps.next()?;
            fs::remove_file(&path).with_context(|| format!("cannot remove {}", path.display()))?;
        }
    }
    Ok(())
}

/// The journals found in the locked directories.
struct Found {
    /// Per transaction id, its journal (the first readable copy).
    journals: Vec<(String, Journal)>,
    /// Journals that cannot be read: written only in part, so the
    /// transaction never reached its commit point (module doc).
    unreadable: Vec<PathBuf>,
}

impl Found {
    fn scan(locks: &[DirLock]) -> Result<Found> {
        let mut found = Found { journals: Vec::new(), unreadable: Vec::new() };
        for lock in locks {
            let entries = fs::read_dir(&lock.dir)
                .with_context(|| format!("cannot read the output directory {}", lock.shown.display()))?;
            for entry in entries.flatten() {
                let name = entry.file_name();
                let Some(id) = name.to_str().and_then(|n| n.strip_prefix(".seam-")?.strip_suffix(".journal"))
                else {
                    continue;
                };
                if found.journals.iter().any(|(known, _)| known == id) {
                    continue;
                }
                let journal = fs::read(entry.path())
                    .ok()
                    .and_then(|bytes| serde_json::from_slice::<Journal>(&bytes).ok())
                    .filter(|j| j.version == 1 && !j.dirs.is_empty());
                match journal {
                    Some(j) => found.journals.push((id.to_string(), j)),
                    None => found.unreadable.push(entry.path()),
                }
            }
        }
        // A readable copy elsewhere recovers (and removes) the unreadable one.
        let ids: Vec<String> = found.journals.iter().map(|(id, _)| journal_name(id)).collect();
        found.unreadable.retain(|p| !ids.iter().any(|n| p.file_name() == Some(OsStr::new(n))));
        Ok(found)
    }
}

/// What a recovery did (module doc).
#[derive(Default)]
struct Recovered {
    /// The directories concerned, as the user named them.
    dirs: Vec<String>,
    /// One phrase per transaction recovered.
    runs: Vec<String>,
    /// Hidden leftovers that no journal names, removed or put back.
    files: usize,
    /// Files put back that an older seam had moved aside.
    restored: Vec<String>,
}

impl Recovered {
    fn touched(&mut self, dir: String) {
        if !self.dirs.contains(&dir) {
            self.dirs.push(dir);
        }
    }

    /// The notice (module doc), if anything was recovered.
    fn line(&self) -> Option<String> {
        if self.dirs.is_empty() {
            return None;
        }
        let mut parts = self.runs.clone();
        if !self.restored.is_empty() {
            parts.push(format!("{} moved aside by an older seam put back", self.restored.join(", ")));
        }
        if self.files > 0 {
            let s = if self.files == 1 { "" } else { "s" };
            parts.push(format!("{} leftover file{s} of interrupted runs removed", self.files));
        }
        Some(format!("recovered {}: {}", self.dirs.join(", "), parts.join("; ")))
    }
}

/// Removes the hidden leftovers of interrupted runs from `dir` (module doc),
/// once every journal there is recovered. A backup `.NAME.seam-PID.old` that
/// no journal names was moved aside by a seam without journals: it is put
/// back when NAME is missing (the newest, if several), else removed.
fn remove_leftovers(dir: &Path, steps: &mut Steps, recovered: &mut Recovered) -> Result<()> {
    let mut backups: Vec<(std::time::SystemTime, String, PathBuf)> = Vec::new();
    for entry in fs::read_dir(dir)?.flatten() {
        let name = entry.file_name();
        let Some(text) = name.to_str() else { continue };
        match Leftover::of(text) {
            Some(Leftover::Backup(original)) => {
                let modified = entry.metadata().and_then(|m| m.modified()).unwrap_or(std::time::UNIX_EPOCH);
                backups.push((modified, original.to_string(), entry.path()));
            }
            Some(Leftover::Other) => {
                steps.next()?;
                fs::remove_file(entry.path())
                    .with_context(|| format!("cannot remove {}", entry.path().display()))?;
                recovered.files += 1;
            }
            None => {}
        }
    }
    backups.sort_by_key(|b| std::cmp::Reverse(b.0)); // newest first
    for (_, original, backup) in backups {
        steps.next()?;
        let target = dir.join(&original);
        if exists(&target) {
            fs::remove_file(&backup).with_context(|| format!("cannot remove {}", backup.display()))?;
        } else {
            fs::rename(&backup, &target).with_context(|| format!("cannot restore {}", target.display()))?;
            recovered.restored.push(original);
            continue;
        }
        recovered.files += 1;
    }
    Ok(())
}

/// A hidden file seam leaves behind (module doc).
#[derive(Debug, PartialEq)]
enum Leftover<'a> {
    /// `.NAME.seam-PID.old`: the file NAME moved aside.
    Backup(&'a str),
    /// A temporary file, a write probe, a journal or a commit marker.
    Other,
}

impl Leftover<'_> {
    fn of(name: &str) -> Option<Leftover<'_>> {
        let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
        let id = |s: &str| {
            let mut parts = s.split('-');
            parts.clone().count() == 2 && parts.all(digits)
        };
        if name.strip_prefix(".seam-write-probe-").is_some_and(digits) {
            return Some(Leftover::Other);
        }
        if let Some(rest) = name.strip_prefix(".seam-") {
            if rest.strip_suffix(".commit").or_else(|| rest.strip_suffix(".journal")).is_some_and(id) {
                return Some(Leftover::Other);
            }
        }
        let rest = name.strip_prefix('.')?;
        let (rest, backup) = match (rest.strip_suffix(".partial"), rest.strip_suffix(".old")) {
            (Some(r), _) => (r, false),
            (_, Some(r)) => (r, true),
            _ => return None,
        };
        let (original, pid) = rest.rsplit_once(".seam-")?;
        if original.is_empty() || !digits(pid) {
            return None;
        }
        Some(if backup { Leftover::Backup(original) } else { Leftover::Other })
    }
}

/// The lock of an output directory (module doc), released when dropped.
struct DirLock {
    /// The directory, resolved.
    dir: PathBuf,
    /// As the user named it.
    shown: PathBuf,
    file: File,
    /// Leave the lock file when released (a simulated kill).
    keep: bool,
}

impl DirLock {
    /// Takes the lock of `dir` (resolved; `shown` as named), waiting for
    /// another holder after a notice kept in `notices`.
    fn acquire(dir: &Path, shown: &Path, notices: &mut Vec<String>) -> Result<DirLock> {
        let path = dir.join(LOCK);
        let unwritable = || format!("output directory {} is not writable", shown.display());
        let mut waited = false;
        loop {
            let file =
                match OpenOptions::new().read(true).write(true).create(true).truncate(false).open(&path) {
                    Ok(file) => file,
                    // Another user's lock file in a shared directory.
                    Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied && path.exists() => {
                        File::open(&path).with_context(unwritable)?
                    }
                    Err(e) => return Err(e).with_context(unwritable),
                };
            // fs4's trait, not std's File::try_lock (Rust 1.89; seam builds with 1.85).
            match FileExt::try_lock(&file) {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    if !waited {
                        let pid = fs::read_to_string(&path).ok().and_then(|t| t.trim().parse::<u32>().ok());
                        let pid = pid.map_or(String::new(), |p| format!(" (pid {p})"));
                        let line = format!(
                            "waiting for another seam run{pid} writing into {} to finish",
                            shown.display()
                        );
                        notify(notices, line);
                        waited = true;
                    }
                    FileExt::lock(&file).with_context(|| format!("cannot lock {}", path.display()))?;
                }
                Err(TryLockError::Error(e)) => {
                    return Err(e).with_context(|| format!("cannot lock {}", path.display()))
                }
            }
            // The last holder removes the file before it unlocks: locked, but
            // no longer the directory's lock file, it is tried again.
            if still_named(&file, &path) {
                let mut lock =
                    DirLock { dir: dir.to_path_buf(), shown: shown.to_path_buf(), file, keep: false };
                let _ = lock.file.set_len(0).and_then(|()| writeln!(lock.file, "{}", std::process::id()));
                return Ok(lock);
            }
        }
    }
}

impl Drop for DirLock {
    fn drop(&mut self) {
        // Removed while held (Unix: the next run checks it took the named
        // file); elsewhere the file stays.
        if cfg!(unix) && !self.keep {
            let _ = fs::remove_file(self.dir.join(LOCK));
        }
    }
}

/// Whether `path` still names the open `file`.
fn still_named(file: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), fs::metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (file, path);
        true
    }
}

/// The steps of a commit and of a recovery that change the file system:
/// counted, so that tests can stop the run at any one of them as a kill or
/// an I/O error would.
#[derive(Default)]
struct Steps {
    done: usize,
    #[cfg(test)]
    fault: Option<(usize, Fault)>,
    #[cfg(test)]
    killed: bool,
}

/// What a test makes happen at a step.
#[cfg(test)]
#[derive(Clone, Copy, Debug, PartialEq)]
enum Fault {
    /// The process dies: nothing more is done, the locks are released.
    Kill,
    /// The step fails as an I/O error would.
    Error,
}

impl Steps {
    /// Counts a step about to be taken.
    fn next(&mut self) -> Result<()> {
        self.done += 1;
        #[cfg(test)]
        if let Some((at, fault)) = self.fault {
            if at == self.done {
                self.killed = fault == Fault::Kill;
                bail!("injected {fault:?} at step {at}");
            }
        }
        Ok(())
    }

    /// Whether a test killed the run.
    fn killed(&self) -> bool {
        #[cfg(test)]
        return self.killed;
        #[cfg(not(test))]
        false
    }
}

/// Whether something (a file, a link, a directory) is at `path`.
fn exists(path: &Path) -> bool {
    fs::symlink_metadata(path).is_ok()
}

/// Flushes the entries of the directory `dir` to disk (Unix; best effort).
fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
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

    /// A scratch directory: in memory where there is one (`/dev/shm`), as the
    /// tests below commit hundreds of times and every commit flushes to disk.
    fn scratch() -> tempfile::TempDir {
        let shm = Path::new("/dev/shm");
        match shm.is_dir() {
            true => tempfile::tempdir_in(shm).unwrap_or_else(|_| tempfile::tempdir().unwrap()),
            false => tempfile::tempdir().unwrap(),
        }
    }

    /// Every entry of `dirs` (names relative to `root`) with its text, sorted:
    /// hidden leftovers and lock files included.
    fn contents(root: &Path, dirs: &[&Path]) -> Vec<(String, String)> {
        let mut v = Vec::new();
        for dir in dirs {
            for e in fs::read_dir(dir).unwrap() {
                let path = e.unwrap().path();
                let name = path.strip_prefix(root).unwrap().to_string_lossy().into_owned();
                v.push((name, fs::read_to_string(&path).unwrap_or_default()));
            }
        }
        v.sort();
        v
    }

    /// (path relative to the root, text).
    type Set = [(&'static str, &'static str)];

    fn set(root: &Path, files: &Set) -> Vec<(String, String)> {
        let mut v: Vec<(String, String)> =
            files.iter().map(|(n, t)| (Path::new(n).to_string_lossy().into_owned(), t.to_string())).collect();
        v.sort();
        let _ = root;
        v
    }

    fn lay(root: &Path, files: &Set) {
        for (name, text) in files {
            fs::write(root.join(name), text).unwrap();
        }
    }

    /// One run writing `new` into `root` with `--force` and removing the
    /// stale outputs `stale`, with `fault` at one of its steps.
    fn run(root: &Path, new: &Set, stale: &[&str], fault: Option<(usize, Fault)>) -> Result<()> {
        let targets: Vec<PathBuf> = new.iter().map(|(n, _)| root.join(n)).collect();
        let mut out = Staged::prepare_with(&targets, &[], true, Steps { fault, ..Steps::default() })?;
        for (target, (_, text)) in targets.iter().zip(new) {
            out.write(target, |p| fs::write(p, text))?;
        }
        let stale: Vec<PathBuf> = stale.iter().map(|n| root.join(n)).collect();
        out.commit(&stale)
    }

    /// The next run writing into `dir` (with `fault`): recovers, writes nothing.
    fn next_run(dir: &Path, fault: Option<(usize, Fault)>) -> Result<Vec<String>> {
        let steps = Steps { fault, ..Steps::default() };
        let out = Staged::prepare_with(&[dir.join("new-output")], &[], true, steps)?;
        Ok(out.notices().to_vec())
    }

    const OLD: &Set = &[("a", "old a"), ("b", "old b"), ("T.mtx", "old T")];
    const NEW: &Set = &[("a", "new a"), ("b", "new b"), ("c", "new c")];

    /// Whether a run with `fault` at `at` ran to its end without the fault:
    /// the new set in place and nothing else.
    fn untouched_by_fault(root: &Path) -> bool {
        contents(root, &[root]) == set(root, NEW)
    }

    #[test]
    fn a_kill_at_any_step_of_a_commit_leaves_the_old_or_the_new_set_once_the_next_run_recovered() {
        let mut outcomes = Vec::new();
        for at in 1.. {
            let tmp = scratch();
            let root = tmp.path();
            lay(root, OLD);
            let _ = run(root, NEW, &["T.mtx"], Some((at, Fault::Kill)));
            if untouched_by_fault(root) {
                break;
            }
            // Killed: the lock file stays; the old set or the new one, or a journal.
            let left = contents(root, &[root]);
            assert!(left.iter().any(|(n, _)| n == LOCK), "step {at}: {left:?}");
            let notices = next_run(root, None).unwrap();
            // Up to the commit marker (journal, marker: steps 1 and 2) the old
            // set, after it the new one; nothing else.
            let expected = if at <= 2 { OLD } else { NEW };
            assert_eq!(contents(root, &[root]), set(root, expected), "kill at step {at}, then {notices:?}");
            assert_eq!(notices.len(), 1, "step {at}: {notices:?}");
            assert!(notices[0].starts_with(&format!("recovered {}: ", root.display())), "{notices:?}");
            let pid = std::process::id();
            match at {
                // Only temporary files: nothing to roll back.
                1 => assert!(
                    notices[0].ends_with(": 3 leftover files of interrupted runs removed"),
                    "{notices:?}"
                ),
                2 => {
                    assert!(notices[0].contains(&format!("(seam pid {pid}) was rolled back")), "{notices:?}")
                }
                // Only the marker, after the last journal: a leftover.
                13 => assert!(
                    notices[0].ends_with(": 1 leftover file of interrupted runs removed"),
                    "{notices:?}"
                ),
                _ => assert!(notices[0].contains(&format!("(seam pid {pid}) was completed")), "{notices:?}"),
            }
            outcomes.push(at);
        }
        // Journal, marker, 3 old files aside (a, b, and T.mtx as stale), 3 new
        // in, 3 backups removed, the journal, the marker: 13 steps.
        assert_eq!(outcomes, (1..=13).collect::<Vec<_>>());
    }

    #[test]
    fn an_error_at_any_step_of_a_commit_keeps_the_old_set_or_completes_the_new_one() {
        for at in 1..=13 {
            let tmp = scratch();
            let root = tmp.path();
            lay(root, OLD);
            match run(root, NEW, &["T.mtx"], Some((at, Fault::Error))) {
                // Before the new set is in place (journal, marker, 6 renames): undone.
                Err(e) => {
                    assert!(at <= 8, "step {at}: {e:#}");
                    assert!(
                        format!("{e:#}").contains("nothing was written and no file was changed"),
                        "{e:#}"
                    );
                    assert_eq!(contents(root, &[root]), set(root, OLD), "error at step {at}");
                }
                // In the clean-up: the new set, leftovers the next run removes.
                Ok(()) => {
                    assert!(at > 8, "step {at}");
                    assert_ne!(contents(root, &[root]), set(root, NEW), "step {at} leaves something");
                    let notices = next_run(root, None).unwrap();
                    assert_eq!(notices.len(), 1, "{notices:?}");
                    assert_eq!(contents(root, &[root]), set(root, NEW), "error at step {at}");
                }
            }
        }
    }

    #[test]
    fn a_kill_during_a_recovery_is_recovered_by_the_run_after() {
        let mut recoveries = 0;
        for at in 1..=13 {
            for again in 1.. {
                let tmp = scratch();
                let root = tmp.path();
                lay(root, OLD);
                let _ = run(root, NEW, &["T.mtx"], Some((at, Fault::Kill)));
                if next_run(root, Some((again, Fault::Kill))).is_ok() {
                    // The recovery had fewer steps: it finished.
                    break;
                }
                recoveries += 1;
                next_run(root, None).unwrap();
                let expected = if at <= 2 { OLD } else { NEW };
                assert_eq!(contents(root, &[root]), set(root, expected), "kill at {at}, then at {again}");
            }
        }
        assert!(recoveries >= 40, "{recoveries} recoveries killed");
    }

    /// `seam assemble -o out --segments seg/s.vtu`: one transaction in two
    /// directories, recovered whole by a run that writes into one of them.
    #[test]
    fn a_transaction_over_two_directories_is_recovered_in_both() {
        const OLD2: &Set = &[("out/B.mtx", "old B"), ("seg/s.vtu", "old s"), ("out/summary.json", "old")];
        const NEW2: &Set = &[("out/B.mtx", "new B"), ("seg/s.vtu", "new s"), ("out/summary.json", "new")];
        let mut kills = 0;
        for at in 1.. {
            let tmp = scratch();
            let root = tmp.path();
            let (out, seg) = (root.join("out"), root.join("seg"));
            fs::create_dir(&out).unwrap();
            fs::create_dir(&seg).unwrap();
            lay(root, OLD2);
            let _ = run(root, NEW2, &[], Some((at, Fault::Kill)));
            if contents(root, &[&out, &seg]) == set(root, NEW2) {
                break;
            }
            kills += 1;
            // The next run writes into seg only: once the journals are there
            // (steps 1 and 2) it locks out too and recovers both; before, out
            // keeps the old files and its hidden temporaries, which the next
            // run writing into out removes.
            let notices = next_run(&seg, None).unwrap();
            assert!(notices.len() <= 1, "{notices:?}");
            // Two journals and the marker: the commit point is step 3.
            let expected = if at <= 3 { OLD2 } else { NEW2 };
            let visible: Vec<(String, String)> = contents(root, &[&out, &seg])
                .into_iter()
                .filter(|(n, _)| !Path::new(n).file_name().unwrap().to_string_lossy().starts_with('.'))
                .collect();
            assert_eq!(visible, set(root, expected), "kill at {at}: {notices:?}");
            let _ = next_run(&out, None).unwrap();
            assert_eq!(contents(root, &[&out, &seg]), set(root, expected), "kill at {at}: {notices:?}");
        }
        assert!(kills >= 10, "{kills}");
    }

    #[test]
    fn leftovers_of_older_runs_are_removed_and_moved_aside_files_put_back() {
        let tmp = scratch();
        let root = tmp.path();
        lay(
            root,
            &[
                ("b", "new b"),
                ("notes.seam-1.old", "a user's file"),
                (".hidden", "a user's file"),
                (".a.seam-41.old", "old a"),
                (".b.seam-41.old", "old b"),
                (".c.seam-41.partial", "half of c"),
                (".seam-write-probe-41", ""),
                (".seam-41-0.commit", ""),
                (".seam-41-1.journal", "{\"seam_output_jour"),
                (LOCK, "41\n"),
            ],
        );
        let notices = next_run(root, None).unwrap();
        assert_eq!(
            notices,
            [format!(
                "recovered {}: a moved aside by an older seam put back; 5 leftover files of interrupted runs removed",
                root.display()
            )]
        );
        let expected: &Set = &[
            ("a", "old a"),
            ("b", "new b"),
            ("notes.seam-1.old", "a user's file"),
            (".hidden", "a user's file"),
        ];
        assert_eq!(contents(root, &[root]), set(root, expected));
        assert_eq!(next_run(root, None).unwrap(), Vec::<String>::new(), "nothing left to recover");
    }

    #[test]
    fn leftover_names_are_recognised_exactly() {
        assert_eq!(Leftover::of(".B.mtx.seam-12.old"), Some(Leftover::Backup("B.mtx")));
        assert_eq!(Leftover::of(".x.seam-y.seam-12.partial"), Some(Leftover::Other));
        for name in [".seam-write-probe-7", ".seam-7-0.journal", ".seam-7-3.commit"] {
            assert_eq!(Leftover::of(name), Some(Leftover::Other), "{name}");
        }
        for name in [
            LOCK,
            ".seam-7.journal",
            ".B.mtx.seam-.old",
            "..seam-12.old",
            "B.seam-1.old",
            ".x.seam-1a.partial",
        ] {
            assert_eq!(Leftover::of(name), None, "{name}");
        }
    }

    /// Two runs writing into one directory at once: the second waits, with
    /// one notice, for the first to commit; then it sees the first's files.
    #[test]
    fn a_second_run_waits_for_the_first_and_then_sees_its_files() {
        static HEARD: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());
        set_notice_handler(|line| HEARD.lock().unwrap().push(line.to_string()));
        let tmp = scratch();
        let a = tmp.path().join("a");
        let mut first = Staged::prepare(std::slice::from_ref(&a), &[], false).unwrap();
        first.write(&a, |p| fs::write(p, "first")).unwrap();
        let (a2, tmp2) = (a.clone(), tmp.path().to_path_buf());
        let second = std::thread::spawn(move || {
            let refused =
                Staged::prepare(std::slice::from_ref(&a2), &[], false).err().map(|e| format!("{e:#}"));
            let mut out = Staged::prepare(std::slice::from_ref(&a2), &[], true).unwrap();
            let seen = fs::read_to_string(&a2).unwrap();
            out.write(&a2, |p| fs::write(p, "second")).unwrap();
            out.commit(&[]).unwrap();
            (refused, seen, names(&tmp2))
        });
        std::thread::sleep(std::time::Duration::from_millis(300));
        assert!(!second.is_finished(), "the second run waits");
        assert_eq!(
            names(tmp.path()),
            [".a.seam-".to_string() + &format!("{}.partial", std::process::id()), LOCK.into()]
        );
        first.commit(&[]).unwrap();
        let (refused, seen, left) = second.join().unwrap();
        let refused = refused.unwrap();
        assert!(refused.ends_with("already exists; pass --force to overwrite it"), "{refused}");
        assert_eq!(seen, "first");
        assert_eq!(fs::read_to_string(&a).unwrap(), "second");
        assert_eq!(left, ["a"]);
        let waiting = format!(
            "waiting for another seam run (pid {}) writing into {} to finish",
            std::process::id(),
            tmp.path().display()
        );
        assert!(HEARD.lock().unwrap().contains(&waiting), "{:?}", HEARD.lock().unwrap());
    }
}
