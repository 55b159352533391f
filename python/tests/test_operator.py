"""Invariants of B, D and T through the Python API, checked against SciPy."""

import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.linalg

import seam
from meshes import SEED_VALUES, as_input, grid, linear_fields

MULTIPLIERS = ["standard", "dual", "lumped"]
# Multipliers whose transfer reproduces linear fields on non-matching meshes (I4).
LINEAR_EXACT = ["standard", "dual"]

# Non-matching pairs (master, slave) covering the unit square; "jittered" is a
# triangulation with moved interior points, so no edge lines up with the other side.
PAIRS = {
    "tri5x3-quad4x4": (grid(5, 3, "triangles"), grid(4, 4, "quads")),
    "jittered7x6-quad3x5": (grid(7, 6, "triangles", jitter=0.12), grid(3, 5, "quads")),
    "quad6x6-jittered4x4": (grid(6, 6, "quads"), grid(4, 4, "triangles", jitter=0.12, seed=3)),
    "mixed4x4-jittered5x5": (grid(4, 4, "mixed"), grid(5, 5, "triangles", jitter=0.12, seed=5)),
}
SAME = {
    "quads": grid(4, 3, "quads"),
    "triangles": grid(3, 4, "triangles"),
    "jittered": grid(6, 5, "triangles", jitter=0.12),
    "mixed": grid(4, 4, "mixed"),
}
# The slave sticks out of the master on the right: [0.3, 1.3] × [0, 1] against
# the unit square, so some slave points are uncovered and some partly covered.
PARTIAL = (grid(5, 4, "triangles", jitter=0.12), grid(5, 5, "quads", box=(0.3, 1.3, 0.0, 1.0)))
PARTIAL_AREA = 0.7

SUMMARY_KEYS = {
    "slave_nodes",
    "master_nodes",
    "slave_faces",
    "master_faces",
    "candidate_pairs",
    "intersecting_pairs",
    "segments",
    "slave_area",
    "covered_area",
    "uncovered_slave_nodes",
    "max_gap",
    "max_overlap",
    "inverse_failures",
    "dual_fallbacks",
    "multiplier",
}


def assemble(pair, multiplier, **kwargs):
    master, slave = pair
    return seam.assemble(as_input(*master), as_input(*slave), multiplier=multiplier, **kwargs)


def rng():
    return np.random.default_rng(SEED_VALUES)


@pytest.mark.parametrize("multiplier", MULTIPLIERS)
@pytest.mark.parametrize("pair", [*PAIRS.values(), PARTIAL], ids=[*PAIRS, "partial"])
def test_i1_row_sums_of_d_and_b_agree_and_t_preserves_constants(pair, multiplier):
    op = assemble(pair, multiplier)
    n_slave, n_master = op.shape
    assert op.B.shape == (n_slave, n_master)
    assert op.D.shape == (n_slave, n_slave)
    d1 = op.D @ np.ones(n_slave)
    b1 = op.B @ np.ones(n_master)
    np.testing.assert_allclose(d1, b1, rtol=0, atol=1e-14)
    covered = op.covered
    assert covered.any()
    t1 = op.transfer(np.ones(n_master))
    np.testing.assert_allclose(t1[covered], 1.0, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(t1[~covered], 0.0)
    if op.T is not None:
        np.testing.assert_allclose((op.T @ np.ones(n_master))[covered], 1.0, rtol=0, atol=1e-12)


@pytest.mark.parametrize("multiplier", MULTIPLIERS)
@pytest.mark.parametrize("pair", PAIRS.values(), ids=PAIRS)
def test_i2_sums_of_d_and_b_are_the_covered_area(pair, multiplier):
    op = assemble(pair, multiplier)
    assert op.D.sum() == pytest.approx(1.0, abs=1e-13)
    assert op.B.sum() == pytest.approx(1.0, abs=1e-13)
    assert op.summary["covered_area"] == pytest.approx(1.0, abs=1e-13)
    assert op.summary["slave_area"] == pytest.approx(1.0, abs=1e-13)
    np.testing.assert_allclose(op.coverage, 1.0, rtol=0, atol=1e-12)
    assert op.covered.all()
    assert op.uncovered_nodes.size == 0


@pytest.mark.parametrize("multiplier", MULTIPLIERS)
def test_i2_partial_overlap_covers_the_intersection(multiplier):
    op = assemble(PARTIAL, multiplier)
    assert op.D.sum() == pytest.approx(PARTIAL_AREA, abs=1e-13)
    assert op.B.sum() == pytest.approx(PARTIAL_AREA, abs=1e-13)
    assert op.summary["covered_area"] == pytest.approx(PARTIAL_AREA, abs=1e-13)
    assert op.summary["slave_area"] == pytest.approx(1.0, abs=1e-13)
    # Slave columns are at x = 0.3, 0.5, ..., 1.3: the supports of the points at
    # x = 1.3 lie beyond x = 1, those at x = 1.1 are partly covered.
    slave_points = PARTIAL[1][0]
    outside = slave_points[:, 0] > 1.2
    partly = np.isclose(slave_points[:, 0], 1.1)
    assert op.covered[partly].all()
    assert (op.coverage[partly] < 0.5).all()
    assert not op.covered[outside].any()
    np.testing.assert_array_equal(op.uncovered_nodes, np.flatnonzero(outside))
    assert op.summary["uncovered_slave_nodes"] == outside.sum()
    np.testing.assert_array_equal(op.covered, op.coverage > 1e-10)
    assert ((op.coverage >= 0) & (op.coverage <= 1 + 1e-12)).all()


@pytest.mark.parametrize("multiplier", LINEAR_EXACT)
@pytest.mark.parametrize("mesh", SAME.values(), ids=SAME)
def test_i3_identical_meshes_transfer_is_identity(mesh, multiplier):
    op = assemble((mesh, mesh), multiplier)
    n = op.shape[0]
    v = rng().standard_normal((n, 2))
    np.testing.assert_allclose(op.transfer(v), v, rtol=0, atol=1e-12)
    np.testing.assert_allclose(op.transfer(v[:, 0]), v[:, 0], rtol=0, atol=1e-12)
    if multiplier == "standard":
        assert op.T is None
        # Standard D is the slave mass matrix, and B equals it on identical meshes.
        np.testing.assert_allclose(op.B.toarray(), op.D.toarray(), rtol=0, atol=1e-14)
    else:
        np.testing.assert_allclose(op.T.toarray(), np.eye(n), rtol=0, atol=1e-12)


@pytest.mark.parametrize("mesh", SAME.values(), ids=SAME)
def test_i3_lumped_on_identical_meshes_is_the_row_normalised_mass_matrix(mesh):
    # Lumping is not exact there: T = diag(M 1)⁻¹ M with M the mass matrix.
    M = assemble((mesh, mesh), "standard").D
    op = assemble((mesh, mesh), "lumped")
    expected = scipy.sparse.diags(1.0 / (M @ np.ones(M.shape[0]))) @ M
    np.testing.assert_allclose(op.T.toarray(), expected.toarray(), rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(op.D.diagonal(), M @ np.ones(M.shape[0]), rtol=1e-14)


@pytest.mark.parametrize("multiplier", LINEAR_EXACT)
@pytest.mark.parametrize("pair", PAIRS.values(), ids=PAIRS)
def test_i4_linear_fields_are_reproduced(pair, multiplier):
    (master, _, _), (slave, _, _) = pair
    op = assemble(pair, multiplier)
    u = op.transfer(linear_fields(master))
    assert u.shape == (len(slave), 3)
    np.testing.assert_allclose(u, linear_fields(slave), rtol=0, atol=1e-12)


@pytest.mark.parametrize("multiplier", MULTIPLIERS)
@pytest.mark.parametrize("pair", PAIRS.values(), ids=PAIRS)
def test_i6_conservative_transfer_keeps_the_total(pair, multiplier):
    op = assemble(pair, multiplier)
    n_slave, n_master = op.shape
    f = rng().standard_normal((n_slave, 3))
    fm = op.transfer_conservative(f)
    assert fm.shape == (n_master, 3)
    np.testing.assert_allclose(fm.sum(axis=0), f.sum(axis=0), rtol=1e-12, atol=1e-12)
    f1 = op.transfer_conservative(f[:, 1])
    assert f1.shape == (n_master,)
    assert f1.sum() == pytest.approx(f[:, 1].sum(), rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("multiplier", MULTIPLIERS)
def test_i6_partial_overlap_keeps_loads_on_covered_points(multiplier):
    op = assemble(PARTIAL, multiplier)
    f = rng().standard_normal(op.shape[0])
    f[~op.covered] = 0.0
    assert op.transfer_conservative(f).sum() == pytest.approx(f.sum(), rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("pair", [*PAIRS.values(), PARTIAL], ids=[*PAIRS, "partial"])
def test_standard_transfer_equals_spsolve_on_covered_rows(pair):
    op = assemble(pair, "standard")
    assert op.T is None
    B, D, c = op.B, op.D, op.covered
    D_cc = D[c][:, c].tocsc()
    v = rng().standard_normal((op.shape[1], 2))
    expected = np.zeros((op.shape[0], 2))
    expected[c] = scipy.sparse.linalg.spsolve(D_cc, (B @ v)[c])
    np.testing.assert_allclose(op.transfer(v), expected, rtol=1e-10, atol=1e-12)
    # Conservative: Tᵀ f = Bᵀ [D_cc⁻¹ f_c; 0].
    f = rng().standard_normal(op.shape[0])
    y = np.zeros(op.shape[0])
    y[c] = scipy.sparse.linalg.spsolve(D_cc, f[c])
    np.testing.assert_allclose(op.transfer_conservative(f), B.T @ y, rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("multiplier", ["dual", "lumped"])
@pytest.mark.parametrize("pair", [*PAIRS.values(), PARTIAL], ids=[*PAIRS, "partial"])
def test_diagonal_t_is_b_scaled_by_d_on_covered_rows(pair, multiplier):
    op = assemble(pair, multiplier)
    D = op.D
    assert scipy.sparse.triu(D, 1).nnz == 0 and scipy.sparse.tril(D, -1).nnz == 0
    d = D.diagonal()
    scale = np.where(op.covered, 1.0 / np.where(op.covered, d, 1.0), 0.0)
    expected = scipy.sparse.diags(scale) @ op.B
    T = op.T
    assert isinstance(T, scipy.sparse.csr_matrix)
    np.testing.assert_allclose(T.toarray(), expected.toarray(), rtol=1e-13, atol=1e-15)
    v = rng().standard_normal(op.shape[1])
    np.testing.assert_allclose(op.transfer(v), T @ v, rtol=1e-13, atol=1e-14)


def test_matrices_are_scipy_csr_with_sorted_indices():
    op = assemble(PAIRS["tri5x3-quad4x4"], "standard")
    for m in (op.B, op.D):
        assert isinstance(m, scipy.sparse.csr_matrix)
        assert m.dtype == np.float64
        assert m.has_sorted_indices
        m.check_format(full_check=True)
    # D is symmetric for standard multipliers.
    assert abs(op.D - op.D.T).max() < 1e-17


@pytest.mark.parametrize("multiplier", MULTIPLIERS)
def test_summary_has_the_rust_fields_and_the_multiplier(multiplier):
    (master, mt, mq), (slave, st, sq) = PAIRS["tri5x3-quad4x4"]
    op = assemble(PAIRS["tri5x3-quad4x4"], multiplier)
    s = op.summary
    assert SUMMARY_KEYS <= set(s)
    assert s["multiplier"] == multiplier == op.multiplier
    assert s["slave_faces"] == len(st) + len(sq)
    assert s["master_faces"] == len(mt) + len(mq)
    assert s["slave_nodes"] == len(slave) and s["master_nodes"] == len(master)
    assert s["intersecting_pairs"] > 0 and s["segments"] >= s["intersecting_pairs"]
    assert s["uncovered_slave_nodes"] == 0
    assert all(isinstance(s[k], int) for k in ("segments", "candidate_pairs", "slave_nodes"))
    assert isinstance(s["covered_area"], float)
    assert multiplier in repr(op) and "covered area 1 of 1" in repr(op)


def test_transfer_shapes_and_input_types():
    op = assemble(PAIRS["tri5x3-quad4x4"], "dual")
    n_slave, n_master = op.shape
    x = np.arange(n_master)  # int64: converted
    assert op.transfer(x).dtype == np.float64
    np.testing.assert_allclose(op.transfer(list(x)), op.transfer(x.astype(float)))
    assert op.transfer(np.ones((n_master, 1))).shape == (n_slave, 1)
    assert op.transfer(np.ones((n_master, 0))).shape == (n_slave, 0)
    # Non-contiguous views are read in logical order.
    v = rng().standard_normal((3, n_master))
    np.testing.assert_array_equal(op.transfer(v.T), op.transfer(np.ascontiguousarray(v.T)))
    np.testing.assert_array_equal(op.transfer(v[1]), op.transfer(v.T)[:, 1])
    assert op.transfer_conservative(np.ones(n_slave, dtype=np.float32)).shape == (n_master,)


def test_points_off_the_surface_get_empty_rows_and_columns():
    (mp, mt, _), (sp, _, sq) = PAIRS["tri5x3-quad4x4"]
    far = np.array([[5.0, 5.0, 5.0]])
    op = seam.assemble((np.vstack([mp, far]), mt), (np.vstack([sp, far]), sq), multiplier="dual")
    n_slave, n_master = op.shape
    assert (n_slave, n_master) == (len(sp) + 1, len(mp) + 1)
    assert op.B[-1].nnz == 0 and op.B[:, -1].nnz == 0 and op.D[-1].nnz == 0
    assert not op.on_surface[-1] and op.on_surface[:-1].all()
    assert op.coverage[-1] == 0.0 and not op.covered[-1]
    assert op.uncovered_nodes.size == 0  # only points on the surface count
    assert op.transfer(np.ones(n_master))[-1] == 0.0


def test_facing_and_max_gap_reach_the_assembly():
    points, tris, _ = grid(4, 4, "triangles")
    _, _, quads = grid(3, 3, "quads")
    lifted = grid(3, 3, "quads", z=0.05)[0]
    # Both sides have normals +z: "opposite" pairs nothing, "any" pairs everything.
    with pytest.raises(seam.NoOverlapError, match="rejected by the normal angle"):
        seam.assemble((points, tris), (lifted, quads), facing="opposite")
    flipped = quads[:, ::-1]
    op = seam.assemble((points, tris), (lifted, flipped), facing="opposite")
    assert op.summary["covered_area"] == pytest.approx(1.0)
    # The slave lies 0.05 above the master.
    with pytest.raises(seam.NoOverlapError, match="by the gap limit"):
        seam.assemble((points, tris), (lifted, quads), max_gap=0.01)
    op = seam.assemble((points, tris), (lifted, quads), max_gap=0.1)
    assert op.summary["max_gap"] == pytest.approx(0.05) or op.summary["max_overlap"] == pytest.approx(0.05)
    op = seam.assemble((points, tris), (lifted, quads), max_angle=10.0, warped_quad_degree=4)
    assert op.summary["covered_area"] == pytest.approx(1.0)
