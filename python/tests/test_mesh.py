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
