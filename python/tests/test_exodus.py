"""Exodus II files in seam.read_mesh.

The fixtures of crates/seam-io/tests/data/exodus were written by the SEACAS
Exodus library from Gmsh's meshes (crates/seam-io/tests/data/abaqus/*.msh,
the same nodes in the same order).
"""

import numpy as np
import pytest

import seam
from meshes import MSH_DATA

EXODUS = MSH_DATA / "exodus"
ABAQUS = MSH_DATA / "abaqus"


def read_exodus(path, group=None):
    """seam.read_mesh of an Exodus II file."""
    return seam.read_mesh(path, group)


@pytest.mark.parametrize(
    "name", ["box_hex.seacas.e", "box_hex.seacas.exo", "box_hex.seacas.ex2", "box_hex20.seacas.e"]
)
def test_read_mesh_reads_an_exodus_side_set_as_its_msh_twin(name):
    exo = read_exodus(EXODUS / name, "top")
    msh = seam.read_mesh(ABAQUS / (name.split(".")[0] + ".msh"), "top")
    np.testing.assert_array_equal(exo.points, msh.points)
    assert exo.n_faces == msh.n_faces
    master = seam.read_mesh(ABAQUS / "box_hex.msh", "top")
    a = seam.assemble(master, exo, multiplier="dual")
    b = seam.assemble(master, msh, multiplier="dual")
    np.testing.assert_allclose(a.D.toarray(), b.D.toarray(), rtol=0, atol=1e-14)


def test_read_mesh_errors_name_the_exodus_file(tmp_path):
    bad = tmp_path / "bad.exo"
    bad.write_text("not an exodus file\n")
    with pytest.raises(seam.MshError, match=r"bad\.exo: "):
        read_exodus(bad)
