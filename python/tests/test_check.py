"""seam.check returns what `seam check --json` writes, for files and for meshes.

Compares with the `seam` binary that `cargo test` builds (target/debug/seam, or
$SEAM_BIN), run on the same meshes written as MSH files.
"""

import json
import math
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest

import seam
from meshes import as_input, grid

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests" / "python"))
from seam_cli import seam as run_cli  # noqa: E402

# The slave reaches past the master (x up to 1.25: five uncovered points) and
# lies just above it; the master is a warped saddle, so the gaps vary.
MASTER = grid(5, 3, "triangles", jitter=0.1)
MASTER[0][:, 2] = 0.02 * MASTER[0][:, 0] * MASTER[0][:, 1]
SLAVE = grid(5, 4, "mixed", box=(0.0, 1.25, 0.0, 1.0), z=0.01)


def write_msh(path, points, triangles, quads):
    cells = [(kind, c) for kind, c in (("triangle", triangles), ("quad", quads)) if len(c)]
    meshio.write(path, meshio.Mesh(points, cells), file_format="gmsh22", binary=True)
    return path


def assert_same(a, b, where="report"):
    """Equal structure, equal ints, strings and bools, floats to 1e-12 relative."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and list(a) == list(b), where
        for k in a:
            assert_same(a[k], b[k], f"{where}[{k!r}]")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{where}[{i}]")
    elif isinstance(a, float):
        assert isinstance(b, float) and math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-15), f"{where}: {a} != {b}"
    else:
        assert type(a) is type(b) and a == b, f"{where}: {a!r} != {b!r}"


@pytest.fixture
def files(tmp_path):
    return write_msh(tmp_path / "master.msh", *MASTER), write_msh(tmp_path / "slave.msh", *SLAVE)


@pytest.fixture
def cli_report(tmp_path, files):
    master, slave = files
    r = run_cli("check", master, slave, "--json", "r.json", "--multiplier", "dual", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    return json.loads((tmp_path / "r.json").read_text())


def test_the_report_of_files_is_that_of_the_cli(files, cli_report):
    master, slave = files
    report = seam.check(str(master), slave, multiplier="dual", threads=1)  # str and PathLike
    assert report == cli_report  # the same reader and the same computation: the same bits
    assert list(report) == list(cli_report)
    assert report["master"] == str(master) and report["slave"] == str(slave)
    assert report["uncovered_slave_nodes"] == 5 and not report["ok"]
    assert report["uncovered_examples"][0] == [6, [1.25, 0.0, 0.01]]
    assert abs(report["covered_fraction"] - 0.8) < 1e-12
    assert all(i["ok"] for i in report["invariants"])


def test_the_report_of_meshes_is_that_of_the_cli(cli_report):
    for master, slave in [
        (as_input(*MASTER), as_input(*SLAVE)),
        (seam.Mesh(*as_input(*MASTER)), seam.Mesh(*as_input(*SLAVE))),
    ]:
        report = seam.check(master, slave, multiplier="dual")
        assert (report["master"], report["slave"]) == ("master", "slave")
        assert report["face_ids"] == "1-based face indices" and cli_report["face_ids"] == "gmsh element tags"
        assert_same(report, {**cli_report, "master": "master", "slave": "slave", "face_ids": "1-based face indices"})


def test_matching_meshes_are_ok():
    points, tris, _ = grid(2, 2, "triangles")
    report = seam.check((points, tris), seam.Mesh(points, tris))
    assert report["ok"] and report["uncovered_examples"] == []
    assert abs(report["covered_fraction"] - 1.0) < 1e-14
    assert abs(report["min_normal_gap"]) < 1e-14 and abs(report["max_normal_gap"]) < 1e-14
    assert len(report["gap_histogram"]) == 10 and sum(b["nodes"] for b in report["gap_histogram"]) == 9


def test_errors_are_those_of_assemble(tmp_path):
    points, tris, _ = grid(2, 2, "triangles")
    far = points + [10.0, 0.0, 0.0]
    with pytest.raises(seam.NoOverlapError, match="the meshes do not overlap"):
        seam.check((points, tris), (far, tris))
    with pytest.raises(seam.InvalidOptionError, match="the max gap must be"):
        seam.check((points, tris), (points, tris), max_gap=-1.0)
    with pytest.raises(ValueError, match='unknown multiplier "mortar"'):
        seam.check((points, tris), (points, tris), multiplier="mortar")
    with pytest.raises(ValueError, match="threads must be at least 1, got 0"):
        seam.check((points, tris), (points, tris), threads=0)
    with pytest.raises(FileNotFoundError):
        seam.check(tmp_path / "missing.msh", (points, tris))
    with pytest.raises(TypeError, match=r"slave must be a seam.Mesh, a \(points, faces\) tuple or the path"):
        seam.check((points, tris), 3)
    with pytest.raises(TypeError, match="positional"):
        seam.check((points, tris), (points, tris), "dual")  # options are keyword-only


def write_quads_msh(path, points, quads, tags, groups):
    """MSH 2.2 ASCII: quad i tagged tags[i] in physical surface groups[i]."""
    nodes = "".join(f"{i + 1} {x} {y} {z}\n" for i, (x, y, z) in enumerate(points))
    elements = "".join(
        f"{t} 3 2 {g} {g} " + " ".join(str(n + 1) for n in q) + "\n" for t, g, q in zip(tags, groups, quads)
    )
    path.write_text(
        f"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{len(points)}\n{nodes}$EndNodes\n"
        f"$Elements\n{len(quads)}\n{elements}$EndElements\n"
    )
    return path


def test_a_doubly_covered_slave_is_not_ok_and_its_faces_are_named(tmp_path):
    # The master's top right quad is repeated (as by two overlapping physical
    # surfaces): the four slave quads behind it, 0-based 10, 11, 14, 15, are
    # covered twice. D·1 = B·1 still holds; the bounds on the covered area and
    # on D's row sums do not.
    master_points, _, master_quads = grid(2, 2)
    master_quads = np.vstack([master_quads, master_quads[3:4]])
    slave_points, _, slave_quads = grid(4, 4)
    report = seam.check((master_points, master_quads), (slave_points, slave_quads))
    assert not report["ok"] and report["uncovered_slave_nodes"] == 0
    assert abs(report["covered_fraction"] - 1.25) < 1e-14
    assert report["face_ids"] == "1-based face indices"
    by_name = {i["name"].split(":")[0]: i for i in report["invariants"]}
    assert all(i["ok"] for i in report["invariants"][:3])
    covered, row_sums = by_name["covered area ≤ slave area"], by_name["D·1 ≤ nodal area"]
    assert not covered["ok"] and abs(covered["value"] - 0.25) < 1e-14
    assert covered["offending_faces"] == [11, 12, 15, 16] and covered["offending_nodes"] == []
    assert not row_sums["ok"] and sorted(row_sums["offending_faces"]) == [11, 12, 15, 16]
    assert sorted(row_sums["offending_nodes"][:4]) == [19, 20, 24, 25]  # 1-based rows, grid points (3..4, 3..4)
    assert [i["offending_faces"] for i in report["invariants"] if i["ok"]] == [[]] * 4

    # From MSH files: the slave's faces by their Gmsh element tags, as `seam check` names them.
    master = write_quads_msh(tmp_path / "master.msh", master_points, master_quads, range(1, 6), [1, 1, 1, 1, 2])
    slave = write_quads_msh(tmp_path / "slave.msh", slave_points, slave_quads, range(101, 117), [1] * 16)
    from_files = seam.check(master, slave)
    read = seam.check(seam.read_mesh(master), seam.read_mesh(slave))
    assert read == {**from_files, "master": "master", "slave": "slave"}
    assert from_files["face_ids"] == "gmsh element tags"
    assert from_files["invariants"][3]["offending_faces"] == [111, 112, 115, 116]
    r = run_cli("check", master, slave, "--json", "r.json", "--strict", cwd=tmp_path)
    assert r.returncode == 3 and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert "111, 112, 115, 116" in r.stderr and "111, 112, 115, 116" in r.stdout
    assert from_files == json.loads((tmp_path / "r.json").read_text())
