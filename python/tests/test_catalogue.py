"""seam's element catalogue against the reference elements Gmsh and VTK report.

For every kind: node count, corners, order, reference nodes in Gmsh's order
(``gmsh.model.mesh.getElementProperties``), the edges with their mid-edge nodes
and the local faces of cells (``getElementEdgeNodes``, ``getElementFaceNodes``
on a one-element model), and the VTK node order against VTK's parametric
coordinates of its cell type.
"""

import numpy as np
import pytest

import seam

gmsh = pytest.importorskip("gmsh")

# Gmsh's names of the reference shapes, by seam's.
SHAPES = {
    "triangle": "Triangle",
    "quadrangle": "Quadrilateral",
    "tetrahedron": "Tetrahedron",
    "hexahedron": "Hexahedron",
    "prism": "Prism",
    "pyramid": "Pyramid",
}

CATALOGUE = seam.catalogue()
FACES = CATALOGUE["faces"]
CELLS = CATALOGUE["cells"]
KINDS = FACES + CELLS
# Gmsh has every kind but the Tri7 faces and Tet14 cells of enriched slave spaces.
GMSH_KINDS = [k for k in KINDS if k["gmsh_type"] is not None]
GMSH_CELLS = [k for k in CELLS if k["gmsh_type"] is not None]


def test_only_the_enriched_kinds_have_no_gmsh_type():
    assert [k["name"] for k in KINDS if k["gmsh_type"] is None] == ["Tri7", "Tet14"]


@pytest.fixture(scope="module")
def session():
    gmsh.initialize(interruptible=False)
    gmsh.option.setNumber("General.Terminal", 0)
    yield gmsh
    gmsh.finalize()


def gmsh_element(session, kind):
    """Gmsh's properties of the kind's type and a model of one element of it
    on its reference nodes: (properties, edges, faces by face type)."""
    name, dim, order, n_nodes, coords, n_primary = session.model.mesh.getElementProperties(kind["gmsh_type"])
    coords = np.asarray(coords).reshape(n_nodes, dim)
    session.model.add(kind["name"])
    entity = session.model.addDiscreteEntity(dim)
    points = np.zeros((n_nodes, 3))
    points[:, :dim] = coords
    tags = list(range(1, n_nodes + 1))
    session.model.mesh.addNodes(dim, entity, tags, points.ravel())
    session.model.mesh.addElementsByType(entity, kind["gmsh_type"], [1], tags)
    edges = np.asarray(session.model.mesh.getElementEdgeNodes(kind["gmsh_type"], -1, False), dtype=int) - 1
    faces = {}
    if dim == 3:
        for face_type in (3, 4):
            nodes = np.asarray(session.model.mesh.getElementFaceNodes(kind["gmsh_type"], face_type, -1, False), dtype=int)
            faces[face_type] = nodes - 1
    session.model.remove()
    return (name, dim, order, n_nodes, coords, n_primary), edges, faces


def seam_coordinates(kind, gmsh_coords):
    """Gmsh's reference coordinates in seam's convention: quadrilateral faces
    on [0, 1]², everything else as Gmsh has it."""
    if kind["shape"] == "quadrangle":
        return (gmsh_coords + 1.0) / 2.0
    return gmsh_coords


@pytest.mark.parametrize("kind", GMSH_KINDS, ids=[k["name"] for k in GMSH_KINDS])
def test_properties_and_reference_nodes_are_gmsh(session, kind):
    (name, dim, order, n_nodes, coords, n_primary), _, _ = gmsh_element(session, kind)
    assert name.split()[0] == SHAPES[kind["shape"]]
    assert dim == (2 if kind in FACES else 3)
    assert (order, n_nodes, n_primary) == (kind["order"], kind["n_nodes"], kind["corners"])
    np.testing.assert_array_equal(np.asarray(kind["reference_nodes"]), seam_coordinates(kind, coords))
    linear = next(k for k in KINDS if k["name"] == kind["linear"])
    assert linear["reference_nodes"] == kind["reference_nodes"][: kind["corners"]]


@pytest.mark.parametrize("kind", GMSH_KINDS, ids=[k["name"] for k in GMSH_KINDS])
def test_edges_and_mid_edge_nodes_are_gmsh(session, kind):
    _, edges, _ = gmsh_element(session, kind)
    per_edge = 2 if kind["order"] == 1 else 3
    edges = edges.reshape(-1, per_edge)
    assert len(edges) == len(kind["edges"])
    for k, (edge, ours) in enumerate(zip(edges, kind["edges"])):
        # Cells list corner pairs sorted, faces in cyclic order.
        assert sorted(edge[:2]) == sorted(ours), f"edge {k}"
        if kind in FACES:
            assert list(edge[:2]) == ours
        if per_edge == 3:
            assert edge[2] == kind["corners"] + k, f"mid-edge node of edge {k}"


def canonical(nodes, corners):
    """A face's nodes rotated so that its smallest corner comes first (the
    mid-edge nodes follow their edges, a centre stays last): equal for the
    same face with the same orientation."""
    c, m, rest = nodes[:corners], nodes[corners : 2 * corners], nodes[2 * corners :]
    r = c.index(min(c))
    return tuple(c[r:] + c[:r] + (m[r:] + m[:r] if m else []) + rest)


@pytest.mark.parametrize("kind", GMSH_CELLS, ids=[k["name"] for k in GMSH_CELLS])
def test_local_faces_are_gmsh_faces_with_their_orientation(session, kind):
    _, _, faces = gmsh_element(session, kind)
    face_kinds = {k["name"]: k for k in FACES}
    ours = sorted(
        canonical(nodes, face_kinds[name]["corners"]) for name, nodes in kind["faces"]
    )
    theirs = []
    for face_type, nodes in faces.items():
        if len(nodes) == 0:
            continue
        # Nodes per face: the face kind with this many corners and the cell's order.
        width = next(
            k["n_nodes"]
            for name, _ in kind["faces"]
            for k in [face_kinds[name]]
            if k["corners"] == face_type
        )
        theirs += [canonical(list(f), face_type) for f in nodes.reshape(-1, width)]
    assert ours == sorted(theirs)
    for name, nodes in kind["faces"]:
        assert len(nodes) == face_kinds[name]["n_nodes"]


def vtk_to_seam(kind, p):
    """VTK's parametric coordinates of a node of the kind's VTK cell, in seam's
    reference coordinates of the kind."""
    r, s, t = p
    shape = kind["shape"]
    if shape in ("triangle", "quadrangle"):
        return [r, s]
    if shape == "tetrahedron":
        return [r, s, t]
    if shape == "hexahedron":
        return [2 * r - 1, 2 * s - 1, 2 * t - 1]
    if shape == "prism":
        return [r, s, 2 * t - 1]
    # VTK's pyramid is collapsed: its apex edges are vertical in (r, s, t).
    return [(2 * r - 1) * (1 - t), (2 * s - 1) * (1 - t), t]


@pytest.mark.parametrize("kind", KINDS, ids=[k["name"] for k in KINDS])
def test_vtk_node_order_matches_vtk_reference_cells(kind):
    vtk = pytest.importorskip("vtk")
    cell = vtk.vtkGenericCell()
    cell.SetCellType(kind["vtk_type"])
    n = cell.GetNumberOfPoints()
    assert n == len(kind["vtk_order"])
    parametric = np.asarray(cell.GetParametricCoords()[: 3 * n]).reshape(n, 3)
    ours = np.asarray(kind["reference_nodes"])[kind["vtk_order"]]
    expected = np.array([vtk_to_seam(kind, p) for p in parametric])
    np.testing.assert_allclose(ours, expected, atol=1e-15)
