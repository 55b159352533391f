"""Second-order (curved) faces through the Python module: Gmsh-written Tri6,
Quad8 and Quad9 interfaces, and (points, faces) tuples of width 6, 8 and 9."""

import numpy as np
import pytest

import seam
from meshes import MSH_DATA


def linear(x):
    return 1.0 + 2.0 * x[:, 0] - 3.0 * x[:, 1] + 0.5 * x[:, 2]


@pytest.mark.parametrize("multiplier", ["standard", "dual"])
@pytest.mark.parametrize(
    "master, slave",
    [
        ("box_hex_o2", "box_tet_o2"),  # Quad9 master, Tri6 slave ([0,1]² of [0,2]×[0,1])
        ("box_hex_o2s", "box_tet_o2"),  # Quad8 master
        ("hybrid_pyramid_o2", "box_hex_o2s"),  # mixed Tri6/Quad9 master, Quad8 slave
        ("box_hex_o2s", "hybrid_pyramid_o2"),  # the reverse
    ],
)
def test_gmsh_second_order_tops_couple_and_reproduce_linear_fields(master, slave, multiplier):
    # Independent Gmsh meshes of box tops at z = 1; flat, so T reproduces
    # linear fields (I4).
    master = seam.read_mesh(MSH_DATA / f"{master}.v41.bin.msh", group="top")
    slave_mesh = seam.read_mesh(MSH_DATA / f"{slave}.v41.ascii.msh", group="top")
    op = seam.assemble(master, slave_mesh, multiplier=multiplier)
    # I1: D·1 = B·1 row by row.
    d1 = np.asarray(op.D.sum(axis=1)).ravel()
    b1 = np.asarray(op.B.sum(axis=1)).ravel()
    np.testing.assert_allclose(d1, b1, rtol=0, atol=1e-13 * abs(d1).max())
    s = op.summary
    assert s["covered_area"] == pytest.approx(s["slave_area"], rel=1e-10)
    used = np.zeros(len(slave_mesh.points), bool)
    for kind in ("triangles", "quads", "tri6", "quad8", "quad9"):
        used[getattr(slave_mesh, kind).ravel()] = True
    ts = op.transfer(linear(master.points))
    np.testing.assert_allclose(ts[used], linear(slave_mesh.points)[used], rtol=0, atol=1e-11)


def quadratic_patch(n, kind, radius):
    """n × n Quad9 or 2n² Tri6 on a cylinder patch, all nodes on the cylinder."""
    m = 2 * n + 1
    u, v = np.meshgrid(np.linspace(0.0, 1.0, m), np.linspace(0.0, 1.0, m))
    theta = 0.3 + u.ravel()
    points = np.column_stack([radius * np.cos(theta), radius * np.sin(theta), v.ravel()])
    idx = np.arange(m * m).reshape(m, m)  # idx[j, i]
    faces = []
    for j in range(0, 2 * n, 2):
        for i in range(0, 2 * n, 2):
            c = [idx[j, i], idx[j, i + 2], idx[j + 2, i + 2], idx[j + 2, i]]
            e = [idx[j, i + 1], idx[j + 1, i + 2], idx[j + 2, i + 1], idx[j + 1, i]]
            centre = idx[j + 1, i + 1]
            if kind == "quad9":
                faces.append(c + e + [centre])
            else:
                faces.append([c[0], c[1], c[2], e[0], e[1], centre])
                faces.append([c[0], c[2], c[3], centre, e[2], e[3]])
    return points, np.array(faces, dtype=np.int64)


@pytest.mark.parametrize("multiplier", ["standard", "dual"])
def test_curved_tuples_of_width_6_and_9_transfer_to_third_order(multiplier):
    # I9 in miniature: Quad9 slave, Tri6 master at radius + h³.
    errors = []
    for n in (3, 6, 12):
        h = 1.0 / n
        slave = quadratic_patch(n, "quad9", 1.5)
        master = quadratic_patch(n + 1, "tri6", 1.5 + h**3)
        op = seam.assemble(master, slave, multiplier=multiplier)
        f = lambda x: np.sin(1.3 * x[:, 0]) + np.cos(0.7 * x[:, 1]) * x[:, 2]
        e = op.transfer(f(master[0])) - f(slave[0])
        mass = seam.assemble(master, slave).D
        errors.append(np.sqrt(e @ (mass @ e)))
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert rates.min() > 2.7, (errors, rates)


def test_lumped_multipliers_are_refused_on_tri6_slaves():
    master = quadratic_patch(3, "quad9", 1.5)
    slave = quadratic_patch(3, "tri6", 1.5)
    with pytest.raises(Exception, match="use dual multipliers"):
        seam.assemble(master, slave, multiplier="lumped")


def test_check_of_second_order_files_is_that_of_the_cli(tmp_path):
    # The Tet10 top (Tri6 faces) under the Hex27 top (Quad9 faces): fully
    # covered, flat, so the invariants hold; the same report as `seam check`.
    import json
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests" / "python"))
    from seam_cli import seam as run_cli

    master, slave = MSH_DATA / "box_hex_o2.v41.bin.msh", MSH_DATA / "box_tet_o2.v22.ascii.msh"
    groups = ("--master-group", "top", "--slave-group", "top")
    r = run_cli("check", master, slave, *groups, "--json", "r.json", "--multiplier", "dual", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    cli_report = json.loads((tmp_path / "r.json").read_text())
    meshes = (seam.read_mesh(master, group="top"), seam.read_mesh(slave, group="top"))
    report = seam.check(*meshes, multiplier="dual", threads=1)
    assert (report["master"], report["slave"]) == ("master", "slave")
    assert report == {**cli_report, "master": "master", "slave": "slave"}
    assert report["ok"] and report["uncovered_slave_nodes"] == 0
    assert all(i["ok"] for i in report["invariants"])
    assert abs(report["covered_fraction"] - 1.0) < 1e-12
