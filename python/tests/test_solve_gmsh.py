"""A case whose meshes Gmsh makes: two boxes (OpenCASCADE), meshed apart with
unstructured tetrahedra of different sizes (the interface does not match),
physical groups named, written as MSH 4.1 by ``gmsh.write``. Solved by
``seam.solve(...).write(dir)`` and by the `seam solve` binary that `cargo
test` builds (target/debug/seam, or $SEAM_BIN): the files must be the same,
byte for byte (summary.json up to the paths, timings and thread count).
Errors are ``seam.SolveError`` with the CLI's one-line message.

Meshes by gmsh_meshes.py (needs the ``gmsh`` wheel).
"""

import json
import sys
from pathlib import Path

import gmsh
import numpy as np
import pytest

import seam
from gmsh_meshes import EPS, mesh_box

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests" / "python"))
from seam_cli import seam as run_cli  # noqa: E402

# name: (box (x0, y0, z0, dx, dy, dz), mesh size)
BOXES = {
    "lower": ((0.0, 0.0, 0.0, 1.0, 1.0, 0.5), 0.22),
    "upper": ((0.0, 0.0, 0.5, 1.0, 1.0, 0.5), 0.31),
}


def case_text(interface):
    """lower (master) and upper (slave) coupled at lower:top / upper:bottom
    with the `interface` keys; lower clamped at the bottom; upper on rollers
    at x = 0 and y = 0 and loaded on its top."""
    text = "".join(f'[[body]]\nname = "{b}"\nmesh = "{b}.msh"\nyoung = {e}\npoisson = {nu}\n\n'
                   for b, e, nu in (("lower", 1000.0, 0.3), ("upper", 400.0, 0.25)))
    text += f'[[interface]]\nmaster = "lower:top"\nslave = "upper:bottom"\n{interface}\n\n'
    text += '[[dirichlet]]\nboundary = "lower:bottom"\nux = 0.0\nuy = 0.0\nuz = 0.0\n\n'
    text += '[[dirichlet]]\nboundary = "upper:xmin"\nux = 0.0\n\n'
    text += '[[dirichlet]]\nboundary = "upper:ymin"\nuy = 0.0\n\n'
    text += '[[traction]]\nboundary = "upper:top"\nt = [0.0, 0.1, -1.0]\n\n'
    return text


INTERFACES = {
    "glue-standard": 'kind = "glue"\nmultiplier = "standard"',
    "glue-dual": 'kind = "glue"\nmultiplier = "dual"',
    "contact": 'kind = "contact"',
}


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    """lower.msh and upper.msh of each order (in o1/ and o2/), made once by Gmsh."""
    d = tmp_path_factory.mktemp("gmsh")
    for order in (1, 2):
        (d / f"o{order}").mkdir()
        for name, (box, size) in BOXES.items():
            mesh_box(d / f"o{order}" / f"{name}.msh", box, size, order)
    return d


def setup_case(meshes, tmp_path, interface, order=1):
    for name in BOXES:
        (tmp_path / f"{name}.msh").write_bytes((meshes / f"o{order}" / f"{name}.msh").read_bytes())
    (tmp_path / "case.toml").write_text(case_text(INTERFACES[interface]))


def without_paths_times_and_threads(summary):
    s = dict(summary)
    for key in ("seconds", "case", "output_dir", "threads"):
        s.pop(key)
    s["bodies"] = [{k: v for k, v in b.items() if k != "mesh"} for b in s["bodies"]]
    return s


@pytest.mark.parametrize("order, kinds", [(1, ("triangle", "tetra")), (2, ("triangle6", "tetra10"))])
def test_gmsh_writes_msh41_tetrahedra_with_named_groups(meshes, order, kinds):
    import meshio

    sizes = []
    for name in BOXES:
        path = meshes / f"o{order}" / f"{name}.msh"
        text = path.read_text()
        assert text.startswith("$MeshFormat\n4.1 0 8\n"), text[:40]
        m = meshio.read(path)
        assert {c.type for c in m.cells} == set(kinds)
        assert {"bottom", "top", "xmin", "ymin", "body"} <= set(m.field_data)
        sizes.append(sum(len(c.data) for c in m.cells if c.type == kinds[1]))
    assert sizes[0] != sizes[1] and min(sizes) > 20  # unstructured, non-matching


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("interface", sorted(INTERFACES))
def test_python_and_cli_write_the_same_bytes(meshes, tmp_path, monkeypatch, interface, order):
    setup_case(meshes, tmp_path, interface, order)
    monkeypatch.chdir(tmp_path)
    solution = seam.solve("case.toml", threads=1)
    written = solution.write(tmp_path / "py")
    cli = run_cli("solve", "case.toml", cwd=tmp_path)
    assert cli.returncode == 0, cli.stderr
    names = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert names == ["lower.vtu", "summary.json", "upper.vtu", "upper_bottom_interface.vtu"]
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == names
    for name in names:
        a, b = (tmp_path / "out" / name).read_bytes(), (tmp_path / "py" / name).read_bytes()
        if name == "summary.json":
            a, b = json.loads(a), json.loads(b)
            assert b == written
            assert without_paths_times_and_threads(a) == without_paths_times_and_threads(b)
            assert b["interfaces"][0]["kind"] == interface.split("-")[0]
        else:
            assert a == b, name
    if order == 2:  # quadratic tetrahedra went through (VTK type 24, node order converted)
        import meshio

        assert {c.type for c in meshio.read(tmp_path / "out" / "upper.vtu").cells} == {"tetra10"}
    # Something was solved: the upper block moved down under its load.
    assert solution.bodies["upper"].displacement[:, 2].max() < 0.0
    assert len(solution.bodies["lower"].stress) > 20


def test_errors_are_the_cli_one_line_messages(meshes, tmp_path, monkeypatch):
    setup_case(meshes, tmp_path, "glue-dual")
    monkeypatch.chdir(tmp_path)
    text = (tmp_path / "case.toml").read_text()
    for name, bad, part in (
        ("surface.toml", text.replace('"upper:bottom"', '"upper:underside"'), "underside"),
        ("body.toml", text.replace('master = "lower:top"', 'master = "middle:top"'), "middle"),
        ("mesh.toml", text.replace('"lower.msh"', '"nowhere.msh"'), "nowhere.msh"),
    ):
        (tmp_path / name).write_text(bad)
        with pytest.raises(seam.SolveError) as e:
            seam.solve(name)
        message = str(e.value)
        assert part in message and "\n" not in message, message
        cli = run_cli("solve", name, cwd=tmp_path)
        assert cli.returncode == 2
        assert cli.stderr == f"seam: error: {message}\n"
    # The missing surface's message lists the surfaces the mesh has.
    with pytest.raises(seam.SolveError, match="underside.*(bottom|top)"):
        seam.solve("surface.toml")
    assert not (tmp_path / "out").exists()


def test_bodies_from_the_volumes_of_one_file(tmp_path, monkeypatch):
    """One Gmsh file with two physical volumes (two fused boxes, one conforming
    mesh): each body selects one (`volume`), so the other's nodes are in its
    points but not its unknowns; the surface between them, glued, faces out
    of each. A uniaxial patch test, u = (νPx, νPy, −Pz)/E, holds at every
    node of each body; the other volume's nodes get zero."""
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        lower = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
        upper = gmsh.model.occ.addBox(0, 0, 1, 1, 1, 1)
        gmsh.model.occ.fragment([(3, lower)], [(3, upper)])
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(3, [lower], name="lower")
        gmsh.model.addPhysicalGroup(3, [upper], name="upper")
        centres = {s: gmsh.model.occ.getCenterOfMass(2, s) for _, s in gmsh.model.getEntities(2)}
        for name, centre in (("bottom", (0.5, 0.5, 0)), ("xmin", (0, 0.5, 0.5)), ("ymin", (0.5, 0, 0.5)),
                             ("mid", (0.5, 0.5, 1)), ("top", (0.5, 0.5, 2))):
            (surface,) = [s for s, c in centres.items() if np.allclose(c, centre)]
            gmsh.model.addPhysicalGroup(2, [surface], name=name)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.5)
        gmsh.model.mesh.generate(3)
        gmsh.write(str(tmp_path / "two.msh"))
    finally:
        gmsh.finalize()
    e, nu, p = 1000.0, 0.25, 2.0
    body = {"mesh": "two.msh", "young": e, "poisson": nu}
    case = {
        "body": [dict(body, name="lower", volume="lower"), dict(body, name="upper", volume="upper")],
        "interface": [{"master": "lower:mid", "slave": "upper:mid", "kind": "glue"}],
        "dirichlet": [{"boundary": "lower:bottom", "uz": 0.0}, {"boundary": "lower:xmin", "ux": 0.0},
                      {"boundary": "lower:ymin", "uy": 0.0}],
        "traction": [{"boundary": "upper:top", "t": [0.0, 0.0, -p]}],
    }
    monkeypatch.chdir(tmp_path)
    solution = seam.solve(case)
    used = 0
    for name, (z0, z1) in (("lower", (0, 1)), ("upper", (1, 2))):
        x, u = solution.bodies[name].points, solution.bodies[name].displacement
        mine = (x[:, 2] >= z0 - EPS) & (x[:, 2] <= z1 + EPS)
        exact = np.where(mine[:, None], np.c_[nu * p * x[:, 0], nu * p * x[:, 1], -p * x[:, 2]] / e, 0.0)
        np.testing.assert_allclose(u, exact, rtol=0, atol=1e-12 * p / e)
        used += mine.sum()
    assert solution.summary["dofs"] == 3 * used < 6 * len(x)
