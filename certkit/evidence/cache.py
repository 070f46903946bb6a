"""The drop-model evidence of a campaign kept between runs, so that a report whose inputs
and evidence-making code have not changed is laid out again in seconds.

An entry is found by a key that hashes everything the evidence is made from:

* the campaign: the name (relative to the spec's folder) and SHA-256 of every input file
  it read (the spec, the run data, the blind-check record: ``Campaign.inputs``), so a
  copy of the campaign elsewhere (the archive's) finds the same entry;
* the code that made it: every ``.py`` file of certkit except the presentation modules
  (:data:`PRESENTATION`: report layout, figures, templates, the CLI and the archive),
  byte for byte, and certkit's version;
* the numerical libraries it ran on (:data:`LIBRARIES`) and the Python version.

Any change to one of these gives another key, so stale evidence is never reused; a
change to the presentation alone (a template, a figure, the wording of a section) keeps
the key.  Entries live in the user's cache folder (:func:`cache_folder`; the environment
variable ``CERTKIT_CACHE`` names another), one private pickle file each, written
atomically; the
oldest are removed beyond :data:`KEEP` entries.  An entry that cannot be read (another
Python, a damaged file) counts as absent and is made again.  The cache holds only what
this user's certkit wrote there: pickle files run code when loaded, so the folder must
not be writable by others (:func:`load` refuses one that is).
"""

from __future__ import annotations

import hashlib
import json
import os
import pickle
import platform
import stat
import sys
from pathlib import Path

from certkit.evidence.provenance import versions
from certkit.outputs import write_bytes_atomically
from certkit.version import VERSION

PACKAGE = Path(__file__).resolve().parent.parent
#: certkit's modules (relative to the package) that only lay the evidence out: changing
#: them keeps the cache key.  Everything else certkit holds is part of the key, so a module
#: added later and not listed here costs a cache miss when it changes, never a stale entry.
PRESENTATION = ("cli/", "archive/", "evidence/audit.py", "evidence/comparison.py",
                "evidence/figures.py", "evidence/gap_view.py", "evidence/methods.py",
                "evidence/limits.py", "evidence/model_view.py", "evidence/render.py",
                "evidence/report.py",
                "evidence/results_document.py", "evidence/sections.py", "evidence/view.py",
                "evidence/cache.py", "evidence/pipeline.py", "evidence/provenance.py",
                "outputs.py")
#: The libraries whose versions are part of the key (the numbers depend on them).
LIBRARIES = ("numpy", "scipy", "numba", "llvmlite", "threadpoolctl", "pandas", "pyarrow",
             "pint", "pydantic", "PyYAML")
#: How many entries the cache keeps (the most recently written).
KEEP = 16


def cache_folder() -> Path:
    """``$CERTKIT_CACHE``, else the platform's user cache folder + ``certkit/evidence``."""
    if os.environ.get("CERTKIT_CACHE"):
        return Path(os.environ["CERTKIT_CACHE"])
    if sys.platform == "win32":
        base = Path(os.environ.get("LOCALAPPDATA", Path.home() / "AppData" / "Local"))
    elif sys.platform == "darwin":
        base = Path.home() / "Library" / "Caches"
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / "certkit" / "evidence"


def _code_digest() -> str:
    digest = hashlib.sha256(VERSION.encode())
    for path in sorted(PACKAGE.rglob("*.py")):
        relative = path.relative_to(PACKAGE).as_posix()
        if relative.startswith(PRESENTATION):
            continue
        digest.update(relative.encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def _libraries() -> dict:
    return {"python": platform.python_version(), **versions(LIBRARIES)}


def key(campaign, what: str) -> str:
    """The cache key of ``what`` (a name for the kind of evidence and its options) made
    from ``campaign`` by this certkit on these libraries."""
    record = {"what": what, "inputs": [[item.name, item.sha256] for item in campaign.inputs],
              "code": _code_digest(), "libraries": _libraries()}
    return hashlib.sha256(json.dumps(record, sort_keys=True).encode()).hexdigest()


def _safe(folder: Path) -> bool:
    """The folder is this user's and no one else may write to it."""
    if not hasattr(os, "getuid"):
        return True
    info = folder.stat()
    return info.st_uid == os.getuid() and not info.st_mode & (stat.S_IWGRP | stat.S_IWOTH)


def load(entry_key: str, folder: Path | None = None):
    """The evidence stored under ``entry_key``, or None (absent, unreadable, or a cache
    folder others may write to)."""
    folder = folder or cache_folder()
    path = folder / f"{entry_key}.pickle"
    try:
        if not path.is_file() or not _safe(folder):
            return None
        with path.open("rb") as handle:
            return pickle.load(handle)
    except Exception:   # noqa: BLE001 - any unreadable entry is made again, never trusted
        return None


def store(entry_key: str, evidence, folder: Path | None = None) -> str | None:
    """Keep ``evidence`` under ``entry_key``.  Returns None, or why it could not be kept
    (the folder cannot be written, the disk is full, the evidence holds something pickle
    cannot keep): the report does not depend on the cache, so that is no error."""
    folder = folder or cache_folder()
    try:
        data = pickle.dumps(evidence, protocol=pickle.HIGHEST_PROTOCOL)
    except (pickle.PicklingError, TypeError, AttributeError, RecursionError) as problem:
        return f"the evidence cannot be pickled ({type(problem).__name__}: {problem})"
    try:
        folder.mkdir(parents=True, exist_ok=True, mode=0o700)
        write_bytes_atomically(folder / f"{entry_key}.pickle", data, private=True)
        _prune(folder)
    except OSError as problem:
        return f"{folder}: {problem.strerror or problem}"
    return None


def _prune(folder: Path) -> None:
    entries = sorted(folder.glob("*.pickle"), key=lambda p: p.stat().st_mtime, reverse=True)
    for old in entries[KEEP:]:
        old.unlink(missing_ok=True)
