"""seam.Mesh and the (points, faces) tuple input, including mixed face lists."""

import numpy as np
import pytest

import seam
from meshes import as_input, grid, linear_fields


def test_mesh_round_trips_points_and_faces():
    points, tris, quads = grid(4, 2, "mixed")
    mesh = seam.Mesh(points, [tris, quads])
    assert mesh.n_points == len(points) and mesh.n_faces == len(tris) + len(quads)
    assert mesh.points.dtype == np.float64 and mesh.points.shape == (len(points), 3)
    assert mesh.triangles.dtype == np.int64 and mesh.quads.dtype == np.int64
    np.testing.assert_array_equal(mesh.points, points)
    np.testing.assert_array_equal(mesh.triangles, tris)
    np.testing.assert_array_equal(mesh.quads, quads)
    # Properties are copies: changing them leaves the mesh alone.
    mesh.points[:] = 0.0
    np.testing.assert_array_equal(mesh.points, points)


def test_single_type_meshes_have_an_empty_array_of_the_other_type():
    points, tris, _ = grid(2, 2, "triangles")
    mesh = seam.Mesh(points, tris)
    assert mesh.quads.shape == (0, 4)
    points, _, quads = grid(2, 2, "quads")
    mesh = seam.Mesh(points, quads)
    assert mesh.triangles.shape == (0, 3)


def test_repr_counts_faces_and_gives_bounds():
    points, tris, quads = grid(4, 2, "mixed", box=(0.0, 2.0, -1.0, 1.0), z=0.5)
    points = np.vstack([points, [[0.0, 0.0, 0.5]]])  # a point on no face
    text = repr(seam.Mesh(points, [tris, quads]))
    assert text == (
        f"<seam.Mesh: {len(points)} points (1 not on a face), {len(tris)} triangles, "
        f"{len(quads)} quads, bounds [0, 2] × [-1, 1] × [0.5, 0.5]>"
    )


def test_face_lists_may_mix_blocks_and_single_faces():
    points, tris, quads = grid(4, 3, "mixed")
    reference = seam.Mesh(points, [tris, quads])
    # One face per item (plain Python lists of different lengths).
    per_face = [list(map(int, f)) for f in tris] + [list(map(int, f)) for f in quads]
    mesh = seam.Mesh(points.tolist(), per_face)
    np.testing.assert_array_equal(mesh.triangles, reference.triangles)
    np.testing.assert_array_equal(mesh.quads, reference.quads)
    # Blocks and single faces together; a tuple works as well as a list.
    mesh = seam.Mesh(points, (tris[:3], quads, tris[3:5], *tris[5:]))
    np.testing.assert_array_equal(mesh.triangles, tris)
    np.testing.assert_array_equal(mesh.quads, quads)
    # Empty blocks are skipped, whatever their dtype.
    mesh = seam.Mesh(points, [np.zeros((0, 3)), tris, quads, np.zeros((0, 4), dtype=np.uint8)])
    np.testing.assert_array_equal(mesh.triangles, tris)


@pytest.mark.parametrize("dtype", [np.int32, np.int64, np.uint16, np.uint64, np.intp])
def test_any_integer_dtype_for_faces_and_real_dtype_for_points(dtype):
    points, tris, _ = grid(3, 3, "triangles")
    mesh = seam.Mesh((points * 3).astype(np.int32), tris.astype(dtype))
    np.testing.assert_array_equal(mesh.triangles, tris)
    np.testing.assert_array_equal(mesh.points, points * 3)
    mesh = seam.Mesh(points.astype(np.float32), np.asfortranarray(tris.astype(dtype)))
    np.testing.assert_array_equal(mesh.triangles, tris)


@pytest.mark.parametrize("multiplier", ["standard", "dual", "lumped"])
def test_tuple_input_with_mixed_lists_equals_mesh_objects(multiplier):
    master = grid(5, 4, "mixed")
    slave = grid(4, 4, "triangles", jitter=0.12)
    by_tuple = seam.assemble(as_input(*master), as_input(*slave), multiplier)
    by_mesh = seam.assemble(seam.Mesh(*as_input(*master)), seam.Mesh(*as_input(*slave)), multiplier)
    for a, b in ((by_tuple.B, by_mesh.B), (by_tuple.D, by_mesh.D)):
        np.testing.assert_array_equal(a.indptr, b.indptr)
        np.testing.assert_array_equal(a.indices, b.indices)
        np.testing.assert_array_equal(a.data, b.data)
    assert by_tuple.summary == by_mesh.summary
    # Mixed tri/quad on the master side, reproduced linear fields on the slave side.
    if multiplier != "lumped":
        u = by_tuple.transfer(linear_fields(master[0]))
        np.testing.assert_allclose(u, linear_fields(slave[0]), rtol=0, atol=1e-12)


def test_mixed_slave_identity_and_area():
    mesh = grid(6, 4, "mixed", jitter=0.1)
    points, tris, quads = mesh
    op = seam.assemble((points, [quads, tris]), (points, [tris, quads]), "dual")
    assert op.summary["slave_faces"] == len(tris) + len(quads)
    assert op.D.sum() == pytest.approx(1.0, abs=1e-13)
    np.testing.assert_allclose(op.transfer(points), points, rtol=0, atol=1e-12)


def test_warped_quads_are_accepted():
    points, tris, quads = grid(4, 4, "quads")
    warped = points.copy()
    warped[:, 2] = 0.05 * np.sin(3 * points[:, 0]) * np.cos(2 * points[:, 1])
    op = seam.assemble((warped, quads), (warped, quads), "dual")
    np.testing.assert_allclose(op.transfer(warped), warped, rtol=0, atol=1e-12)
    assert op.summary["slave_area"] > 1.0


def second_order_patch():
    """A 2×1 patch of a Quad9 and a Quad8 on z = x² (curved), and a Tri6 over
    the unit triangle beside them, sharing edges: nodes in Gmsh order."""
    grid_xy = [(x / 2, y / 2) for y in range(3) for x in range(5)]  # 5 × 3 nodes, x in [0, 2]
    points = [[x, y, x * x] for x, y in grid_xy]
    at = lambda i, j: 5 * j + i  # noqa: E731
    quad9 = [[at(0, 0), at(2, 0), at(2, 2), at(0, 2), at(1, 0), at(2, 1), at(1, 2), at(0, 1), at(1, 1)]]
    quad8 = [[at(2, 0), at(4, 0), at(4, 2), at(2, 2), at(3, 0), at(4, 1), at(3, 2), at(2, 1)]]
    # A Tri6 below the quads, y in [-1, 0], sharing the edge (0,0)-(1,0).
    first = len(points)
    points += [[0.5, -0.5, 0.25], [0.0, -1.0, 0.0], [0.25, -0.5, 0.0625], [0.0, -0.5, 0.0]]
    tri6 = [[at(0, 0), first + 1, at(2, 0), first + 3, first + 0, at(1, 0)]]
    return (
        np.array(points, dtype=float),
        np.array(tri6, dtype=np.int64),
        np.array(quad8, dtype=np.int64),
        np.array(quad9, dtype=np.int64),
    )


def test_second_order_faces_round_trip_through_the_tuple_input():
    points, tri6, quad8, quad9 = second_order_patch()
    tris, quads = np.array([[0, 2, 10]]), np.array([[2, 4, 14, 12]])
    for faces in ([tri6, quad8, quad9, tris, quads], [quad9, quads, tri6, tris, quad8]):
        mesh = seam.Mesh(points, faces)
        assert mesh.n_faces == 5
        for name, block in [("tri6", tri6), ("quad8", quad8), ("quad9", quad9), ("triangles", tris), ("quads", quads)]:
            got = getattr(mesh, name)
            assert got.dtype == np.int64, name
            np.testing.assert_array_equal(got, block, err_msg=name)
        # What comes out goes back in.
        again = seam.Mesh(mesh.points, [mesh.tri6, mesh.quad8, mesh.quad9, mesh.triangles, mesh.quads])
        for name in ("tri6", "quad8", "quad9", "triangles", "quads"):
            np.testing.assert_array_equal(getattr(again, name), getattr(mesh, name), err_msg=name)
    # Single faces in a list, unsigned indices, and empty getters.
    mesh = seam.Mesh(points, [tri6[0], quad9[0].astype(np.uint32), quad8[0].tolist()])
    np.testing.assert_array_equal(mesh.quad9, quad9)
    mesh = seam.Mesh(points, tri6)
    assert mesh.quad8.shape == (0, 8) and mesh.quad9.shape == (0, 9) and mesh.triangles.shape == (0, 3)
    assert "1 Tri6" in repr(mesh) and "0 triangles, 0 quads" in repr(mesh)


@pytest.mark.parametrize("width", [2, 5, 10, 11])
def test_faces_of_other_widths_are_refused_with_the_widths_allowed(width):
    points, *_ = second_order_patch()
    faces = np.arange(2 * width).reshape(2, width) % len(points)
    allowed = r"3 \(triangles\), 4 \(quads\), 6 \(Tri6\), 7 \(Tri7\), 8 \(Quad8\) or 9 \(Quad9\)"
    with pytest.raises(ValueError, match=rf"faces must have {allowed} columns, got shape \(2, {width}\)"):
        seam.Mesh(points, faces)
    with pytest.raises(ValueError, match=rf"faces\[1\] must list {allowed} node indices, got {width}"):
        seam.Mesh(points, [np.arange(6), np.arange(width)])


def test_second_order_faces_are_checked_like_first_order_ones():
    points, tri6, _, quad9 = second_order_patch()
    bad = quad9.copy()
    bad[0, 8] = bad[0, 0]
    with pytest.raises(seam.MeshError, match="face 0 is degenerate: node 0 appears twice"):
        seam.Mesh(points, bad)
    bad = tri6.copy()
    bad[0, 4] = len(points)
    with pytest.raises(seam.MeshError, match=rf"face 0 corner 4 refers to node {len(points)}"):
        seam.Mesh(points, bad)
    bad[0, 4] = -1
    with pytest.raises(seam.MeshError, match="face 0 corner 4 refers to node -1"):
        seam.Mesh(points, bad)
