"""Which code decides a gap diagnosis, and its fingerprint: a blind-check record keeps the
hashes of the code that ran its cases, and the report says which files differ from the
running certkit (:mod:`certkit.evidence.gap_view`)."""

from __future__ import annotations

import hashlib
from pathlib import Path

#: The certkit package folder.
PACKAGE = Path(__file__).resolve().parent.parent

#: The modules whose code decides a blind check's outcome (simulation, data, diagnosis);
#: a folder stands for every module in it.
DIAGNOSIS_CODE = ("gap/attribution.py", "gap/selection.py", "gap/missing_force.py",
                  "physics/calibration.py", "physics/starts.py",
                  "physics/drop_model.py", "physics/dynamics.py", "physics/effects/",
                  "physics/fitting.py", "gap/holdout.py", "compliance/measures.py",
                  "gap/phases.py", "gap/residuals.py", "spec/rundata.py",
                  "physics/simulation.py", "physics/synthetic.py", "compliance/servicing.py")


def code_fingerprint() -> str:
    """SHA-256 over the source of :data:`DIAGNOSIS_CODE`: a record made by other code (other
    thresholds, another simulator) says so in the report."""
    digest = hashlib.sha256()
    folder = PACKAGE
    for entry in DIAGNOSIS_CODE:
        names = ([f"{entry}{path.name}" for path in sorted((folder / entry).glob("*.py"))]
                 if entry.endswith("/") else [entry])
        for name in names:
            digest.update(name.encode("utf-8") + b"\0" + (folder / name).read_bytes())
    return digest.hexdigest()


def code_files() -> dict[str, str]:
    """SHA-256 of each module of :data:`DIAGNOSIS_CODE` (path under certkit/): a record
    keeps them so that the report can say which files differ from the running certkit."""
    folder = PACKAGE
    files = {}
    for entry in DIAGNOSIS_CODE:
        names = ([f"{entry}{path.name}" for path in sorted((folder / entry).glob("*.py"))]
                 if entry.endswith("/") else [entry])
        for name in names:
            files[name] = hashlib.sha256((folder / name).read_bytes()).hexdigest()
    return files


def differing_files(recorded: dict[str, str] | None) -> list[str] | None:
    """The modules of the diagnosis code whose content differs from ``recorded`` (added or
    removed ones too); None when the record keeps no per-file hashes."""
    if recorded is None:
        return None
    now = code_files()
    return sorted(name for name in set(now) | set(recorded) if now.get(name) != recorded.get(name))
