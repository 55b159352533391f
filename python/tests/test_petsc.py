"""seam.solve(case, solver="petsc"): a PETSc KSP (CG + GAMG by default) gives
the direct solver's answer to the solver tolerance, its report is in the
summary, PETSc's options pass through, and PETSc's errors are SolveErrors.

Needs the module built with the cargo feature `petsc` (scripts/test does so
when PETSc is installed and sets SEAM_TEST_PETSC=1, in which case these tests
must run; otherwise they are skipped when the module has no PETSc).
"""

import os
import sys
from pathlib import Path

import numpy as np
import pytest

import seam

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests" / "python"))
from seam_cli import seam as run_cli  # noqa: E402


@pytest.fixture
def case(tmp_path):
    """The warped-glue example, small, with dual multipliers."""
    done = run_cli("example", "warped-glue", "-o", "ex", "--slave-cells", "4", "--ratio", "2", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    path = tmp_path / "ex" / "case.toml"
    path.write_text(path.read_text().replace('multiplier = "standard"', 'multiplier = "dual"'))
    try:
        seam.solve(path, solver="petsc")
    except seam.SolveError as e:
        if "built without PETSc" in str(e) and os.environ.get("SEAM_TEST_PETSC") != "1":
            pytest.skip("the seam module was built without the petsc feature")
        raise
    return path


def test_petsc_gives_the_direct_answer(case):
    direct = seam.solve(case)
    iterative = seam.solve(case, solver="petsc", rtol=1e-12)
    for name in ("lower", "upper"):
        u, v = direct.bodies[name].displacement, iterative.bodies[name].displacement
        assert np.abs(u - v).max() <= 1e-9 * np.abs(u).max(), name
    s = iterative.summary
    assert s["solver"] == "petsc" and "petsc" not in direct.summary
    p = s["petsc"]
    assert (p["ksp_type"], p["pc_type"]) == ("cg", "gamg")
    assert len(p["iterations"]) == 1 and p["iterations"][0] > 0
    assert p["reasons"] == ["CONVERGED_RTOL"] and p["residual"] < 1e-9
    assert set(p["seconds"]) == {"assembly", "setup", "solve"}


def test_petsc_options_and_errors(case):
    s = seam.solve(case, solver="petsc", petsc_options="-pc_type jacobi").summary
    assert s["petsc"]["pc_type"] == "jacobi"
    # Options stay in PETSc's database for the process: set the default back.
    s = seam.solve(case, solver="petsc", petsc_options="-pc_type gamg").summary
    assert s["petsc"]["pc_type"] == "gamg"
    with pytest.raises(seam.ConvergenceError, match="DIVERGED_ITS after 1 iterations"):
        seam.solve(case, solver="petsc", petsc_options="-ksp_max_it 1")
    seam.solve(case, solver="petsc", petsc_options="-ksp_max_it 10000")
    with pytest.raises(ValueError, match='petsc_options needs solver="petsc"'):
        seam.solve(case, petsc_options="-ksp_monitor")
