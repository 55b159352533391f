"""Every VTU file the `seam` command line writes, read back by meshio (an
independent reader): field names, shapes and values.

Uses the `seam` binary that `cargo test` builds (target/debug/seam, or $SEAM_BIN).
"""
import json

import meshio
import numpy as np
import pytest

from seam_cli import DATA, seam


def surface_points(mesh):
    used = np.zeros(len(mesh.points), bool)
    for block in mesh.cells:
        used[block.data.ravel()] = True
    return used


def test_transfer_output(tmp_path):
    r = seam("transfer", DATA / "square_tri.v41.ascii.msh", DATA / "square_mixed.v41.bin.msh",
             "-o", "t.vtu", "--expr", "3*x - 2*y + 1", "--name", "u", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    m = meshio.read(tmp_path / "t.vtu")
    assert {c.type for c in m.cells} == {"triangle", "quad"}
    n = len(m.points)
    for name in ("u", "coverage", "normal_gap"):
        assert m.point_data[name].shape in ((n,), (n, 1)), name
    used = surface_points(m)
    u = m.point_data["u"].reshape(n)
    exact = 3 * m.points[:, 0] - 2 * m.points[:, 1] + 1
    assert np.abs(u[used] - exact[used]).max() < 1e-12  # linear fields are exact (I4)
    assert np.allclose(m.point_data["coverage"].reshape(n)[used], 1.0)
    summary = json.loads((tmp_path / "t.json").read_text())
    assert summary["l2_error"] < 1e-13


def test_check_and_segments_outputs(tmp_path):
    master, slave = DATA / "square_tri.v41.ascii.msh", DATA / "square_mixed.v41.ascii.msh"
    r = seam("check", master, slave, "--vtu", "c.vtu", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    c = meshio.read(tmp_path / "c.vtu")
    assert set(c.point_data) >= {"coverage", "normal_gap"}
    r = seam("assemble", master, slave, "-o", "out", "--segments", "seg.vtu", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    s = meshio.read(tmp_path / "seg.vtu")
    (block,) = s.cells
    assert block.type == "triangle"
    summary = json.loads((tmp_path / "out/summary.json").read_text())
    assert len(block.data) == summary["segments"]
    slave_ids = s.cell_data["slave_face"][0].reshape(-1)
    assert slave_ids.min() >= 0 and slave_ids.max() < summary["slave_faces"]
    # The segments tile the unit square: their areas add up to 1.
    p = s.points[block.data]
    area = 0.5 * np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])[:, 2]).sum()
    assert abs(area - 1.0) < 1e-12


@pytest.mark.parametrize("binary", [False, True])
def test_meshio_written_source_field(tmp_path, binary):
    """A field in a VTU written by meshio is transferred like an expression."""
    src = meshio.read(DATA / "square_tri.v41.ascii.msh")
    pts = src.points
    tri = [c for c in src.cells if c.type == "triangle"]
    field = np.sin(pts[:, 0]) + pts[:, 1]
    meshio.write(tmp_path / "src.vtu", meshio.Mesh(pts, tri, point_data={"T": field}), binary=binary)
    r = seam("transfer", "src.vtu", DATA / "square_mixed.v22.ascii.msh", "-o", "a.vtu", "--field", "T", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    r = seam("transfer", DATA / "square_tri.v41.ascii.msh", DATA / "square_mixed.v22.ascii.msh",
             "-o", "b.vtu", "--expr", "sin(x) + y", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    a = meshio.read(tmp_path / "a.vtu").point_data["T"].reshape(-1)
    b = meshio.read(tmp_path / "b.vtu").point_data["f"].reshape(-1)
    # meshio's ASCII writer keeps 12 significant digits of the source field and
    # points; its binary writer keeps every bit.
    assert np.abs(a - b).max() < (1e-13 if binary else 1e-10)
