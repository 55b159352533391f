"""The files of `seam solve` and `seam example warped-glue`, read back by meshio
(an independent reader): the meshes the example writes, the body and interface
VTU files with their fields, and their agreement with summary.json.

Uses the `seam` binary that `cargo test` builds (target/debug/seam, or $SEAM_BIN).
"""
import json

import meshio
import numpy as np
import pytest

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


def write_block_msh(path, n, lo, hi, sides):
    """A structured n[0] × n[1] × n[2] hexahedral block over the box [lo, hi] as
    a Gmsh MSH 2.2 ASCII file, written here (not by seam), with the physical
    surfaces `sides` ({name: (axis, 0 for the low end or 1 for the high end)})
    and the physical volume "body"."""
    nx, ny, nz = n
    grid = [np.linspace(lo[a], hi[a], n[a] + 1) for a in range(3)]

    def node(i, j, k):
        return 1 + i + (nx + 1) * (j + (ny + 1) * k)

    nodes = [(node(i, j, k), grid[0][i], grid[1][j], grid[2][k])
             for k in range(nz + 1) for j in range(ny + 1) for i in range(nx + 1)]
    elements = []  # (gmsh type, physical tag, nodes)
    for tag, (name, (axis, end)) in enumerate(sides.items(), start=1):
        a, b = [c for c in range(3) if c != axis]
        for s in range(n[a]):
            for t in range(n[b]):
                corners = []
                for ds, dt in ((0, 0), (1, 0), (1, 1), (0, 1)):
                    ijk = [0, 0, 0]
                    ijk[axis], ijk[a], ijk[b] = end * n[axis], s + ds, t + dt
                    corners.append(node(*ijk))
                elements.append((3, tag, corners))
    volume = len(sides) + 1
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                bottom = [node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k)]
                elements.append((5, volume, bottom + [p + (nx + 1) * (ny + 1) for p in bottom]))
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(sides) + 1)]
    lines += [f'2 {tag} "{name}"' for tag, name in enumerate(sides, start=1)]
    lines += [f'3 {volume} "body"', "$EndPhysicalNames", "$Nodes", str(len(nodes))]
    lines += [f"{p} {float(x)!r} {float(y)!r} {float(z)!r}" for p, x, y, z in nodes]
    lines += ["$EndNodes", "$Elements", str(len(elements))]
    lines += [f"{e} {kind} 2 {tag} {tag} " + " ".join(map(str, corners))
              for e, (kind, tag, corners) in enumerate(elements, start=1)]
    lines += ["$EndElements"]
    path.write_text("\n".join(lines) + "\n")


def contact_case(top):
    """Two blocks, lower.msh (E = 1000, ν = 0.25) and upper.msh (E = 500,
    ν = 0.3), in contact at lower:top (master) and upper:bottom (slave), each
    on rollers at xmin (ux) and ymin (uy), the lower one at bottom (uz), with
    `top` appended."""
    bodies = [("lower", 1000.0, 0.25), ("upper", 500.0, 0.3)]
    text = "".join(f'[[body]]\nname = "{b}"\nmesh = "{b}.msh"\nyoung = {e}\npoisson = {nu}\n\n'
                   for b, e, nu in bodies)
    text += '[[interface]]\nmaster = "lower:top"\nslave = "upper:bottom"\nkind = "contact"\n\n'
    rollers = [("lower:bottom", "uz"), ("lower:xmin", "ux"), ("lower:ymin", "uy"),
               ("upper:xmin", "ux"), ("upper:ymin", "uy")]
    text += "".join(f'[[dirichlet]]\nboundary = "{b}"\n{c} = 0.0\n\n' for b, c in rollers)
    return text + top


@pytest.mark.parametrize("loading", ["pressed", "lifted"])
def test_contact_outputs(tmp_path, loading):
    """Two stacked blocks meshed 4×4×2 (lower, master) and 3×3×2 (upper, slave),
    in frictionless contact. Pressed by P on top, the upper block presses on
    the lower one with the uniform pressure P (uniaxial stress, exact for these
    elements); started 0.01 above and moved down by 0.005, it never touches."""
    p, gap = 2.0, (0.0 if loading == "pressed" else 0.01)
    sides = {"bottom": (2, 0), "top": (2, 1), "xmin": (0, 0), "ymin": (1, 0)}
    write_block_msh(tmp_path / "lower.msh", (4, 4, 2), (0, 0, 0), (1, 1, 0.5), sides)
    write_block_msh(tmp_path / "upper.msh", (3, 3, 2), (0, 0, 0.5 + gap), (1, 1, 1 + gap), sides)
    top = (f'[[traction]]\nboundary = "upper:top"\nt = [0.0, 0.0, {-p}]\n' if loading == "pressed"
           else '[[dirichlet]]\nboundary = "upper:top"\nuz = -0.005\n')
    (tmp_path / "case.toml").write_text(contact_case(top))
    r = seam("solve", "case.toml", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "contact " in r.stdout and "KKT max" in r.stdout, r.stdout
    summary = json.loads((tmp_path / "out/summary.json").read_text())

    f = meshio.read(tmp_path / "out/upper_bottom_interface.vtu")
    n = len(f.points)
    assert n == 16  # the slave surface's own points
    ((block,),) = [f.cells]
    assert block.type == "quad" and len(block.data) == 9
    pressure = f.point_data["contact_pressure"].reshape(-1)
    active = f.point_data["active"].reshape(-1)
    gap_after = f.point_data["gap"].reshape(-1)
    initial = f.point_data["initial_gap"].reshape(-1)
    for values in (pressure, active, gap_after, initial):
        assert values.shape == (n,)
    for name in ("normal", "traction", "displacement"):
        assert f.point_data[name].shape == (n, 3), name
    normal, traction = f.point_data["normal"], f.point_data["traction"]
    assert np.allclose(normal, [0.0, 0.0, -1.0], rtol=0, atol=1e-15)
    assert np.allclose(traction, -pressure[:, None] * normal, rtol=0, atol=1e-14)
    assert set(np.unique(active)) <= {0.0, 1.0}
    assert np.allclose(initial, gap, rtol=0, atol=1e-14)

    c = summary["contact"]
    assert c["contact_points"] == n
    assert c["active_points"] == int(active.sum())
    assert c["iterations"] == len(c["steps"]) >= 1
    assert c["kkt"]["max"] <= 1e-8
    force = np.array(c["interfaces"][0]["force"])
    if loading == "pressed":
        assert np.all(active == 1)
        assert np.abs(pressure - p).max() <= 1e-8 * p  # P where active
        assert np.abs(gap_after).max() <= 1e-12
        assert np.abs(force - [0.0, 0.0, p]).max() <= 1e-8 * p  # P over the unit square
    else:
        assert np.all(active == 0) and np.all(pressure == 0.0)
        assert np.abs(gap_after - 0.005).max() <= 1e-12
        assert np.all(force == 0.0)
    assert abs(c["interfaces"][0]["force_magnitude"] - np.linalg.norm(force)) <= 1e-14
    assert summary["interfaces"][0]["multiplier"] == "lumped"  # the default for contact
