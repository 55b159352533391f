"""Writes the VTU fixtures that `crates/seam-io/tests/vtu.rs` reads.

    python3 make_fixtures.py [OUT_DIR]      # default: this directory

All files hold the same small mesh (`MESH` below; the Rust test hard-codes it
as `fixture_mesh`): 7 points, cells tri, quad, vertex, line, tri, point fields
p (scalar), u (3-vector), id (Int32) and cell fields c (scalar), g (2 components).
Values are exact in meshio's 12-digit ASCII format.

- meshio_ascii.vtu, meshio_binary.vtu: meshio 5.3 (`binary=False`, and
  `binary=True` with its default zlib compression, UInt32 headers, version 0.1).
- vtk_appended_raw_zlib.vtu, vtk_binary_lz4.vtu: VTK's vtkXMLUnstructuredGridWriter
  (the writer of ParaView; appended raw data is ParaView's default) with UInt64
  headers and 8-byte compression blocks, so that every Float64 and Int64 array
  fills its last block exactly (VTK then writes 0 as the partial block size,
  which a reader must take as a full block). Written only if the `vtk`
  package is installed.

tests/python/test_vtu_meshio.py imports this file and writes the same files into
a temporary directory.
"""

import sys
from pathlib import Path

import numpy as np

POINTS = np.array(
    [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.5],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.25],
        [2.0, 1.0, -0.5],
        [3.0, 3.0, 3.0],
    ]
)
# (meshio cell type, VTK cell type, nodes), in file order.
CELLS = [
    ("triangle", 5, [0, 1, 4]),
    ("quad", 9, [1, 2, 5, 4]),
    ("vertex", 1, [6]),
    ("line", 3, [3, 6]),
    ("triangle", 5, [0, 4, 3]),
]
N = len(POINTS)
POINT_DATA = {
    "p": 0.5 * np.arange(N),
    "u": np.array([[i, -i, 0.25 * i] for i in range(N)], dtype=float),
    "id": np.arange(10, 10 + N, dtype=np.int32),
}
CELL_DATA = {
    "c": np.array([1.5, 2.5, -1.0, -2.0, 4.25]),
    "g": np.array([[i, 2 * i] for i in range(len(CELLS))], dtype=float),
}


def meshio_mesh():
    """The mesh as a meshio.Mesh: one cell block per cell, in file order."""
    import meshio

    cells = [(kind, np.array([nodes])) for kind, _, nodes in CELLS]
    cell_data = {name: [values[i : i + 1] for i in range(len(CELLS))] for name, values in CELL_DATA.items()}
    return meshio.Mesh(POINTS, cells, point_data=POINT_DATA, cell_data=cell_data)


def write_meshio(out_dir):
    import meshio

    mesh = meshio_mesh()
    meshio.write(Path(out_dir) / "meshio_ascii.vtu", mesh, binary=False)
    meshio.write(Path(out_dir) / "meshio_binary.vtu", mesh, binary=True)


def write_vtk(out_dir):
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk

    grid = vtk.vtkUnstructuredGrid()
    points = vtk.vtkPoints()
    points.SetDataTypeToDouble()
    for p in POINTS:
        points.InsertNextPoint(*p)
    grid.SetPoints(points)
    for _, vtk_type, nodes in CELLS:
        grid.InsertNextCell(vtk_type, len(nodes), nodes)
    for data, arrays in ((grid.GetPointData(), POINT_DATA), (grid.GetCellData(), CELL_DATA)):
        for name, values in arrays.items():
            array = numpy_to_vtk(values, deep=1)
            array.SetName(name)
            data.AddArray(array)
    for name, mode, compressor in (
        ("vtk_appended_raw_zlib.vtu", "appended", "zlib"),
        ("vtk_binary_lz4.vtu", "binary", "lz4"),
    ):
        writer = vtk.vtkXMLUnstructuredGridWriter()
        writer.SetInputData(grid)
        writer.SetFileName(str(Path(out_dir) / name))
        writer.SetHeaderTypeToUInt64()
        writer.SetBlockSize(8)
        if mode == "appended":
            writer.SetDataModeToAppended()
            writer.EncodeAppendedDataOff()
        else:
            writer.SetDataModeToBinary()
        {"zlib": writer.SetCompressorTypeToZLib, "lz4": writer.SetCompressorTypeToLZ4}[compressor]()
        if writer.Write() != 1:
            raise RuntimeError(f"VTK failed to write {name}")


def main(out_dir):
    write_meshio(out_dir)
    try:
        import vtk  # noqa: F401
    except ImportError:
        print("vtk is not installed: no vtk_*.vtu fixtures", file=sys.stderr)
        return
    write_vtk(out_dir)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).parent)
