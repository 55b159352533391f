"""The ``seam`` command of the wheel (``pyproject.toml``, ``[project.scripts]``):
the Rust command-line tool, run in this process. ``python -m seam`` is the same."""

import signal
import sys

from . import _seam


def main() -> None:
    """Runs ``seam`` on ``sys.argv`` and exits with its code."""
    # Ctrl-C and a closed pipe end the command as they end the binary.
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    if hasattr(signal, "SIGPIPE"):
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    sys.stdout.flush()
    sys.stderr.flush()
    # clap names the program by argv[0]: "seam", also for `python -m seam`.
    raise SystemExit(_seam.cli(["seam", *sys.argv[1:]]))
