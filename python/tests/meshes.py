"""Small meshes built in NumPy for the tests (structured grids on rectangles)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

# crates/seam-io/tests/data, the Gmsh fixtures of seam-io.
MSH_DATA = Path(__file__).resolve().parents[2] / "crates" / "seam-io" / "tests" / "data"

SEED_JITTER = 20240611
SEED_VALUES = 7


def grid(nx, ny, kind="quads", box=(0.0, 1.0, 0.0, 1.0), z=0.0, jitter=0.0, seed=SEED_JITTER):
    """A structured nx × ny grid on ``box`` = (x0, x1, y0, y1) at height z.

    kind: "quads"; "triangles" (each cell cut along alternating diagonals);
    "mixed" (left half quads, right half triangles). ``jitter`` moves interior
    points by up to that fraction of the cell size in x and y (boundary points
    stay, so the domain is exactly the box; 0.12 keeps every face positive).

    Returns (points (n, 3) float64, triangles (m3, 3) int64, quads (m4, 4) int64).
    """
    x0, x1, y0, y1 = box
    xs, ys = np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1)
    X, Y = np.meshgrid(xs, ys)  # (ny + 1, nx + 1), row j is y = ys[j]
    points = np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, float(z))])
    if jitter:
        rng = np.random.default_rng(seed)
        hx, hy = (x1 - x0) / nx, (y1 - y0) / ny
        interior = (X > x0) & (X < x1) & (Y > y0) & (Y < y1)
        interior = interior.ravel()
        shift = rng.uniform(-jitter, jitter, size=(interior.sum(), 2)) * [hx, hy]
        points[interior, :2] += shift

    def node(i, j):
        return j * (nx + 1) + i

    triangles, quads = [], []
    for j in range(ny):
        for i in range(nx):
            a, b, c, d = node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)
            as_quad = kind == "quads" or (kind == "mixed" and i < nx // 2)
            if as_quad:
                quads.append([a, b, c, d])
            elif (i + j) % 2 == 0:
                triangles += [[a, b, c], [a, c, d]]
            else:
                triangles += [[a, b, d], [b, c, d]]
    return (
        points,
        np.array(triangles, dtype=np.int64).reshape(-1, 3),
        np.array(quads, dtype=np.int64).reshape(-1, 4),
    )


def as_input(points, triangles, quads):
    """The (points, faces) tuple seam.assemble takes: a single array when the
    mesh has one face type, else the list [triangles, quads]."""
    if len(quads) == 0:
        return points, triangles
    if len(triangles) == 0:
        return points, quads
    return points, [triangles, quads]


def linear_fields(points):
    """Three linear fields (columns) of the points: x, y and 1 + 2x - 3y."""
    x, y = points[:, 0], points[:, 1]
    return np.column_stack([x, y, 1.0 + 2.0 * x - 3.0 * y])
