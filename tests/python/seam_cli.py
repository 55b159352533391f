"""Runs the `seam` binary that `cargo test` builds (target/debug/seam, or $SEAM_BIN)
for the tests of its output files."""
import os
import pathlib
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "crates/seam-io/tests/data"
SEAM = pathlib.Path(os.environ.get("SEAM_BIN", ROOT / "target/debug/seam"))


def seam(*args, cwd):
    """`seam ARGS` in `cwd`, with its output captured."""
    if not SEAM.exists():
        raise AssertionError(f"{SEAM} is missing: run `cargo build -p seam-cli` (scripts/test does)")
    return subprocess.run([str(SEAM), *map(str, args)], cwd=cwd, capture_output=True, text=True)
