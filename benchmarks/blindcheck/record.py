"""Writing a blind-check record: who ran its cases and who scored them (provenance), and
the two files (blind-check.json, blind-check-cases.csv).  certkit reads the record
(:mod:`certkit.spec.blind_record`); only the batteries here write it."""

from __future__ import annotations

import csv
import datetime as dt
import hashlib
import json
from pathlib import Path

from certkit.gap.code import code_files, code_fingerprint
from certkit.version import VERSION, git_commit

#: The battery code beside certkit's (this package and the independent truth generator):
#: hashed into a record's provenance, as the diagnosis code is.
BENCHMARKS = Path(__file__).resolve().parent.parent


def battery_files() -> dict[str, str]:
    """SHA-256 of each module of the battery code (path under benchmarks/)."""
    files = {}
    for folder in ("blindcheck", "truthgen"):
        for path in sorted((BENCHMARKS / folder).glob("*.py")):
            files[f"{folder}/{path.name}"] = hashlib.sha256(path.read_bytes()).hexdigest()
    for name in ("blind_independent.py", "blind_own.py"):
        files[name] = hashlib.sha256((BENCHMARKS / name).read_bytes()).hexdigest()
    return files


def provenance(command: str) -> dict:
    """Who did a step of a blind check (ran its cases, or scored them): certkit's version
    and commit, the diagnosis code's fingerprint and per-file hashes, the battery code's
    per-file hashes, the date, the command."""
    return {"certkit": VERSION, "commit": git_commit(), "code": code_fingerprint(),
            "files": code_files(), "battery_files": battery_files(),
            "date": dt.date.today().isoformat(), "command": command}


def write_blind_check(document: dict, folder: str | Path) -> None:
    """``blind-check.json`` (the whole document) and ``blind-check-cases.csv`` (a row per
    case: truth, size, what was named, held-out load RMSE before and after)."""

    folder = Path(folder)
    text = json.dumps(document, indent=1, sort_keys=True, ensure_ascii=False) + "\n"
    (folder / "blind-check.json").write_text(text, encoding="utf-8")
    with (folder / "blind-check-cases.csv").open("w", encoding="utf-8", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(["case", "truth", "effect/noise", "seed", "named", "statement",
                         "held-out load RMSE before [N]", "after [N]", "shrink [%]"])
        for o in document["cases"]:
            writer.writerow([o["id"], " + ".join(o["truth"]) or "none",
                             "" if o["ratio"] is None else f"{o['ratio']:g}", o["seed"],
                             " + ".join(o["named"]) or "none", o["statement"],
                             "" if o["before"] is None else f"{o['before']:.6g}",
                             "" if o["after"] is None else f"{o['after']:.6g}",
                             f"{100 * o['shrink']:.4g}"])
