"""seam.read_mesh on the Gmsh fixtures of crates/seam-io/tests/data."""

import errno
import pathlib

import numpy as np
import pytest

import seam
from meshes import MSH_DATA, grid

SQUARE_TRI = MSH_DATA / "square_tri.v41.ascii.msh"

# square_tri.v41.ascii.msh copied by hand: node tags 1..31 in file order, then the
# 44 triangles of physical group 7 "interface" as node tags (elements 17..60).
SQUARE_TRI_POINTS = np.array(
    [
        [0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
        [0.25, 0, 0], [0.5, 0, 0], [0.75, 0, 0],
        [1, 0.25, 0], [1, 0.5, 0], [1, 0.75, 0],
        [0.75, 1, 0], [0.5, 1, 0], [0.25, 1, 0],
        [0, 0.75, 0], [0, 0.5, 0], [0, 0.25, 0],
        [0.3640358958115698, 0.7953881872687139, 0],
        [0.375, 0.2165063509461096, 0],
        [0.788306988736042, 0.3760593423202191, 0],
        [0.7885993441589132, 0.6240050006292597, 0],
        [0.5669872981077807, 0.5, 0],
        [0.6328802641586005, 0.2125963991930914, 0],
        [0.2917273223602594, 0.4796557459309013, 0],
        [0.6010369744916511, 0.7634332779177373, 0],
        [0.1768489190752347, 0.3103138265074931, 0],
        [0.155290190286839, 0.625, 0],
        [0.8169872981077806, 0.8169872981077807, 0],
        [0.8169872981077806, 0.1830127018922193, 0],
        [0.1749592066742909, 0.8219022194693535, 0],
        [0.4115988944960767, 0.6167789108779783, 0],
        [0.1484804596480833, 0.1459265064213862, 0],
    ],
    dtype=float,
)
SQUARE_TRI_TAGS = [
    [21, 23, 18], [18, 22, 21], [21, 22, 19], [20, 24, 21], [15, 25, 23], [24, 30, 21],
    [23, 26, 15], [20, 21, 19], [6, 18, 5], [9, 20, 19], [9, 19, 8], [10, 20, 9],
    [13, 17, 12], [16, 25, 15], [26, 30, 17], [7, 22, 6], [12, 24, 11], [6, 22, 18],
    [17, 24, 12], [21, 30, 23], [23, 25, 18], [8, 28, 2], [3, 27, 10], [2, 28, 7],
    [11, 27, 3], [14, 29, 4], [4, 29, 13], [17, 30, 24], [17, 29, 26], [18, 31, 5],
    [23, 30, 26], [7, 28, 22], [24, 27, 11], [15, 26, 14], [13, 29, 17], [19, 28, 8],
    [10, 27, 20], [25, 31, 18], [5, 31, 1], [1, 31, 16], [22, 28, 19], [20, 27, 24],
    [26, 29, 14], [16, 31, 25],
]
SQUARE_TRI_TRIANGLES = np.array(SQUARE_TRI_TAGS) - 1


def test_square_tri_matches_the_mesh_built_by_hand():
    mesh = seam.read_mesh(SQUARE_TRI, group="interface")
    np.testing.assert_array_equal(mesh.points, SQUARE_TRI_POINTS)
    np.testing.assert_array_equal(mesh.triangles, SQUARE_TRI_TRIANGLES)
    assert mesh.quads.shape == (0, 4)
    # The same operator from the file and from the arrays.
    master = grid(3, 5, "quads")[0], grid(3, 5, "quads")[2]
    from_file = seam.assemble(master, mesh)
    by_hand = seam.assemble(master, (SQUARE_TRI_POINTS, SQUARE_TRI_TRIANGLES))
    for a, b in ((from_file.B, by_hand.B), (from_file.D, by_hand.D)):
        np.testing.assert_array_equal(a.indptr, b.indptr)
        np.testing.assert_array_equal(a.indices, b.indices)
        np.testing.assert_array_equal(a.data, b.data)


@pytest.mark.parametrize("flavour", ["v41.bin", "v22.ascii", "v22.bin"])
def test_every_flavour_reads_the_same_mesh(flavour):
    mesh = seam.read_mesh(MSH_DATA / f"square_tri.{flavour}.msh", group="interface")
    np.testing.assert_allclose(mesh.points, SQUARE_TRI_POINTS, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(mesh.triangles, SQUARE_TRI_TRIANGLES)


def test_group_by_number_by_name_or_none():
    by_name = seam.read_mesh(str(SQUARE_TRI), group="interface")
    by_number = seam.read_mesh(SQUARE_TRI, group=7)
    whole = seam.read_mesh(SQUARE_TRI)
    for mesh in (by_number, whole):
        np.testing.assert_array_equal(mesh.triangles, by_name.triangles)


def test_fixture_counts_match_expected_txt():
    # From crates/seam-io/tests/data/expected.txt.
    mixed = seam.read_mesh(MSH_DATA / "square_mixed.v41.ascii.msh", group="interface")
    assert (mixed.n_points, len(mixed.triangles), len(mixed.quads)) == (38, 22, 16)
    box = seam.read_mesh(MSH_DATA / "box_tet.v41.ascii.msh")  # volume boundary
    assert (box.n_points, len(box.triangles), len(box.quads)) == (45, 84, 0)
    assert "(1 not on a face)" in repr(box)
    top = seam.read_mesh(MSH_DATA / "box_hex.v41.ascii.msh", group="top")
    assert (top.n_points, len(top.triangles), len(top.quads)) == (45, 0, 8)


def test_mixed_fixture_against_itself_is_the_identity():
    mesh = seam.read_mesh(MSH_DATA / "square_mixed.v41.ascii.msh", group="interface")
    op = seam.assemble(mesh, mesh, "dual")
    assert op.summary["slave_area"] == pytest.approx(1.0, abs=1e-13)
    np.testing.assert_allclose(op.transfer(mesh.points), mesh.points, rtol=0, atol=1e-12)


def test_unknown_group_lists_the_available_ones():
    with pytest.raises(seam.MshError, match=r'no physical group "lid".*available: "interface" \(7\)'):
        seam.read_mesh(SQUARE_TRI, group="lid")
    with pytest.raises(ValueError):  # MshError is a ValueError
        seam.read_mesh(SQUARE_TRI, group=99)
    with pytest.raises(TypeError, match="group must be"):
        seam.read_mesh(SQUARE_TRI, group=1.5)


def test_missing_file_is_file_not_found(tmp_path):
    path = tmp_path / "missing.msh"
    with pytest.raises(FileNotFoundError, match="cannot read the file") as info:
        seam.read_mesh(path)
    assert info.value.errno == errno.ENOENT
    assert info.value.filename == str(path)


def test_directory_is_an_os_error(tmp_path):
    with pytest.raises(OSError) as info:
        seam.read_mesh(tmp_path)
    assert isinstance(info.value, IsADirectoryError)


def test_not_an_msh_file(tmp_path):
    path = tmp_path / "mesh.msh"
    path.write_text("solid cube\nendsolid\n")
    with pytest.raises(seam.MshError, match=r"mesh\.msh: line 1: not a Gmsh MSH file"):
        seam.read_mesh(path)


def test_truncated_file_names_the_section(tmp_path):
    text = SQUARE_TRI.read_text()
    path = tmp_path / "cut.msh"
    path.write_text(text[: text.index("$EndNodes")])
    with pytest.raises(seam.MshError, match=r"cut\.msh: .*truncated file.*\$Nodes"):
        seam.read_mesh(pathlib.Path(path))


# From crates/seam-io/tests/data/second_order.txt (top: a physical surface).
SECOND_ORDER_TOPS = [
    # fixture, (triangles, quads, tri6, quad8, quad9) of "top", of the boundary
    ("box_tet_o2", (0, 0, 14, 0, 0), (0, 0, 84, 0, 0)),
    ("box_hex_o2", (0, 0, 0, 0, 8), (0, 0, 0, 0, 40)),
    ("box_hex_o2s", (0, 0, 0, 8, 0), (0, 0, 0, 40, 0)),
    ("slab_prism_o2", (0, 0, 26, 0, 0), (0, 0, 52, 0, 24)),
    ("slab_prism_o2s", (0, 0, 26, 0, 0), (0, 0, 52, 24, 0)),
    ("hybrid_pyramid_o2", (0, 0, 14, 0, 4), (0, 0, 70, 0, 20)),
    ("hybrid_pyramid_o2s", (0, 0, 14, 4, 0), (0, 0, 70, 20, 0)),
]
FACE_KINDS = ("triangles", "quads", "tri6", "quad8", "quad9")


def assert_mid_nodes_on_straight_edges(mesh, block):
    """The fixtures have flat sides: Gmsh puts mid-edge nodes in the middle of
    their edges, a Quad9 centre at the mean of the corners."""
    p = mesh.points
    k = 3 if block.shape[1] == 6 else 4
    corners = p[block[:, :k]]
    middles = 0.5 * (corners + np.roll(corners, -1, axis=1))
    np.testing.assert_allclose(p[block[:, k : 2 * k]], middles, rtol=0, atol=1e-12)
    if block.shape[1] == 9:
        np.testing.assert_allclose(p[block[:, 8]], corners.mean(axis=1), rtol=0, atol=1e-12)


@pytest.mark.parametrize("flavour", ["v41.ascii", "v41.bin", "v22.ascii", "v22.bin"])
@pytest.mark.parametrize("fixture, top, boundary", SECOND_ORDER_TOPS)
def test_second_order_fixtures_read_as_second_order_faces(fixture, top, boundary, flavour):
    path = MSH_DATA / f"{fixture}.{flavour}.msh"
    for group, counts in (("top", top), (None, boundary)):
        mesh = seam.read_mesh(path, group=group)
        shapes = [getattr(mesh, kind).shape for kind in FACE_KINDS]
        assert shapes == [(n, w) for n, w in zip(counts, (3, 4, 6, 8, 9))], (group, shapes)
        assert mesh.n_faces == sum(counts)
        for kind in ("tri6", "quad8", "quad9"):
            block = getattr(mesh, kind)
            assert block.dtype == np.int64
            if len(block):
                assert_mid_nodes_on_straight_edges(mesh, block)
    assert "Tri6" in repr(mesh) or "Quad" in repr(mesh)


@pytest.mark.parametrize("fixture", ["box_tet_o2", "hybrid_pyramid_o2", "hybrid_pyramid_o2s"])
def test_second_order_top_has_the_nodes_gmsh_gives(fixture):
    """Gmsh's own API (the gmsh package) and seam agree on the top's faces:
    the same node coordinates, face by face (seam may start a face at another
    corner or reverse it to point outward)."""
    gmsh = pytest.importorskip("gmsh")
    path = MSH_DATA / f"{fixture}.v41.bin.msh"
    mesh = seam.read_mesh(path, group="top")
    ours = sorted(
        tuple(sorted(map(tuple, mesh.points[row].round(12).tolist())))
        for kind in ("tri6", "quad8", "quad9")
        for row in getattr(mesh, kind)
    )
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        tag = next(t for d, t in gmsh.model.getPhysicalGroups(2) if gmsh.model.getPhysicalName(d, t) == "top")
        theirs = []
        for entity in gmsh.model.getEntitiesForPhysicalGroup(2, tag):
            types, _, node_tags = gmsh.model.mesh.getElements(2, entity)
            for t, nodes in zip(types, node_tags):
                n = gmsh.model.mesh.getElementProperties(t)[3]
                for row in np.asarray(nodes).reshape(-1, n):
                    coords = [tuple(np.round(gmsh.model.mesh.getNode(int(v))[0], 12).tolist()) for v in row]
                    theirs.append(tuple(sorted(coords)))
    finally:
        gmsh.finalize()
    assert ours == sorted(theirs)


def test_third_order_elements_are_refused_naming_tag_and_type(tmp_path):
    nodes = "\n".join(f"{i + 1} {x} {y} 0" for i, (x, y) in enumerate(
        [(0, 0), (1, 0), (0, 1), (1 / 3, 0), (2 / 3, 0), (2 / 3, 1 / 3), (1 / 3, 2 / 3), (0, 2 / 3), (0, 1 / 3), (1 / 3, 1 / 3)]
    ))
    path = tmp_path / "p3.msh"
    path.write_text(
        f"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10\n{nodes}\n$EndNodes\n"
        "$Elements\n1\n57 21 2 3 1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n"
    )
    with pytest.raises(seam.MshError, match=r"element 57 is a 10-node triangle \(type 21\); only triangles "
                       r"\(3 or 6 nodes\) and quadrangles \(4, 8 or 9 nodes\) are supported"):
        seam.read_mesh(path, group=3)
