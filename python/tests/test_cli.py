"""The wheel's ``seam`` command (``[project.scripts]`` in pyproject.toml) is the
command-line tool: the same version, the same files byte for byte as the Rust
binary (``target/debug/seam`` or $SEAM_BIN), the same exit codes and one-line
errors; ``python -m seam`` too."""

import subprocess
import sys
from pathlib import Path

import pytest

import seam

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests/python"))
from seam_cli import DATA  # noqa: E402
from seam_cli import seam as run_binary  # noqa: E402

# The console script pip installed beside this interpreter.
SCRIPT = Path(sys.executable).parent / "seam"


def run_script(*args, cwd):
    if not SCRIPT.exists():
        pytest.fail(f"{SCRIPT} is missing: the wheel installs a `seam` command")
    return subprocess.run([str(SCRIPT), *map(str, args)], cwd=cwd, capture_output=True, text=True)


def test_the_command_has_the_module_version(tmp_path):
    r = run_script("--version", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == f"seam {seam.__version__}"
    m = subprocess.run([sys.executable, "-m", "seam", "--help"], cwd=tmp_path, capture_output=True, text=True)
    assert m.returncode == 0, m.stderr
    assert "Usage: seam <COMMAND>" in m.stdout


def test_assemble_writes_the_binary_s_bytes(tmp_path):
    master, slave = DATA / "square_tri.v41.ascii.msh", DATA / "square_mixed.v41.bin.msh"
    for name, run in (("script", run_script), ("binary", run_binary)):
        r = run("assemble", master, slave, "-o", name, "--multiplier", "dual", cwd=tmp_path)
        assert r.returncode == 0, f"{name}: {r.stderr}"
    for matrix in ("B.mtx", "D.mtx", "T.mtx"):
        assert (tmp_path / "script" / matrix).read_bytes() == (tmp_path / "binary" / matrix).read_bytes(), matrix


def test_errors_are_one_line_with_the_binary_s_exit_codes(tmp_path):
    cases = [
        (("solve", "missing.toml"), 2),  # a file that does not exist
        (("assemble", "--no-such-flag"), 2),  # a usage error
    ]
    for args, code in cases:
        r = run_script(*args, cwd=tmp_path)
        b = run_binary(*args, cwd=tmp_path)
        assert r.returncode == b.returncode == code, (args, r.stderr, b.stderr)
        assert r.stderr == b.stderr, args
        assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    # A written output is not overwritten without --force, by either.
    master, slave = DATA / "square_tri.v41.ascii.msh", DATA / "square_mixed.v41.bin.msh"
    assert run_script("assemble", master, slave, "-o", "out", cwd=tmp_path).returncode == 0
    again = run_script("assemble", master, slave, "-o", "out", cwd=tmp_path)
    assert again.returncode == 2 and "--force" in again.stderr, again.stderr
