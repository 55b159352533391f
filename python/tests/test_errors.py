"""Bad input raises the right exception class with a message naming the problem."""

import re

import numpy as np
import pytest

import seam
from meshes import grid

POINTS, TRIS, _ = grid(2, 2, "triangles")
MASTER = grid(3, 3, "quads")[0], grid(3, 3, "quads")[2]


def square(points=None, faces=None):
    return (POINTS if points is None else points, TRIS if faces is None else faces)


def raises_in_mesh_and_assemble(exc, pattern, points=None, faces=None):
    """The same error from seam.Mesh and from assemble's tuple input (both sides)."""
    p, f = square(points, faces)
    with pytest.raises(exc, match=pattern):
        seam.Mesh(p, f)
    with pytest.raises(exc, match=pattern) as info:
        seam.assemble(MASTER, (p, f))
    assert str(info.value).startswith("slave: ")
    with pytest.raises(exc, match=pattern) as info:
        seam.assemble((p, f), MASTER)
    assert str(info.value).startswith("master: ")


def test_exception_hierarchy():
    for cls in (seam.MeshError, seam.MshError, seam.MortarError):
        assert issubclass(cls, ValueError)
    for cls in (seam.NoOverlapError, seam.InvalidOptionError, seam.FactorizationError):
        assert issubclass(cls, seam.MortarError)
    assert seam.NoOverlapError.__module__ == "seam"


@pytest.mark.parametrize(
    "points, shape",
    [
        (POINTS[:, :2], "(9, 2)"),
        (POINTS.ravel(), "(27,)"),
        (POINTS[None], "(1, 9, 3)"),
    ],
)
def test_points_of_the_wrong_shape(points, shape):
    raises_in_mesh_and_assemble(ValueError, re.escape(f"points must be an n×3 array (x, y, z per row), got shape {shape}"), points=points)


def test_ragged_points():
    raises_in_mesh_and_assemble(ValueError, "points cannot be converted to an array", points=[[0, 0, 0], [1, 0]])


@pytest.mark.parametrize(
    "faces, pattern",
    [
        (np.zeros((2, 5), dtype=int), r"faces must have 3 \(triangles\), 4 \(quads\), 6 \(Tri6\), 7 \(Tri7\), 8 \(Quad8\) or 9 \(Quad9\) columns, got shape \(2, 5\)"),
        (np.array([0, 1, 2]), r"faces must be an m×k array with k = 3 \(triangles\), 4 \(quads\), 6 .*got shape \(3,\)"),
        (np.zeros((2, 2, 3), dtype=int), r"faces must be an m×k.*got shape \(2, 2, 3\)"),
        ([TRIS, np.zeros((1, 2), dtype=int)], r"faces\[1\] must have 3 \(triangles\).*columns, got shape \(1, 2\)"),
        ([[0, 1, 2], [0, 1, 2, 3, 4]], r"faces\[1\] must list 3 \(triangles\), 4 \(quads\), 6 \(Tri6\), 7 \(Tri7\), 8 \(Quad8\) or 9 \(Quad9\) node indices, got 5"),
        ([TRIS, 3], r"faces\[1\] must be one face .* got shape \(\)"),
    ],
)
def test_faces_of_the_wrong_shape(faces, pattern):
    raises_in_mesh_and_assemble(ValueError, pattern, faces=faces)


def test_wrong_dtypes_are_type_errors():
    raises_in_mesh_and_assemble(TypeError, "faces must be integer node indices, got dtype float64", faces=TRIS.astype(float))
    raises_in_mesh_and_assemble(TypeError, r"faces\[0\] must be integer node indices, got dtype bool", faces=[TRIS > 3])
    raises_in_mesh_and_assemble(TypeError, "points must be real numbers, got dtype complex128", points=POINTS + 0j)
    raises_in_mesh_and_assemble(TypeError, "points must be real numbers, got dtype <U1", points=np.full((9, 3), "a"))


def test_index_out_of_range():
    faces = TRIS.copy()
    faces[3, 2] = 9
    raises_in_mesh_and_assemble(
        seam.MeshError, "face 3 corner 2 refers to node 9, but there are only 9 nodes", faces=faces
    )


def test_negative_index():
    faces = TRIS.copy()
    faces[1, 0] = -1
    raises_in_mesh_and_assemble(seam.MeshError, "face 1 corner 0 refers to node -1; node indices are 0-based", faces=faces)


def test_face_numbers_count_through_a_mixed_list():
    _, _, quads = grid(2, 2, "quads")
    bad = quads.copy()
    bad[1, 3] = 100
    # 8 triangles first, so the second quad is face 9.
    raises_in_mesh_and_assemble(seam.MeshError, "face 9 corner 3 refers to node 100", faces=[TRIS, bad])


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_non_finite_point(value):
    points = POINTS.copy()
    points[4, 1] = value
    raises_in_mesh_and_assemble(seam.MeshError, "node 4 has a non-finite coordinate", points=points)


def test_coordinates_out_of_range():
    points = POINTS.copy()
    points[4, 2] = 1e300
    raises_in_mesh_and_assemble(
        seam.MeshError, re.escape("node 4 has coordinate 1e300, out of range (|x| ≤ 1e50)"), points=points
    )


def test_degenerate_faces():
    faces = TRIS.copy()
    faces[2] = [0, 1, 0]
    raises_in_mesh_and_assemble(seam.MeshError, "face 2 is degenerate: node 0 appears twice", faces=faces)
    faces = TRIS.copy()
    faces[5] = [0, 1, 2]  # three points on the line y = 0
    raises_in_mesh_and_assemble(seam.MeshError, "face 5 is degenerate: its area is zero", faces=faces)


def test_no_faces():
    raises_in_mesh_and_assemble(seam.MeshError, "the mesh has no faces", faces=np.zeros((0, 3), dtype=int))
    raises_in_mesh_and_assemble(seam.MeshError, "the mesh has no faces", faces=[])


def test_non_overlapping_meshes():
    far = POINTS + [10.0, 0.0, 0.0]
    with pytest.raises(seam.NoOverlapError, match="the meshes do not overlap") as info:
        seam.assemble(MASTER, (far, TRIS))
    assert isinstance(info.value, ValueError)
    above = POINTS + [0.0, 0.0, 3.0]
    with pytest.raises(seam.NoOverlapError, match="do not overlap.*away from the nearest slave face"):
        seam.assemble(MASTER, (above, TRIS))


@pytest.mark.parametrize(
    "kwargs, exc, pattern",
    [
        ({"multiplier": "mortar"}, ValueError, 'unknown multiplier "mortar": expected "standard", "dual" or "lumped"'),
        ({"facing": "up"}, ValueError, 'unknown facing "up"'),
        ({"max_gap": -1.0}, seam.InvalidOptionError, "invalid option: the max gap must be a finite non-negative number, got -1"),
        ({"max_gap": float("nan")}, seam.InvalidOptionError, "the max gap must be"),
        ({"max_angle": 90.0}, seam.InvalidOptionError, r"the max angle must lie in \(0, 90\) degrees, got 90"),
        ({"warped_quad_degree": 0}, seam.InvalidOptionError, "the quadrature degree must lie in 1..=20, got 0"),
        ({"threads": 0}, ValueError, "threads must be at least 1, got 0"),
        ({"threads": -3}, ValueError, "threads must be at least 1, got -3"),
        ({"threads": 100000}, ValueError, r"threads=100000: 100000 worker threads are more than 4 per core \(this machine has \d+ cores?: at most \d+\)"),
    ],
)
def test_bad_options(kwargs, exc, pattern):
    with pytest.raises(exc, match=pattern):
        seam.assemble(MASTER, square(), **kwargs)


@pytest.mark.parametrize("bad", [None, 3, "mesh.msh", [POINTS, TRIS], (POINTS,), (POINTS, TRIS, TRIS)])
def test_master_and_slave_must_be_meshes_or_pairs(bad):
    with pytest.raises(TypeError, match="master must be a seam.Mesh or a \\(points, faces\\) tuple"):
        seam.assemble(bad, square())
    with pytest.raises(TypeError, match="slave must be a seam.Mesh or a \\(points, faces\\) tuple"):
        seam.assemble(square(), bad)


def test_transfer_input_shapes():
    op = seam.assemble(MASTER, square(), "dual")
    n_slave, n_master = op.shape
    assert (n_slave, n_master) == (9, 16)
    with pytest.raises(ValueError, match=re.escape("values must have shape (16,) or (16, k), one row per master point, got shape (9,)")):
        op.transfer(np.ones(n_slave))
    with pytest.raises(ValueError, match=re.escape("got shape (16, 2, 1)")):
        op.transfer(np.ones((n_master, 2, 1)))
    with pytest.raises(ValueError, match=re.escape("got shape ()")):
        op.transfer(1.0)
    with pytest.raises(TypeError, match="values must be real numbers, got dtype complex128"):
        op.transfer(np.ones(n_master, dtype=complex))
    with pytest.raises(ValueError, match=re.escape("loads must have shape (9,) or (9, k), one row per slave point, got shape (16,)")):
        op.transfer_conservative(np.ones(n_master))


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_values_are_refused_not_transferred(bad):
    op = seam.assemble(MASTER, square(), "dual")
    n_slave, n_master = op.shape
    values = np.ones(n_master)
    values[7] = bad
    with pytest.raises(ValueError, match=re.escape(f"values[7] is {bad} (master point 7): only finite values can be used").replace("nan", "NaN")):
        op.transfer(values)
    vectors = np.ones((n_slave, 2))
    vectors[3, 1] = bad
    with pytest.raises(ValueError, match=re.escape(f"loads[3, 1] is {bad} (slave point 3)").replace("nan", "NaN")):
        op.transfer_conservative(vectors)


def test_mesh_properties_are_read_only():
    mesh = seam.Mesh(*square())
    with pytest.raises(AttributeError):
        mesh.points = POINTS


@pytest.mark.parametrize(
    "entry, cls",
    [("mesh", seam.MeshError), ("read_mesh", seam.MshError), ("mortar", seam.MortarError), ("solve", seam.SolveError)],
)
def test_a_panic_in_the_library_is_the_entry_points_exception(entry, cls):
    """A bug that panics in Rust raises the entry point's class (an
    `Exception`, which pyo3's PanicException is not) with the panic's message."""
    from seam import _seam

    with pytest.raises(Exception) as info:
        _seam._panic_in(entry)
    assert type(info.value) is cls
    assert str(info.value) == "internal error in seam (a bug; please report it with the input): a panic forced by a test"


@pytest.mark.parametrize(
    "field, value, message",
    [
        ("young", float("inf"), "case dict: body[0].young: inf is not a finite number"),
        ("body_force", [0.0, float("-inf"), 0.0], "case dict: body[0].body_force[1]: -inf is not a finite number"),
        ("t", (0.0, float("nan"), 1.0), "case dict: traction[0].t[1]: NaN is not a finite number"),
    ],
)
def test_a_case_dict_with_inf_or_nan_names_the_field(field, value, message):
    """JSON has no inf or NaN: the field holding one is named, not a position
    in the JSON text."""
    body = {"name": "a", "mesh": "a.msh", "young": 1.0, "poisson": 0.3}
    traction = {"boundary": "a:top", "t": [0.0, 0.0, 1.0]}
    (body if field != "t" else traction)[field] = value
    with pytest.raises(seam.SolveError) as info:
        seam.solve({"body": [body], "traction": [traction]})
    assert str(info.value) == message
