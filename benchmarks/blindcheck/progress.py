"""A battery run's progress on disk, so that a run stopped part-way (a session's end, a
reboot, a kill) can be resumed by the same code and still make one honest record.

While a battery runs, ``DIR/blind-check-progress.jsonl`` holds, on its first line, who runs
the cases (:func:`blindcheck.record.provenance`, taken before the first case ran) and the
ids of the battery's cases, then one line per finished case: its outcome, as the record
will hold it.  A resume (``--resume``) continues only when the resuming process is the same
code in every respect the provenance records (certkit's version and commit, the diagnosis
code's and the battery code's per-file hashes, the command) and the battery is the same; the
date alone may differ, and the record's ``run_by`` then names every date its cases ran on.
A case is a pure function of its id's draws, so a resumed record holds what one
uninterrupted run would have.  The file is removed once the record is written.
"""

from __future__ import annotations

import json
from pathlib import Path

NAME = "blind-check-progress.jsonl"


class ProgressError(ValueError):
    """The progress file cannot be continued (the message says why and what to do)."""


def _line(document: dict) -> str:
    return json.dumps(document, sort_keys=True, ensure_ascii=False) + "\n"


def as_recorded(outcome: dict) -> dict:
    """``outcome`` as the progress file and the record hold it (JSON and back), so a case
    read back on a resume is the same object as one just run."""
    return json.loads(json.dumps(outcome))


class Progress:
    """The progress file of a battery run in ``folder``."""

    def __init__(self, folder: Path):
        self.path = Path(folder) / NAME

    def exists(self) -> bool:
        return self.path.exists()

    def start(self, run_by: dict, case_ids: list[str]) -> None:
        """A new run: who runs it and which cases, before any case runs."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.path.write_text(_line({"run_by": run_by, "cases": case_ids}), encoding="utf-8")

    def resume(self, now: dict, case_ids: list[str]) -> tuple[dict, dict[str, dict]]:
        """The run's provenance (its ``date`` naming every date its cases ran on, ``now``'s
        included) and the outcomes already run, by case id; :class:`ProgressError` if
        ``now`` (this process's provenance) or the battery differs from the run's."""
        lines = self.path.read_text(encoding="utf-8").splitlines(keepends=True)
        try:
            head = json.loads(lines[0])
        except (IndexError, json.JSONDecodeError) as error:
            raise ProgressError(f"{self.path}: its first line is not a run's header "
                                f"({error}); remove the file and run the battery "
                                "again") from None
        run_by = head["run_by"]
        differing = sorted(key for key in set(run_by) | set(now) if key != "date"
                           and run_by.get(key) != now.get(key))
        if differing:
            raise ProgressError(
                f"{self.path} was started by other code or with another command (differing: "
                f"{', '.join(differing)}); resume it from a clean clone of commit "
                f"{run_by.get('commit')}, or remove it and run the battery again")
        if head["cases"] != case_ids:
            raise ProgressError(f"{self.path} holds another battery's cases; remove it and "
                                "run the battery again")
        done = {}
        kept = [lines[0]]
        for line in lines[1:]:
            if not line.endswith("\n"):       # the last write, cut short by the stop
                break
            outcome = json.loads(line)
            done[outcome["id"]] = outcome
            kept.append(line)
        if len(kept) < len(lines):
            self.path.write_text("".join(kept), encoding="utf-8")
        dates = sorted({d for d in run_by["date"].split(" and ")} | {now["date"]})
        return {**run_by, "date": " and ".join(dates)}, done

    def add(self, outcome: dict) -> None:
        """One finished case (flushed at once: a stop loses at most the case running)."""
        with self.path.open("a", encoding="utf-8") as handle:
            handle.write(_line(outcome))
            handle.flush()

    def remove(self) -> None:
        self.path.unlink(missing_ok=True)
