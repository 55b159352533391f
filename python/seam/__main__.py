"""``python -m seam ARGS``: the ``seam`` command."""

from ._cli import main

main()
