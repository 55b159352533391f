"""Abaqus / CalculiX input files (.inp) in seam.read_mesh and seam.solve.

The .inp fixtures of crates/seam-io/tests/data/abaqus were written by Gmsh
with their .msh twins (same nodes in the same order); the blocks solved here
are written as .inp text by the test itself, with sparse ids.
"""

import numpy as np
import pytest

import seam
from meshes import MSH_DATA

ABAQUS = MSH_DATA / "abaqus"


@pytest.mark.parametrize("name", ["box_hex", "box_hex20", "box_tet"])
def test_read_mesh_reads_an_inp_surface_as_its_msh_twin(name):
    inp = seam.read_mesh(ABAQUS / f"{name}.inp", "TOP")  # *SURFACE names in any case
    msh = seam.read_mesh(ABAQUS / f"{name}.msh", "top")
    # Gmsh's .inp gives coordinates to 16 digits, its .msh to 17.
    np.testing.assert_allclose(inp.points, msh.points, rtol=0, atol=1e-15)
    assert inp.n_faces == msh.n_faces
    # The same operator from a master on the same plane, node by node.
    master = seam.read_mesh(ABAQUS / "box_hex.msh", "top")
    a = seam.assemble(master, inp, multiplier="dual")
    b = seam.assemble(master, msh, multiplier="dual")
    np.testing.assert_allclose(a.D.toarray(), b.D.toarray(), rtol=0, atol=1e-14)
    np.testing.assert_allclose(a.T.toarray(), b.T.toarray(), rtol=0, atol=1e-12)


def test_read_mesh_errors_name_the_inp_file_and_line(tmp_path):
    bad = tmp_path / "bad.inp"
    bad.write_text("*NODE\n1, 0, 0, 0\n2, 1, zero, 0\n")
    with pytest.raises(seam.MshError, match=r"bad\.inp:3: .*node 2"):
        seam.read_mesh(bad)
    with pytest.raises(seam.MshError, match=r"no physical group \"lid\""):
        seam.read_mesh(ABAQUS / "box_hex.inp", "lid")
    with pytest.raises(FileNotFoundError):
        seam.read_mesh(tmp_path / "none.inp")


def block_inp(n, z0, node_base, element_base):
    """An n×n×1 block of C3D8 over [0,1]² × [z0, z0 + 0.5] as .inp text, node
    ids node_base + 2·k, element ids element_base + 3·k (k from 0), the
    element set BLOCK and the surfaces bottom (S1), top (S2), xmin (S6) and
    ymin (S3). Returns the text, the node ids and the element ids."""
    nid = lambda i, j, k: node_base + 2 * (k * (n + 1) ** 2 + j * (n + 1) + i)  # noqa: E731
    lines = ["*NODE"]
    nodes = []
    for k in range(2):
        for j in range(n + 1):
            for i in range(n + 1):
                nodes.append(nid(i, j, k))
                lines.append(f"{nid(i, j, k)}, {i / n}, {j / n}, {z0 + 0.5 * k}")
    lines.append("*ELEMENT, TYPE=C3D8R, ELSET=BLOCK")
    elements, faces = [], {"bottom": [], "top": [], "xmin": [], "ymin": []}
    for j in range(n):
        for i in range(n):
            e = element_base + 3 * len(elements)
            elements.append(e)
            corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
            ids = [nid(a, b, 0) for a, b in corners] + [nid(a, b, 1) for a, b in corners]
            lines.append(f"{e}, " + ", ".join(map(str, ids)))
            faces["bottom"].append(f"{e}, S1")
            faces["top"].append(f"{e}, S2")
            if i == 0:
                faces["xmin"].append(f"{e}, S6")
            if j == 0:
                faces["ymin"].append(f"{e}, S3")
    for name, listed in faces.items():
        lines += [f"*SURFACE, NAME={name}, TYPE=ELEMENT", *listed]
    return "\n".join(lines) + "\n", nodes, elements


def test_solve_a_dict_with_inp_bodies_keeps_their_ids(tmp_path, monkeypatch):
    lower, lower_nodes, lower_elements = block_inp(3, 0.0, 100, 7)
    upper, upper_nodes, upper_elements = block_inp(2, 0.5, 5000, 40)
    (tmp_path / "lower.inp").write_text(lower)
    (tmp_path / "upper.dat").write_text(upper)
    monkeypatch.chdir(tmp_path)
    rollers = [
        {"boundary": "lower:bottom", "uz": 0.0},
        {"boundary": "lower:xmin", "ux": 0.0},
        {"boundary": "lower:ymin", "uy": 0.0},
    ]
    case = {
        "body": [
            {"name": "lower", "mesh": "lower.inp", "volume": "block", "young": 1000.0, "poisson": 0.25},
            {"name": "upper", "mesh": "upper.dat", "format": "abaqus", "young": 1000.0, "poisson": 0.25},
        ],
        "interface": [{"master": "lower:top", "slave": "upper:bottom", "kind": "glue"}],
        "dirichlet": rollers,
        "traction": [{"boundary": "upper:top", "t": [0.0, 0.0, -1.0]}],
    }
    solution = seam.solve(case, threads=1)
    for name, nodes, elements in [
        ("lower", lower_nodes, lower_elements),
        ("upper", upper_nodes, upper_elements),
    ]:
        body = solution.bodies[name]
        assert body.node_id.dtype == np.int64 and body.element_id.dtype == np.int64
        np.testing.assert_array_equal(body.node_id, nodes)
        np.testing.assert_array_equal(body.element_id, elements)
        # Uniaxial stress -1 along z through both blocks of one material.
        np.testing.assert_allclose(body.stress[:, 2], -1.0, rtol=1e-8)
    interface = solution.interfaces[0]
    np.testing.assert_array_equal(interface.node_id, np.array(upper_nodes)[interface.body_point])
    assert interface.node_id.dtype == np.int64
    # An unknown format is one line, a CaseError.
    case["body"][1]["format"] = "nastran"
    with pytest.raises(seam.CaseError, match=r'body "upper": unknown format "nastran"'):
        seam.solve(case)
