"""The examples of python/examples run as python/README.md and docs/examples.md show them, and their
answers are the exact ones."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("gmsh")

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_glue_and_contact_carries_the_uniaxial_stress(tmp_path, capsys):
    example = load("glue_and_contact")
    solution = example.main(tmp_path)
    p = example.P
    contact, glue = solution.interfaces
    assert (contact.kind, glue.kind) == ("contact", "glue")
    assert contact.active.min() == 1, "every contact point is active"
    assert np.abs(contact.contact_pressure - p).max() <= 1e-9 * p
    covered = glue.constrained == 1
    assert covered.any()
    assert np.abs(glue.normal_traction[covered] + p).max() <= 1e-9 * p
    for body in solution.bodies.values():
        exact = np.array([0.0, 0.0, -p, 0.0, 0.0, 0.0])
        assert np.abs(body.stress - exact).max() <= 1e-9 * p
    assert solution.summary["contact"]["kkt"]["max"] <= 1e-10
    for name in ("base.vtu", "block.vtu", "cap.vtu", "summary.json"):
        assert (tmp_path / "out" / name).is_file()
    assert "pressure" in capsys.readouterr().out
