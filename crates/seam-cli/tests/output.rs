//! The output directory of `seam solve` under kills and concurrent runs, with
//! the binary: `seam solve --force` killed (SIGKILL) at moments spread over
//! its run, then the next run's recovery checked; two runs writing into one
//! directory at once.

use crate::common;

use common::{seam, stacked_case, stderr, write_block};
use seam_fem::generate::Side;
use std::collections::BTreeMap;
use std::fs;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The files `seam solve` writes for the cases of [`two_cases`].
const SET: [&str; 4] = ["lower.vtu", "summary.json", "upper.vtu", "upper_bottom_interface.vtu"];

/// Two cases, `a/case.toml` and `b/case.toml`: the same two glued blocks
/// (n × n × n/2 cells below, one fewer across above) pressed by different
/// loads, both writing into `out/`.
fn two_cases(root: &Path, n: usize) {
    let lower = [("bottom", Side::ZMin), ("top", Side::ZMax), ("xmin", Side::XMin), ("ymin", Side::YMin)];
    let upper = [("bottom", Side::ZMin), ("top", Side::ZMax)];
    for (variant, load) in [("a", 1.0), ("b", 2.0)] {
        let dir = root.join(variant);
        fs::create_dir(&dir).unwrap();
        write_block(&dir.join("lower.msh"), [n, n, n / 2], |u, v, w| [u, v, 0.5 * w], &lower);
        write_block(&dir.join("upper.msh"), [n - 1, n - 1, n / 2], |u, v, w| [u, v, 0.5 + 0.5 * w], &upper);
        let rest =
            format!("[[traction]]\nboundary = \"upper:top\"\nt = [0.0, 0.0, -{load:?}]\n\n[output]\ndir = \"../out\"\n");
        let case =
            stacked_case((1000.0, 0.3), (1000.0, 0.3), "kind = \"glue\"\nmultiplier = \"dual\"", &rest);
        fs::write(dir.join("case.toml"), case).unwrap();
    }
}

/// A scratch directory with the [`two_cases`] of size `n` and their results.
fn scene(n: usize) -> (tempfile::TempDir, Reference) {
    let tmp = tempfile::tempdir().unwrap();
    two_cases(tmp.path(), n);
    let reference = Reference::new(tmp.path());
    (tmp, reference)
}

/// `seam solve VARIANT/case.toml [--force]` in `root`, started.
fn start(root: &Path, variant: &str, force: bool) -> Child {
    let case = format!("{variant}/case.toml");
    let mut args = vec!["solve", &case, "--threads", "1"];
    if force {
        args.push("--force");
    }
    Command::new(env!("CARGO_BIN_EXE_seam"))
        .args(&args)
        .current_dir(root)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Every entry of `dir` with its bytes.
fn entries(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path();
            (path.file_name().unwrap().to_string_lossy().into_owned(), fs::read(&path).unwrap_or_default())
        })
        .collect()
}

/// The VTU files of each variant's results, and its summary's "case".
struct Reference {
    vtu: BTreeMap<&'static str, BTreeMap<String, Vec<u8>>>,
}

impl Reference {
    /// Solves both cases once (into `out/`, the last one, b, stays there).
    fn new(root: &Path) -> Reference {
        let mut vtu = BTreeMap::new();
        for variant in ["a", "b"] {
            let o = seam(&["solve", &format!("{variant}/case.toml"), "--threads", "1", "--force"], root);
            assert!(o.status.success(), "{}", stderr(&o));
            let mut files = entries(&root.join("out"));
            assert_eq!(files.keys().collect::<Vec<_>>(), SET, "exactly the set, nothing hidden");
            files.remove("summary.json");
            vtu.insert(variant, files);
        }
        assert_ne!(vtu["a"], vtu["b"], "the two loads give different results");
        Reference { vtu }
    }

    /// The variant whose whole set `out` holds, and nothing else; None when
    /// it holds anything else.
    fn whole_set(&self, out: &Path) -> Option<&'static str> {
        self.whole(entries(out))
    }

    /// The variant whose whole set `files` (name → bytes) are.
    fn whole(&self, mut files: BTreeMap<String, Vec<u8>>) -> Option<&'static str> {
        if files.keys().collect::<Vec<_>>() != SET {
            return None;
        }
        let summary: serde_json::Value = serde_json::from_slice(&files.remove("summary.json")?).ok()?;
        let variant = ["a", "b"].into_iter().find(|v| files == self.vtu[v])?;
        (summary["case"] == format!("{variant}/case.toml")).then_some(variant)
    }
}

/// `seam solve --force` killed with SIGKILL at moments spread over its run
/// (most of them in its last quarter, where the results are written), each
/// time replacing the other case's results: after each kill, the next run
/// that writes into `out/` (here one without `--force`, which recovers and
/// then refuses to overwrite) leaves exactly one case's whole set, with
/// nothing hidden; and it says so in one line when it recovered something.
#[test]
fn solve_killed_at_any_moment_leaves_a_whole_set_after_the_next_run() {
    let (tmp, reference) = scene(8);
    let (root, out) = (tmp.path(), tmp.path().join("out"));
    // The time of a whole run (the shortest of three), for the kill moments.
    let mut whole = Duration::MAX;
    for _ in 0..3 {
        let clock = Instant::now();
        let o = start(root, "a", true).wait_with_output().unwrap();
        assert!(o.status.success());
        whole = whole.min(clock.elapsed());
    }
    assert_eq!(reference.whole_set(&out), Some("a"));

    let (mut recovered, mut kills) = (0, 0);
    let mut state = 12_345_u64; // a fixed sequence of moments
    for i in 0..16 {
        let variant = ["b", "a"][i % 2];
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let fraction = (state >> 11) as f64 / (1u64 << 53) as f64;
        let moment = whole.mul_f64(if i % 4 == 0 { fraction } else { 0.75 + 0.3 * fraction });
        let mut child = start(root, variant, true);
        std::thread::sleep(moment);
        let finished = child.try_wait().unwrap().is_some();
        child.kill().unwrap(); // SIGKILL
        child.wait().unwrap();
        kills += usize::from(!finished);
        if finished {
            // The machine got faster than when `whole` was measured (other
            // tests ended): aim the later kills earlier.
            whole = whole.mul_f64(0.8);
        }
        let mut left = entries(&out);
        left.remove(".seam.lock"); // left by a killed run
        let hidden: Vec<String> = left.keys().filter(|n| n.starts_with('.')).cloned().collect();
        let recovers = !hidden.is_empty();
        // Right after the kill: a whole set, or leftovers the next run recovers.
        assert!(recovers || reference.whole(left.clone()).is_some(), "kill {i}: {:?}", left.keys());
        let o = start(root, variant, false).wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert_eq!(o.status.code(), Some(2), "kill {i}: {err}");
        let lines: Vec<&str> = err.lines().collect();
        assert!(lines.last().unwrap().contains("already exists; pass --force"), "kill {i}: {err}");
        match lines.len() {
            1 => assert!(!recovers, "kill {i}: leftovers {hidden:?} but no notice: {err}"),
            2 => {
                assert!(lines[0].starts_with("seam: recovered "), "kill {i}: {err}");
                assert!(recovers, "kill {i}: {hidden:?}");
                recovered += 1;
            }
            _ => panic!("kill {i}: {err}"),
        }
        let variant_left = reference.whole_set(&out);
        assert!(variant_left.is_some(), "kill {i}: not a whole set: {:?}", entries(&out).keys());
        if finished {
            assert_eq!(variant_left, Some(variant), "run {i} finished before its kill");
        }
    }
    eprintln!("{kills} runs killed, {recovered} of them in the write phase (a run takes {whole:?})");
    assert!(kills >= 8, "{kills} of 16 runs killed before they finished");
}

/// Two runs of `seam solve` without `--force` into one empty directory at
/// once: exactly one writes its results, the other one refuses (whether it
/// waited for the first or came after it), and the directory holds the
/// first one's whole set. With `--force`, both succeed one after the other.
#[test]
fn two_runs_into_one_directory_never_both_replace_it_unseen() {
    let (tmp, reference) = scene(6);
    let (root, out) = (tmp.path(), tmp.path().join("out"));
    for round in 0..3 {
        fs::remove_dir_all(&out).unwrap();
        let (a, b) = (start(root, "a", false), start(root, "b", false));
        let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
        let codes = (a.status.code(), b.status.code());
        let winner = match codes {
            (Some(0), Some(2)) => ("a", b),
            (Some(2), Some(0)) => ("b", a),
            _ => panic!("round {round}: exit codes {codes:?}: {} / {}", stderr(&a), stderr(&b)),
        };
        let err = stderr(&winner.1);
        assert!(err.trim_end().lines().last().unwrap().contains("already exists; pass --force"), "{err}");
        assert_eq!(reference.whole_set(&out), Some(winner.0), "round {round}");
    }
    // With --force: one waits if they overlap, and both succeed in turn.
    let (a, b) = (start(root, "a", true), start(root, "b", true));
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    assert!(a.status.success() && b.status.success(), "{} / {}", stderr(&a), stderr(&b));
    assert!(reference.whole_set(&out).is_some());
}

/// A run that finds the output directory locked waits, says so in one line
/// naming the holder, leaves the old results alone meanwhile, and writes
/// once the lock is released. The lock is held here by this test, as
/// another `seam` holds it (`flock` on `out/.seam.lock`).
#[test]
fn a_run_waits_for_the_lock_with_one_line_then_writes() {
    let (tmp, reference) = scene(4);
    let (root, out) = (tmp.path(), tmp.path().join("out"));
    let lock_path = out.join(".seam.lock");
    let lock = fs::File::create(&lock_path).unwrap();
    lock.lock().unwrap();
    fs::write(&lock_path, "4242\n").unwrap();
    let mut child = start(root, "a", true);
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    err.read_line(&mut line).unwrap();
    assert_eq!(
        line.trim_end(),
        format!("seam: waiting for another seam run (pid 4242) writing into {} to finish", "a/../out")
    );
    std::thread::sleep(Duration::from_millis(200));
    assert!(child.try_wait().unwrap().is_none(), "it waits");
    assert_eq!(reference.whole_set(&out), None, "the lock file is there");
    drop(lock); // released, as by a holder that was killed
    let status = child.wait().unwrap();
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut err, &mut rest).unwrap();
    assert!(status.success(), "{rest}");
    assert_eq!(rest, "", "nothing more on stderr");
    assert_eq!(reference.whole_set(&out), Some("a"), "its results, no lock file left");
}
