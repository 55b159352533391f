"""The files of `seam solve` and `seam example warped-glue`, read back by meshio
(an independent reader): the meshes the example writes, the body and interface
VTU files with their fields, and their agreement with summary.json.

Uses the `seam` binary that `cargo test` builds (target/debug/seam, or $SEAM_BIN).
"""
import json

import meshio
import numpy as np

from seam_cli import seam


def test_warped_glue_outputs(tmp_path):
    r = seam("example", "warped-glue", "-o", "ex", "--ratio", "2", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    ex = tmp_path / "ex"
    summary = json.loads((ex / "out/summary.json").read_text())

    # The meshes: hexahedra and the named boundaries, as Gmsh would give them.
    for name, cells in (("lower", 16 * 16 * 8), ("upper", 8 * 8 * 8)):
        m = meshio.read(ex / f"{name}.msh")
        hexes = sum(len(c.data) for c in m.cells if c.type == "hexahedron")
        quads = sum(len(c.data) for c in m.cells if c.type == "quad")
        assert hexes == cells
        assert quads == 2 * (16 if name == "lower" else 8) ** 2  # bottom and top
        assert {"bottom", "top", name} <= set(m.field_data)

    # The bodies: displacement per point, stress and von Mises per cell and per point.
    total_dofs = 0
    for body in summary["bodies"]:
        m = meshio.read(ex / "out" / body["file"])
        n = len(m.points)
        total_dofs += 3 * n
        ((block,),) = [m.cells]
        assert block.type == "hexahedron" and len(block.data) == body["cells"]
        u = m.point_data["displacement"]
        assert u.shape == (n, 3)
        assert abs(np.linalg.norm(u, axis=1).max() - body["max_displacement"]) < 1e-12
        assert m.point_data["stress"].shape == (n, 6)
        s = m.cell_data["stress"][0]
        assert s.shape == (len(block.data), 6)
        vm = m.cell_data["von_mises"][0].reshape(-1)
        # von Mises from the Voigt components (xx yy zz yz xz xy).
        expected = np.sqrt(0.5 * ((s[:, 0] - s[:, 1]) ** 2 + (s[:, 1] - s[:, 2]) ** 2 + (s[:, 2] - s[:, 0]) ** 2)
                           + 3 * (s[:, 3] ** 2 + s[:, 4] ** 2 + s[:, 5] ** 2))
        assert np.allclose(vm, expected, rtol=1e-12, atol=1e-14)
    assert total_dofs == summary["dofs"]
    lower = meshio.read(ex / "out/lower.vtu")
    bottom = np.abs(lower.points[:, 2]) < 1e-12
    assert np.abs(lower.point_data["displacement"][bottom]).max() == 0.0  # clamped

    # The interface: the slave surface's 81 points, tractions split into normal
    # and tangential parts, and their resultant equal to the load on the slave body.
    f = meshio.read(ex / "out/upper_bottom_interface.vtu")
    assert len(f.points) == 81
    ((block,),) = [f.cells]
    assert block.type == "quad" and len(block.data) == 64
    t = f.point_data["traction"]
    n = f.point_data["normal"]
    tn = f.point_data["normal_traction"].reshape(-1)
    tt = f.point_data["tangential_traction"]
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0)
    assert np.allclose(tn, (t * n).sum(axis=1), atol=1e-14)
    assert np.allclose(tt, t - tn[:, None] * n, atol=1e-14)
    assert tn.mean() < 0  # the upper block presses on the lower one: compression
    assert np.all(f.point_data["constrained"] == 1)
    load = np.array(summary["bodies"][1]["applied_load"])
    force = np.array(summary["interfaces"][0]["force"])
    assert np.abs(force + load).max() <= 1e-10 * np.abs(load).max()
