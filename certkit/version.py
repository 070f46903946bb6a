"""certkit's version: its one home, read by the package (``certkit.__version__``), by the
build (pyproject.toml's dynamic version) and by every record that names the software."""

import subprocess
from pathlib import Path

VERSION = "0.1.0"


def git_commit() -> str | None:
    """Commit of the certkit source tree, with '-dirty' when it has uncommitted changes
    (None outside a git checkout, e.g. an installed wheel)."""
    source = Path(__file__).resolve().parent.parent   # the repository, if any
    if not (source / ".git").exists():
        return None
    try:
        commit = subprocess.run(["git", "-C", str(source), "rev-parse", "HEAD"], check=True,
                                capture_output=True, text=True, timeout=10).stdout.strip()
        # no optional locks: a plain status refreshes the index under .git/index.lock, and
        # a run stopped at that moment (Ctrl-C kills it) would leave the lock in the user's
        # repository, refusing their next git command
        dirty = subprocess.run(["git", "--no-optional-locks", "-C", str(source), "status",
                                "--porcelain", "--untracked-files=no"], check=True,
                               capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return commit + ("-dirty" if dirty else "")
