"""Structured hexahedral and tetrahedral blocks written as Gmsh MSH 2.2 files
here (not by seam), with named physical surfaces: the meshes of the patch
tests of seam.solve (test_solve_patch.py)."""

from __future__ import annotations

import itertools

import numpy as np

# Side name: (axis, 0 for the low end or 1 for the high end).
SIDES = {
    "xmin": (0, 0),
    "xmax": (0, 1),
    "ymin": (1, 0),
    "ymax": (1, 1),
    "bottom": (2, 0),
    "top": (2, 1),
}


def block(n, kind, mapping):
    """An n[0] × n[1] × n[2] block of "hex" or "tet" cells (six Kuhn tets per
    grid cell) on the unit cube mapped by ``mapping(u, v, w) -> (x, y, z)``
    (arrays in, arrays out).

    Returns (points (p, 3), cells (c, 8 or 4), grid index (p, 3) of each point).
    """
    nx, ny, nz = n
    k, j, i = np.meshgrid(np.arange(nz + 1), np.arange(ny + 1), np.arange(nx + 1), indexing="ij")
    ijk = np.column_stack([i.ravel(), j.ravel(), k.ravel()])
    u, v, w = (ijk / np.array(n, dtype=float)).T
    points = np.column_stack(mapping(u, v, w)).astype(float)

    def node(a, b, c):
        return a + (nx + 1) * (b + (ny + 1) * c)

    cells = []
    for c, b, a in itertools.product(range(nz), range(ny), range(nx)):
        corner = lambda d: node(a + d[0], b + d[1], c + d[2])  # noqa: E731
        if kind == "hex":
            cells.append([corner(d) for d in ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                                              (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))])
            continue
        for axes in itertools.permutations(range(3)):
            d = [0, 0, 0]
            path = [corner(d)]
            for axis in axes:
                d[axis] = 1
                path.append(corner(d))
            tet = path
            x = points[tet]
            if np.linalg.det(x[1:] - x[0]) < 0:
                tet = [tet[0], tet[2], tet[1], tet[3]]
            cells.append(tet)
    return points, np.array(cells, dtype=np.int64), ijk


def boundary_faces(points, cells, ijk, n, side, keep=None):
    """The faces of the cells on ``side`` (a key of SIDES), oriented outward;
    ``keep(centroid)`` selects some of them."""
    axis, end = SIDES[side]
    on = ijk[:, axis] == end * n[axis]
    local = ([[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
             if cells.shape[1] == 8 else [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    faces = []
    for cell in cells:
        centre = points[cell].mean(axis=0)
        for f in local:
            face = cell[f]
            if not on[face].all():
                continue
            c = points[face].mean(axis=0)
            if keep is not None and not keep(c):
                continue
            normal = np.cross(points[face[1]] - points[face[0]], points[face[2]] - points[face[0]])
            if normal @ (c - centre) < 0:
                face = face[::-1]
            faces.append(list(face))
    return faces


def write_msh(path, points, cells, surfaces):
    """Writes a Gmsh MSH 2.2 ASCII file: the cells in the physical volume
    "body", each surface ({name: faces}) a physical surface of that name."""
    elements = []  # (gmsh type, physical tag, 1-based nodes)
    names = list(surfaces)
    for tag, name in enumerate(names, start=1):
        for f in surfaces[name]:
            elements.append((2 if len(f) == 3 else 3, tag, [p + 1 for p in f]))
    volume = len(names) + 1
    for c in cells:
        elements.append((5 if len(c) == 8 else 4, volume, [p + 1 for p in c]))
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names) + 1)]
    lines += [f'2 {tag} "{name}"' for tag, name in enumerate(names, start=1)]
    lines += [f'3 {volume} "body"', "$EndPhysicalNames", "$Nodes", str(len(points))]
    lines += [f"{p + 1} {x!r} {y!r} {z!r}" for p, (x, y, z) in enumerate(points.tolist())]
    lines += ["$EndNodes", "$Elements", str(len(elements))]
    lines += [f"{e} {kind} 2 {tag} {tag} " + " ".join(map(str, nodes))
              for e, (kind, tag, nodes) in enumerate(elements, start=1)]
    lines += ["$EndElements"]
    path.write_text("\n".join(lines) + "\n")


def write_block(path, n, kind, mapping, split=None):
    """A block (see ``block``) with its six sides as physical surfaces named as
    in SIDES, written to ``path``; ``split`` ({name: (side, keep)}) replaces
    a side by parts of it. Returns the points."""
    points, cells, ijk = block(n, kind, mapping)
    surfaces = {}
    split = split or {}
    replaced = {side for side, _ in split.values()}
    for side in SIDES:
        if side not in replaced:
            surfaces[side] = boundary_faces(points, cells, ijk, n, side)
    for name, (side, keep) in split.items():
        surfaces[name] = boundary_faces(points, cells, ijk, n, side, keep)
    write_msh(path, points, cells, surfaces)
    return points
