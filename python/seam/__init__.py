"""Mortar coupling operators between non-matching surface meshes.

    >>> import seam
    >>> master = seam.read_mesh("master.msh", group="interface")   # doctest: +SKIP
    >>> op = seam.assemble(master, slave, multiplier="dual")        # doctest: +SKIP
    >>> u_slave = op.transfer(u_master)                             # doctest: +SKIP
    >>> seam.check("master.msh", "slave.msh")["covered_fraction"]   # doctest: +SKIP

See ``help(seam.assemble)``, ``help(seam.Mortar)`` and ``help(seam.check)``.
"""

from ._seam import (
    FactorizationError,
    InvalidOptionError,
    Mesh,
    MeshError,
    Mortar,
    MortarError,
    MshError,
    NoOverlapError,
    __version__,
    assemble,
    check,
    read_mesh,
)

__all__ = [
    "FactorizationError",
    "InvalidOptionError",
    "Mesh",
    "MeshError",
    "Mortar",
    "MortarError",
    "MshError",
    "NoOverlapError",
    "__version__",
    "assemble",
    "check",
    "read_mesh",
]
