"""Mortar coupling operators between non-matching surface meshes.

    >>> import seam
    >>> master = seam.read_mesh("master.msh", group="interface")   # doctest: +SKIP
    >>> op = seam.assemble(master, slave, multiplier="dual")        # doctest: +SKIP
    >>> u_slave = op.transfer(u_master)                             # doctest: +SKIP
    >>> seam.check("master.msh", "slave.msh")["covered_fraction"]   # doctest: +SKIP
    >>> seam.solve("case.toml").summary["bodies"][0]["max_displacement"]  # doctest: +SKIP

See ``help(seam.assemble)``, ``help(seam.Mortar)``, ``help(seam.check)`` and ``help(seam.solve)``.
"""

from ._seam import (
    CaseError,
    ConvergenceError,
    FactorizationError,
    InvalidOptionError,
    Mesh,
    MeshError,
    Mortar,
    MortarError,
    MshError,
    NoCouplingError,
    NoOverlapError,
    OutputWarning,
    Solution,
    SolveError,
    __version__,
    assemble,
    catalogue,
    check,
    read_mesh,
    solve,
)

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
