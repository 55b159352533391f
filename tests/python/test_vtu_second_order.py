"""Second-order cells in seam's VTU output, checked by VTK.

    pip install vtk meshio numpy pytest
    python3 -m pytest tests/python/test_vtu_second_order.py -q

The Rust test `write_second_order_cells_for_python` (crates/seam-io/tests/vtu.rs)
writes one cell of each second-order type (Tet10, Hex20, Hex27, Prism15,
Prism18, Pyramid13, Pyramid14) built from Gmsh's reference nodes (Gmsh's node
order), mapped by a positive affine map (second_order_affine.vtu) and, before
that, bent by a volume-keeping quadratic shear (second_order_curved.vtu), with
the exact volume of each cell as the cell field "volume". seam converts Gmsh's
node order to VTK's on writing; VTK must then see the same cells:

- vtkCellSizeFilter (which splits a quadratic cell into linear ones through its
  nodes) gives the exact volume of every straight-sided cell;
- integrating det J of VTK's own interpolation (vtkCell.InterpolateDerivs, on
  VTK's parametric domain of the cell) gives the exact volume of every cell,
  straight or curved, with det J > 0 at every quadrature point: the nodes are
  where VTK expects them, not merely a permutation of them.

A Pyramid14 is written as VTK's 13-node pyramid (VTK has no 14-node one).
(meshio 5.3 cannot read these files: it lacks the dimension of "wedge15".)
"""

import numpy as np
import pytest

from test_vtu_meshio import run_rust_test

vtk = pytest.importorskip("vtk")
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

FILES = ["second_order_affine.vtu", "second_order_curved.vtu"]
# Gmsh type -> (VTK type, nodes VTK lists)
TYPES = {11: (24, 10), 17: (25, 20), 12: (29, 27), 18: (26, 15), 13: (32, 18), 19: (27, 13), 14: (27, 13)}
# VTK type -> parametric domain of its interpolation: the unit simplex, the
# unit triangle × [0, 1], or the unit cube (VTK's quadratic pyramid is a
# hexahedron collapsed onto its apex, with parameters in the cube).
DOMAINS = {24: "tetra", 25: "cube", 29: "cube", 26: "wedge", 32: "wedge", 27: "cube"}


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    out = tmp_path_factory.mktemp("seam_vtu_second_order")
    run_rust_test("write_second_order_cells_for_python", SEAM_VTU_OUT=str(out))
    return out


def read_grid(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def cell_field(grid, name):
    return vtk_to_numpy(grid.GetCellData().GetArray(name))


def quadrature(domain, order=8):
    """Points and weights of a Gauss rule on a parametric domain (collapsed
    Gauss-Legendre for the simplex and the triangle)."""
    g, w = np.polynomial.legendre.leggauss(order)
    g, w = (g + 1) / 2, w / 2
    for a, wa in zip(g, w):
        for b, wb in zip(g, w):
            for c, wc in zip(g, w):
                if domain == "cube":
                    yield (a, b, c), wa * wb * wc
                elif domain == "wedge":
                    yield (a, b * (1 - a), c), wa * wb * wc * (1 - a)
                else:
                    yield (a, b * (1 - a), c * (1 - a) * (1 - b)), wa * wb * wc * (1 - a) ** 2 * (1 - b)


def integrate_volume(cell):
    """∫ det J over the cell's parametric domain, with VTK's interpolation, and
    the smallest det J at the quadrature points."""
    n = cell.GetNumberOfPoints()
    x = np.array([cell.GetPoints().GetPoint(i) for i in range(n)])
    derivs = [0.0] * (3 * n)
    volume, smallest = 0.0, np.inf
    for p, weight in quadrature(DOMAINS[cell.GetCellType()]):
        cell.InterpolateDerivs(p, derivs)
        det = np.linalg.det(np.reshape(derivs, (3, n)) @ x)
        volume += weight * det
        smallest = min(smallest, det)
    return volume, smallest


@pytest.mark.parametrize("name", FILES)
def test_vtk_reads_the_cell_types(written, name):
    grid = read_grid(written / name)
    gmsh_types = cell_field(grid, "gmsh_type").astype(int)
    assert sorted(gmsh_types) == sorted(TYPES)
    for i, t in enumerate(gmsh_types):
        assert (grid.GetCellType(i), grid.GetCell(i).GetNumberOfPoints()) == TYPES[t], (i, t)


def test_vtk_cell_size_filter_gives_the_exact_volume_of_straight_cells(written):
    grid = read_grid(written / "second_order_affine.vtu")
    sizes = vtk.vtkCellSizeFilter()
    sizes.SetInputData(grid)
    sizes.Update()
    volumes = vtk_to_numpy(sizes.GetOutput().GetCellData().GetArray("Volume"))
    np.testing.assert_allclose(volumes, cell_field(grid, "volume"), rtol=1e-12, atol=0)


@pytest.mark.parametrize("name", FILES)
def test_vtk_interpolation_gives_the_exact_volume_with_positive_jacobian(written, name):
    grid = read_grid(written / name)
    exact = cell_field(grid, "volume")
    gmsh_types = cell_field(grid, "gmsh_type").astype(int)
    for i in range(grid.GetNumberOfCells()):
        volume, smallest = integrate_volume(grid.GetCell(i))
        assert smallest > 0, (name, gmsh_types[i], smallest)
        assert volume == pytest.approx(exact[i], rel=1e-12), (name, gmsh_types[i])


def test_curved_cells_are_curved(written):
    """The curved file is not the straight one: the bent cells move mid-edge
    nodes off the straight edges (so the volume test above sees curvature)."""
    straight = vtk_to_numpy(read_grid(written / "second_order_affine.vtu").GetPoints().GetData())
    curved = vtk_to_numpy(read_grid(written / "second_order_curved.vtu").GetPoints().GetData())
    assert straight.shape == curved.shape
    assert np.abs(straight - curved).max() > 0.1


def face_area(cell):
    """∫ |x_r × x_s| over the face's parametric domain (the unit triangle or
    square), with VTK's interpolation."""
    n = cell.GetNumberOfPoints()
    x = np.array([cell.GetPoints().GetPoint(i) for i in range(n)])
    derivs = [0.0] * (2 * n)
    g, w = np.polynomial.legendre.leggauss(8)
    g, w = (g + 1) / 2, w / 2
    area = 0.0
    for a, wa in zip(g, w):
        for b, wb in zip(g, w):
            if cell.GetCellType() == 22:  # the triangle, collapsed
                p, weight = (a, b * (1 - a), 0.0), wa * wb * (1 - a)
            else:
                p, weight = (a, b, 0.0), wa * wb
            cell.InterpolateDerivs(p, derivs)
            jacobian = np.reshape(derivs, (2, n)) @ x
            area += weight * np.linalg.norm(np.cross(jacobian[0], jacobian[1]))
    return area


def test_vtk_sees_flat_second_order_faces_with_their_exact_areas(written):
    """The faces of the straight-sided cells are flat: VTK's interpolation gives
    each the area of the polygon of its corners, which a misplaced mid-edge or
    centre node would fold and enlarge."""
    grid = read_grid(written / "second_order_faces.vtu")
    kinds = {grid.GetCellType(i) for i in range(grid.GetNumberOfCells())}
    assert kinds == {22, 23, 28}
    for i in range(grid.GetNumberOfCells()):
        cell = grid.GetCell(i)
        corners = np.array([cell.GetPoints().GetPoint(k) for k in range(3 if cell.GetCellType() == 22 else 4)])
        polygon = 0.5 * np.linalg.norm(sum(np.cross(corners[k], corners[(k + 1) % len(corners)]) for k in range(len(corners))))
        assert face_area(cell) == pytest.approx(polygon, rel=1e-12), (i, cell.GetCellType())


def test_seam_reads_the_second_order_faces_vtk_writes(written, tmp_path):
    """VTK's reader and writer (ASCII, appended raw, zlib-compressed binary)
    keep the faces; seam reads them all back as the faces it wrote."""
    grid = read_grid(written / "second_order_faces.vtu")
    for name, configure in [
        ("ascii.vtu", lambda w: w.SetDataModeToAscii()),
        ("appended.vtu", lambda w: (w.SetDataModeToAppended(), w.EncodeAppendedDataOff())),
        ("zlib.vtu", lambda w: (w.SetDataModeToBinary(), w.SetCompressorTypeToZLib())),
    ]:
        writer = vtk.vtkXMLUnstructuredGridWriter()
        writer.SetInputData(grid)
        writer.SetFileName(str(tmp_path / name))
        configure(writer)
        assert writer.Write() == 1
    run_rust_test("second_order_faces_written_by_vtk_are_read", SEAM_VTU_IN=str(tmp_path))
