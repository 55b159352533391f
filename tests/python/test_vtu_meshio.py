"""VTU interoperability of seam-io with meshio (and with VTK, the reader of ParaView).

    pip install meshio numpy pytest     # optional: vtk
    python3 -m pytest tests/python -q

Both directions go through the Rust test binary of crates/seam-io/tests/vtu.rs,
so nothing here needs the seam CLI:

- seam → meshio/VTK: `write_fixtures_for_python` writes VTU files and
  expected.json (points, cells, fields, with shortest round-trip decimals) into
  SEAM_VTU_OUT; meshio.read (and VTK's reader, if the vtk package is installed)
  must find exactly those cells, points and fields, bit for bit.
- meshio/VTK → seam: the functions of crates/seam-io/tests/data/vtu/make_fixtures.py
  (which made the committed fixtures) write the fixture mesh with the installed
  meshio in several encodings (and with VTK in raw-appended and compressed ones);
  `files_written_by_meshio_and_vtk_are_read` reads every file of SEAM_VTU_IN.
"""

import importlib.util
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

meshio = pytest.importorskip("meshio")

ROOT = Path(__file__).resolve().parents[2]
FIXTURE_DIR = ROOT / "crates" / "seam-io" / "tests" / "data" / "vtu"
SEAM_FILES = ["mixed.vtu", "patch.vtu", "bare.vtu"]
VTK_CELL_TYPES = {"triangle": 5, "quad": 9}


def run_rust_test(name, **env):
    """Runs one test of crates/seam-io/tests/vtu.rs with extra environment variables.

    With the cargo arguments of scripts/test ($SEAM_CARGO_TEST_ARGS, by default
    `--workspace --locked`), so that cargo finds the test binary that run already
    built (with other packages or features it would build seam-io, seam and the
    test a second time)."""
    cargo_args = os.environ.get("SEAM_CARGO_TEST_ARGS", "--workspace --locked").split()
    command = ["cargo", "test", "--quiet", *cargo_args, "--test", "main", f"vtu::{name}", "--", "--exact"]
    done = subprocess.run(
        command, cwd=ROOT, env={**os.environ, **env}, capture_output=True, text=True, timeout=1800
    )
    assert done.returncode == 0, f"{' '.join(command)} failed:\n{done.stdout}\n{done.stderr}"
    assert "1 passed" in done.stdout, f"{name} did not run:\n{done.stdout}"


def load_make_fixtures():
    spec = importlib.util.spec_from_file_location("make_fixtures", FIXTURE_DIR / "make_fixtures.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def seam_output(tmp_path_factory):
    """The directory the Rust test wrote into, and its expected.json."""
    out = tmp_path_factory.mktemp("seam_vtu")
    run_rust_test("write_fixtures_for_python", SEAM_VTU_OUT=str(out))
    expected = json.loads((out / "expected.json").read_text())
    assert sorted(expected) == sorted(SEAM_FILES)
    return out, expected


def field_array(field, n):
    """The (n,) or (n, components) float64 array of a field of expected.json."""
    values = np.array(field["values"], dtype=np.float64)
    k = field["components"]
    return values if k == 1 else values.reshape(n, k)


def assert_bitwise_equal(actual, expected, what):
    actual = np.asarray(actual)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape}, expected {expected.shape}"
    assert actual.dtype == np.float64, f"{what}: dtype {actual.dtype}"
    # Bits, so that -0.0 and subnormal values count too.
    assert np.array_equal(actual.view(np.uint64), expected.view(np.uint64)), f"{what} differs"


@pytest.mark.parametrize("name", SEAM_FILES)
def test_meshio_reads_what_seam_writes(seam_output, name):
    out, expected = seam_output
    want = expected[name]
    mesh = meshio.read(out / name)

    points = np.array(want["points"], dtype=np.float64).reshape(-1, 3)
    assert_bitwise_equal(mesh.points, points, "points")

    cells = [(block.type, [int(n) for n in row]) for block in mesh.cells for row in block.data]
    assert cells == [(kind, nodes) for kind, nodes in want["cells"]]
    kinds = [kind for kind, _ in want["cells"]]
    for kind in ("triangle", "quad"):
        found = sum(len(block.data) for block in mesh.cells if block.type == kind)
        assert found == kinds.count(kind), kind

    assert sorted(mesh.point_data) == sorted(want["point_data"])
    for field_name, field in want["point_data"].items():
        wanted = field_array(field, len(points))
        assert_bitwise_equal(mesh.point_data[field_name], wanted, f"point field {field_name}")

    assert sorted(mesh.cell_data) == sorted(want["cell_data"])
    for field_name, field in want["cell_data"].items():
        # meshio splits cell data by cell block; the blocks follow file order.
        found = np.concatenate(mesh.cell_data[field_name])
        assert_bitwise_equal(found, field_array(field, len(cells)), f"cell field {field_name}")


@pytest.mark.parametrize("name", SEAM_FILES)
def test_vtk_reads_what_seam_writes(seam_output, name):
    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    out, expected = seam_output
    want = expected[name]
    problems = []
    reader = vtk.vtkXMLUnstructuredGridReader()
    for event in ("ErrorEvent", "WarningEvent"):
        reader.AddObserver(event, lambda obj, ev: problems.append(ev))
    reader.SetFileName(str(out / name))
    reader.Update()
    assert not problems, problems
    grid = reader.GetOutput()

    points = np.array(want["points"], dtype=np.float64).reshape(-1, 3)
    assert_bitwise_equal(vtk_to_numpy(grid.GetPoints().GetData()), points, "points")
    assert grid.GetNumberOfCells() == len(want["cells"])
    for i, (kind, nodes) in enumerate(want["cells"]):
        cell = grid.GetCell(i)
        assert cell.GetCellType() == VTK_CELL_TYPES[kind]
        assert [cell.GetPointId(j) for j in range(cell.GetNumberOfPoints())] == nodes

    for data, fields, n in (
        (grid.GetPointData(), want["point_data"], len(points)),
        (grid.GetCellData(), want["cell_data"], len(want["cells"])),
    ):
        names = sorted(data.GetArrayName(i) for i in range(data.GetNumberOfArrays()))
        assert names == sorted(fields)
        for field_name, field in fields.items():
            array = data.GetArray(field_name)
            assert array.GetNumberOfComponents() == field["components"]
            assert_bitwise_equal(vtk_to_numpy(array), field_array(field, n), field_name)
    # The first scalar and first vector field are the active ones.
    if name == "mixed.vtu":
        assert grid.GetPointData().GetScalars().GetName() == "p"
        assert grid.GetPointData().GetVectors().GetName() == "u"


def test_seam_reads_what_meshio_and_vtk_write(tmp_path):
    make_fixtures = load_make_fixtures()
    make_fixtures.main(tmp_path)  # meshio_ascii, meshio_binary (zlib), vtk_* if vtk is installed
    mesh = make_fixtures.meshio_mesh()
    meshio.write(tmp_path / "meshio_binary_uncompressed.vtu", mesh, binary=True, compression=None)
    meshio.write(tmp_path / "meshio_binary_lzma.vtu", mesh, binary=True, compression="lzma")
    meshio.write(tmp_path / "meshio_binary_uint64.vtu", mesh, binary=True, header_type="UInt64")
    assert len(list(tmp_path.glob("*.vtu"))) >= 5
    run_rust_test("files_written_by_meshio_and_vtk_are_read", SEAM_VTU_IN=str(tmp_path))


def test_meshio_reads_the_committed_fixtures_as_described():
    """The committed fixtures hold what make_fixtures.py says (guards against stale files)."""
    make_fixtures = load_make_fixtures()
    for path in sorted(FIXTURE_DIR.glob("*.vtu")):
        if "lz4" in path.name:
            continue  # meshio reads no LZ4-compressed data
        mesh = meshio.read(path)
        assert np.array_equal(mesh.points, make_fixtures.POINTS), path.name
        cells = [(block.type, [int(n) for n in row]) for block in mesh.cells for row in block.data]
        assert cells == [(kind, nodes) for kind, _, nodes in make_fixtures.CELLS], path.name
        for field_name, values in make_fixtures.POINT_DATA.items():
            assert np.array_equal(mesh.point_data[field_name], values), (path.name, field_name)
        for field_name, values in make_fixtures.CELL_DATA.items():
            assert np.array_equal(np.concatenate(mesh.cell_data[field_name]), values), (path.name, field_name)


def test_volume_cells_read_by_meshio_and_vtk(tmp_path):
    """The volume writer: cell types and fields as meshio reads them, and positive
    volumes in VTK (so Gmsh's node orders are VTK's for every cell type)."""
    run_rust_test("write_volume_fixture_for_python", SEAM_VTU_OUT=str(tmp_path))
    m = meshio.read(tmp_path / "volume.vtu")
    assert [c.type for c in m.cells] == ["tetra", "hexahedron", "wedge", "pyramid"]
    assert np.array_equal(m.point_data["z"], m.points[:, 2])
    assert np.array_equal(np.concatenate([d.reshape(-1) for d in m.cell_data["cell_id"]]), [0, 1, 2, 3])
    vtk = pytest.importorskip("vtk")
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(tmp_path / "volume.vtu"))
    reader.Update()
    quality = vtk.vtkMeshQuality()
    quality.SetInputData(reader.GetOutput())
    quality.SetTetQualityMeasureToVolume()
    quality.SetHexQualityMeasureToVolume()
    quality.SetWedgeQualityMeasureToVolume()
    quality.SetPyramidQualityMeasureToVolume()
    quality.Update()
    q = quality.GetOutput().GetCellData().GetArray("Quality")
    volumes = [q.GetValue(i) for i in range(q.GetNumberOfTuples())]
    assert np.allclose(volumes, [1 / 6, 1.0, 0.5, 1 / 3])
