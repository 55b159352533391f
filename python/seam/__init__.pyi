"""Mortar coupling operators between non-matching surface meshes (type stubs).

The full docstrings are those of the compiled module: ``help(seam.assemble)``.
"""

import os
from typing import List, Literal, Optional, Sequence, Tuple, TypedDict, Union, final

import numpy as np
import numpy.typing as npt
import scipy.sparse

__all__ = [
    "CaseError",
    "ConvergenceError",
    "FactorizationError",
    "InvalidOptionError",
    "Mesh",
    "MeshError",
    "Mortar",
    "MortarError",
    "MshError",
    "NoCouplingError",
    "NoOverlapError",
    "OutputWarning",
    "Solution",
    "SolveError",
    "__version__",
    "assemble",
    "catalogue",
    "check",
    "read_mesh",
    "solve",
]

__version__: str

_Faces = Union[npt.ArrayLike, Sequence[npt.ArrayLike]]
"""An (m, k) integer array, k = 3, 4, 6, 8 or 9, or a list of such arrays and single faces."""

_MeshLike = Union["Mesh", Tuple[npt.ArrayLike, _Faces]]
"""A Mesh, or a ``(points, faces)`` tuple."""

class MeshError(ValueError):
    """The points and faces do not form a valid surface mesh."""

class MshError(ValueError):
    """A Gmsh MSH file could not be interpreted (the message gives file and line)."""

class MortarError(ValueError):
    """The mortar assembly produced no operator."""

class InvalidOptionError(MortarError):
    """An option of ``assemble`` is out of range."""

class NoOverlapError(MortarError):
    """No master face meets a slave face within the gap and angle limits."""

class FactorizationError(MortarError):
    """D restricted to the covered slave nodes is not positive definite."""

class OutputWarning(UserWarning):
    """A notice about an output directory: ``Solution.write`` waits for another
    run writing into it, or recovered what an interrupted run left there."""

@final
class Mesh:
    """A surface mesh of linear triangles and bilinear quads and their
    second-order versions Tri6, Quad8 and Quad9 (possibly mixed).

    Args:
        points: Array-like of shape (n, 3), real numbers.
        faces: Integer array of shape (m, k) of 0-based point indices, k = 3
            (triangles), 4 (quads), 6 (Tri6), 7 (Tri7), 8 (Quad8) or 9
            (Quad9), nodes in Gmsh order (corners, mid-edge nodes of edges
            0-1, 1-2, ..., the Quad9 or Tri7 centre); or a list of such arrays
            and/or single faces, numbered in list order.

    Raises:
        ValueError: A wrong shape (also a face width other than 3, 4, 6, 7, 8, 9).
        TypeError: Points that are not real numbers, faces that are not integers.
        MeshError: Non-finite coordinate, index out of range or negative,
            repeated corner, zero-area face, no faces.
    """

    def __new__(cls, points: npt.ArrayLike, faces: _Faces) -> "Mesh": ...
    @property
    def points(self) -> npt.NDArray[np.float64]:
        """Point coordinates, shape (n_points, 3) (a copy)."""
    @property
    def triangles(self) -> npt.NDArray[np.int64]:
        """Triangles in face order, shape (n_triangles, 3), 0-based."""
    @property
    def quads(self) -> npt.NDArray[np.int64]:
        """Quadrilaterals in face order, shape (n_quads, 4), 0-based."""
    @property
    def tri6(self) -> npt.NDArray[np.int64]:
        """6-node triangles in face order, shape (n, 6): corners, mid-edge nodes."""
    @property
    def quad8(self) -> npt.NDArray[np.int64]:
        """8-node quadrilaterals in face order, shape (n, 8): corners, mid-edge nodes."""
    @property
    def quad9(self) -> npt.NDArray[np.int64]:
        """9-node quadrilaterals in face order, shape (n, 9): corners, mid-edge nodes, centre."""
    @property
    def n_points(self) -> int:
        """Number of points, including points no face uses."""
    @property
    def n_faces(self) -> int:
        """Number of faces."""

class _Summary(TypedDict):
    """``Mortar.summary``: the Rust MortarSummary fields plus ``multiplier``."""

    slave_nodes: int
    master_nodes: int
    slave_faces: int
    master_faces: int
    candidate_pairs: int
    intersecting_pairs: int
    segments: int
    slave_area: float
    covered_area: float
    uncovered_slave_nodes: int
    max_gap: float
    max_overlap: float
    inverse_failures: int
    dual_fallbacks: int
    multiplier: Literal["standard", "dual", "lumped"]

@final
class Mortar:
    """The assembled mortar operator: B, D and the transfer T = D⁻¹B.

    Rows of B and D are slave points, columns of B master points; the transfer
    acts on the covered slave points (uncovered ones receive 0).
    """

    @property
    def B(self) -> scipy.sparse.csr_matrix:
        """B, shape (n_slave_points, n_master_points); a new matrix at each access."""
    @property
    def D(self) -> scipy.sparse.csr_matrix:
        """D, shape (n_slave_points, n_slave_points); a new matrix at each access."""
    @property
    def T(self) -> Optional[scipy.sparse.csr_matrix]:
        """T = D⁻¹B when D is diagonal ("dual", "lumped"), else None."""
    def transfer(self, values: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """Master → slave nodal values, u_s = T u_m.

        Args:
            values: Shape (n_master_points,) or (n_master_points, k).

        Returns:
            Shape (n_slave_points,) or (n_slave_points, k).
        """
    def transfer_conservative(self, loads: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """Slave → master nodal loads, f_m = Tᵀ f_s (keeps the total).

        Args:
            loads: Shape (n_slave_points,) or (n_slave_points, k).

        Returns:
            Shape (n_master_points,) or (n_master_points, k).
        """
    @property
    def summary(self) -> _Summary:
        """Totals over the interface (a new dict at each access)."""
    @property
    def coverage(self) -> npt.NDArray[np.float64]:
        """Per slave point, the covered fraction of ∫ λ_p (0 off the surface)."""
    @property
    def covered(self) -> npt.NDArray[np.bool_]:
        """Per slave point, covered (coverage above 1e-10): the rows T acts on."""
    @property
    def on_surface(self) -> npt.NDArray[np.bool_]:
        """Per slave point, used by some slave face."""
    @property
    def uncovered_nodes(self) -> npt.NDArray[np.int64]:
        """Slave points on the surface that are not covered, ascending."""
    @property
    def multiplier(self) -> Literal["standard", "dual", "lumped"]:
        """The multiplier the matrices were built with."""
    @property
    def shape(self) -> Tuple[int, int]:
        """(n_slave_points, n_master_points)."""

def read_mesh(path: Union[str, "os.PathLike[str]"], group: Union[str, int, None] = None) -> Mesh:
    """Reads the surface to couple from a Gmsh MSH file (4.1 or 2.2, ASCII or binary).

    Args:
        path: The file.
        group: A physical group of dimension 2, by name or number; None for all
            2-D elements (or the boundary of the volume cells, if any). Faces
            may be of first or second order (``tri6``, ``quad8``, ``quad9``).

    Returns:
        The surface; points are all the file's nodes, in file order.

    Raises:
        FileNotFoundError: No such file (other I/O failures: the matching OSError).
        MshError: Invalid file, unknown group, unsupported or degenerate elements.
    """

def assemble(
    master: _MeshLike,
    slave: _MeshLike,
    multiplier: Literal["standard", "dual", "lumped"] = "standard",
    max_gap: Optional[float] = None,
    facing: Literal["any", "opposite"] = "any",
    threads: Optional[int] = None,
    *,
    max_angle: float = 45.0,
    warped_quad_degree: Optional[int] = None,
) -> Mortar:
    """Assembles the mortar matrices B and D between two surface meshes.

    Args:
        master: The master (mortar) side.
        slave: The slave (non-mortar) side, carrying the multipliers.
        multiplier: "standard", "dual" (D diagonal) or "lumped" (D row-summed).
        max_gap: Largest normal distance between paired points, a length; None
            for half the local slave face diameter.
        facing: "any" or "opposite" (the faces face each other).
        threads: Worker threads; None for all cores. B and D do not depend on it.
        max_angle: Largest angle between the normals, in degrees.
        warped_quad_degree: Triangle-rule degree (1 to 20) on warped slave quads;
            None chooses it per face.

    Returns:
        The operator.

    Raises:
        NoOverlapError: No master face meets a slave face within the limits.
        InvalidOptionError: An option out of range.
        MeshError: A (points, faces) tuple that is not a valid mesh.
        ValueError: Unknown multiplier or facing, threads < 1, wrong shapes.
        TypeError: master or slave of another type.
    """

# One bin [from, to) of the normal-gap histogram ("from" is a keyword, hence
# the functional syntax).
_GapBin = TypedDict("_GapBin", {"from": float, "to": float, "nodes": int})

class _Quality(TypedDict):
    """The worst faces of a surface."""

    min_angle_degrees: float
    max_angle_degrees: float
    max_warp: float

class _Invariant(TypedDict):
    """An invariant measured on the operator."""

    name: str
    value: float
    tolerance: float
    ok: bool

class _CheckReport(TypedDict):
    """``check``: the report of ``seam check --json``, keys in its order."""

    master: str
    slave: str
    slave_faces: int
    master_faces: int
    slave_area: float
    master_area: float
    covered_area: float
    covered_fraction: float
    uncovered_slave_nodes: int
    uncovered_examples: List[Tuple[int, Tuple[float, float, float]]]
    gap_histogram: List[_GapBin]
    min_normal_gap: Optional[float]
    max_normal_gap: Optional[float]
    slave_orientation_conflicts: int
    master_orientation_conflicts: int
    slave_quality: _Quality
    master_quality: _Quality
    invariants: List[_Invariant]
    ok: bool

def check(
    master: Union[_MeshLike, str, "os.PathLike[str]"],
    slave: Union[_MeshLike, str, "os.PathLike[str]"],
    *,
    multiplier: Literal["standard", "dual", "lumped"] = "standard",
    max_gap: Optional[float] = None,
    facing: Literal["any", "opposite"] = "any",
    threads: Optional[int] = None,
    max_angle: float = 45.0,
    warped_quad_degree: Optional[int] = None,
) -> _CheckReport:
    """Reports how two surfaces meet: the report of ``seam check --json``, a dict.

    Args:
        master: The master side: a Mesh, a (points, faces) tuple, or the path of
            a Gmsh MSH file, read as ``read_mesh(path)`` reads it.
        slave: The slave side, of the same kinds.
        multiplier, max_gap, facing, threads, max_angle, warped_quad_degree:
            As for ``assemble``.

    Returns:
        The report; "master" and "slave" are the paths given, or "master" and
        "slave" for meshes.

    Raises:
        As ``assemble``; as ``read_mesh`` for a path; FactorizationError when
        T = D⁻¹B cannot be formed.
    """

class _ElementKind(TypedDict):
    name: str
    shape: str
    order: int
    linear: str
    n_nodes: int
    corners: int
    gmsh_type: Optional[int]
    vtk_type: int
    vtk_order: List[int]
    reference_nodes: List[List[float]]
    edges: List[List[int]]

class _CellKind(_ElementKind):
    faces: List[Tuple[str, List[int]]]

class _Catalogue(TypedDict):
    faces: List[_ElementKind]
    cells: List[_CellKind]

def catalogue() -> _Catalogue:
    """The element kinds seam knows, each with its description from seam's element catalogue.

    Nodes are in Gmsh's order. Reference coordinates are Gmsh's, except that
    seam's quadrilateral faces live on [0, 1]² (Gmsh's [-1, 1]² mapped by
    ξ ↦ (ξ + 1)/2).

    Returns:
        {"faces": [...], "cells": [...]}: per kind its name, shape, order,
        linear kind, node and corner counts, Gmsh and VTK type numbers, VTK
        node order, reference nodes, edges (corner pairs; edge k carries node
        corners + k at second order) and, for cells, the local faces
        ([kind name, local nodes], outward).
    """

class SolveError(ValueError):
    """``solve`` could not solve the case or write its results (the one-line message of ``seam solve``)."""

class CaseError(SolveError):
    """The case (file or dict), an option of ``solve`` or an input file is wrong."""

class NoCouplingError(SolveError):
    """An interface whose surfaces do not meet: nothing to couple (``seam solve`` exits with 1)."""

class ConvergenceError(SolveError):
    """An iteration did not converge: PCG, PETSc's Krylov solver, or the contact active set."""

@final
class Solution:
    """A solved case (``solve``)."""

    @property
    def summary(self) -> dict:
        """The content of summary.json."""
    @property
    def bodies(self) -> dict:
        """Per body name: ``.points``, ``.displacement`` (n, 3), ``.stress`` (cells, 6), ``.von_mises``."""
    @property
    def interfaces(self) -> list:
        """Per interface in case order: ``.master``, ``.slave``, ``.kind`` and its point fields."""
    def write(self, dir: Union[str, "os.PathLike[str]"], force: bool = False) -> dict:
        """Writes the files of ``seam solve`` into ``dir``; returns the summary written.

        Waits for another run writing into ``dir``, and first recovers what an
        interrupted run left there: each said in a ``seam.OutputWarning``.
        """

def solve(
    case: Union[str, "os.PathLike[str]", dict],
    solver: Literal["direct", "pcg", "petsc"] = "direct",
    threads: Optional[int] = None,
    *,
    rtol: float = 1e-10,
    petsc_options: Optional[str] = None,
) -> Solution:
    """Solves a case (a case file, or a dict with its schema) as ``seam solve`` does, without writing.

    ``rtol``: PCG and PETSc stop when ‖r‖₂ ≤ rtol ‖b‖₂ (``seam solve --rtol``), in (0, 1).
    ``solver="petsc"``: a PETSc KSP (CG + GAMG by default; the module built with the
    cargo feature ``petsc``); ``petsc_options`` as ``seam solve --petsc-options``.

    Raises:
        CaseError: A bad case, option (an rtol outside (0, 1)) or mesh.
        NoCouplingError: An interface whose surfaces do not meet.
        ConvergenceError: An iteration that did not converge.
        SolveError: Anything else (a singular system, an unwritable output); the
            base class of the three above. Messages are those of ``seam solve``.
        ValueError: An unknown solver, threads < 1.
    """
