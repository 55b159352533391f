"""Boxes meshed by the gmsh Python module and written as MSH 4.1, with named
physical groups: the meshes of test_solve_gmsh.py and test_glue_patch_gmsh.py.

Needs the ``gmsh`` wheel (scripts/test installs it) and, headless, the X11
and OpenGL runtime libraries it links to (.ci/run installs them).
"""

import gmsh
import numpy as np

EPS = 1e-6


def add_geo_box(box):
    """The box (x0, y0, z0, dx, dy, dz) in Gmsh's built-in kernel, as a user
    writes it in a .geo file: 8 points, 12 lines, 6 plane surfaces, a
    volume. Returns the volume's tag."""
    x0, y0, z0, dx, dy, dz = box
    geo = gmsh.model.geo
    points = {c: geo.addPoint(x0 + c[0] * dx, y0 + c[1] * dy, z0 + c[2] * dz) for c in np.ndindex(2, 2, 2)}
    lines = {}

    def line(a, b):
        if (a, b) not in lines:
            lines[a, b] = geo.addLine(points[a], points[b])
            lines[b, a] = -lines[a, b]
        return lines[a, b]

    # Each side's loop in the plane of the axes a + 1, a + 2 (mod 3) (a its
    # normal axis) through corners (u, v) = (0, 1), (0, 0), (1, 0), (1, 1) as
    # OpenCASCADE's box, the top's through (0, 0), (1, 0), (1, 1), (0, 1):
    # found by trial, these make the triangles of a structured tetrahedral
    # mesh's sides faces of its tetrahedra (OpenCASCADE's loop on the top
    # leaves every top triangle across the diagonal of its tetrahedra).
    surfaces = []
    for axis in range(3):
        for end in (0, 1):
            corners = []
            for du, dv in ((0, 1), (0, 0), (1, 0), (1, 1)):
                c = [0, 0, 0]
                c[axis], c[(axis + 1) % 3], c[(axis + 2) % 3] = end, du, dv
                corners.append(tuple(c))
            if axis == 2 and end == 1:
                corners = corners[1:] + corners[:1]
            loop = geo.addCurveLoop([line(corners[k], corners[(k + 1) % 4]) for k in range(4)])
            surfaces.append(geo.addPlaneSurface([loop]))
    volume = geo.addVolume([geo.addSurfaceLoop(surfaces)])
    geo.synchronize()
    return volume


def mesh_box(path, box, size, order, *, cells=None, recombine=True, incomplete=False, kernel="occ", smoothing=1):
    """One box (x0, y0, z0, dx, dy, dz) meshed by Gmsh with the physical
    surfaces bottom, top, xmin, ymin, xmax, ymax and the physical volume
    "body", written as MSH 4.1.

    Unstructured tetrahedra of mesh size ``size``; or, with ``cells`` =
    (nx, ny, nz), a structured (transfinite) mesh of nx × ny × nz hexahedra
    (``recombine``) or of 6 tetrahedra per cell. ``order`` 1, or 2: Tet10
    (Tri6 faces), Hex27 (Quad9), or Hex20 (Quad8) if ``incomplete``.
    ``kernel``: "occ" (OpenCASCADE's box) or "geo" (``add_geo_box``; Gmsh
    places the nodes of its lines a few 1e-12 off the exact grid there).
    ``smoothing``: Gmsh's Mesh.Smoothing, its smoothing steps (1, Gmsh's
    default; above 1 the nodes of a structured surface move too, by ~1e-12,
    so that its grid lines are no longer straight).
    """
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add(path.stem)
        x0, y0, z0, dx, dy, dz = box
        if kernel == "geo":
            volume = add_geo_box(box)
        else:
            volume = gmsh.model.occ.addBox(x0, y0, z0, dx, dy, dz)
            gmsh.model.occ.synchronize()
        lo, hi = np.array([x0, y0, z0]), np.array([x0 + dx, y0 + dy, z0 + dz])
        for name, axis, at in (("xmin", 0, lo), ("xmax", 0, hi), ("ymin", 1, lo), ("ymax", 1, hi),
                               ("bottom", 2, lo), ("top", 2, hi)):
            a, b = lo - EPS, hi + EPS
            a[axis], b[axis] = at[axis] - EPS, at[axis] + EPS
            (surface,) = gmsh.model.getEntitiesInBoundingBox(*a, *b, dim=2)
            gmsh.model.addPhysicalGroup(2, [surface[1]], name=name)
        gmsh.model.addPhysicalGroup(3, [volume], name="body")
        if cells is None:
            gmsh.option.setNumber("Mesh.MeshSizeMin", size)
            gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        else:
            for _, curve in gmsh.model.getEntities(1):
                bounds = np.array(gmsh.model.getBoundingBox(1, curve))
                axis = int(np.argmax(bounds[3:] - bounds[:3]))
                gmsh.model.mesh.setTransfiniteCurve(curve, cells[axis] + 1)
            for _, surface in gmsh.model.getEntities(2):
                gmsh.model.mesh.setTransfiniteSurface(surface)
                if recombine:
                    gmsh.model.mesh.setRecombine(2, surface)
            gmsh.model.mesh.setTransfiniteVolume(volume)
        gmsh.option.setNumber("Mesh.Smoothing", smoothing)
        gmsh.model.mesh.generate(3)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", int(incomplete))
        gmsh.model.mesh.setOrder(order)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


# The faces of meshio's tetra and hexahedron cells (Gmsh's corner order), by corner.
CELL_FACES = {
    "tetra": [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)],
    "hexahedron": [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)],
}


def faces_not_of_cells(path):
    """The number of the file's 2-D elements whose corners are not those of
    the face of exactly one cell (a boundary face)."""
    import meshio

    m = meshio.read(path)
    cell_faces = [np.sort(block.data[:, f], axis=1) for block in m.cells
                  for f in CELL_FACES.get(block.type.rstrip("0123456789"), [])]
    bad = 0
    for k, kind in ((3, "triangle"), (4, "quad")):
        faces = [np.sort(block.data[:, :k], axis=1) for block in m.cells if block.type.startswith(kind)]
        if faces:
            known, count = np.unique(np.vstack([f for f in cell_faces if f.shape[1] == k]), axis=0, return_counts=True)
            boundary = {tuple(f) for f in known[count == 1].tolist()}
            bad += sum(tuple(f) not in boundary for f in np.vstack(faces).tolist())
    return bad
