"""A battery run's progress on disk, so that a run stopped part-way (a session's end, a
reboot, a kill) can be resumed by the same code and still make one honest record.

While a battery runs, ``DIR/blind-check-progress.jsonl`` holds, on its first line, what
the run is (:func:`header`: who runs the cases, :func:`blindcheck.record.provenance` taken
before the first case ran; the template spec's fingerprint and the gear; the versions of
Python and the numerical packages; the ids of the battery's cases), then one line per
finished case: its outcome, as the record will hold it.  A resume continues only when the
resuming process is the run's in all of that, the date alone aside, and the run was started
from a committed source tree (a tree with uncommitted changes has no commit that names its
code).  A case is a pure function of its id's draws, so a resumed record holds what one
uninterrupted run would have; its ``run_by`` date names the day the run started and the day
of each resume (each resume writes its day into the header).  One process at a time holds
the file (an advisory lock), and it is removed once the record is written.
"""

from __future__ import annotations

import fcntl
import json
import os
import platform
from importlib import metadata
from pathlib import Path

NAME = "blind-check-progress.jsonl"
#: The packages whose version a resume must match (the numbers a case gives are theirs).
PACKAGES = ("numpy", "scipy", "numba")


class ProgressError(ValueError):
    """The progress file cannot be started or continued (the message says why and what to
    do)."""


def header(run_by: dict, template: str, gear_id: str, case_ids: list[str]) -> dict:
    """What a run is: ``run_by`` (its provenance), the template spec's fingerprint (``template``)
    and gear, the environment, and the ids of its cases."""
    return {"run_by": run_by, "template": template, "gear": gear_id,
            "environment": {"python": platform.python_version(),
                            **{name: metadata.version(name) for name in PACKAGES}},
            "cases": case_ids}


def _line(document: dict) -> str:
    # ASCII only: the file is split at "\n" alone, and no outcome's text can break a line
    return json.dumps(document, sort_keys=True, ensure_ascii=True) + "\n"


def as_recorded(outcome: dict) -> dict:
    """``outcome`` as the progress file and the record hold it (JSON and back), so a case
    read back on a resume is the same object as one just run."""
    return json.loads(json.dumps(outcome))


def _differing(run: dict, now: dict) -> list[str]:
    """The keys of two headers that differ, the date of the run aside."""
    keys = []
    for key in sorted(set(run) | set(now)):
        if key == "run_by":
            keys += [f"run_by.{k}" for k in sorted(set(run[key]) | set(now[key]))
                     if k != "date" and run[key].get(k) != now[key].get(k)]
        elif run.get(key) != now.get(key):
            keys.append(key)
    return keys


class Progress:
    """The progress file of a battery run in ``folder``: open it with :meth:`start` or
    :meth:`resume`, add each finished case, :meth:`close` it (and :meth:`remove` it once the
    record is written)."""

    def __init__(self, folder: Path):
        self.path = Path(folder) / NAME
        self._handle = None

    def exists(self) -> bool:
        return self.path.exists()

    def _open(self) -> None:
        self._handle = self.path.open("a", encoding="utf-8")
        try:
            fcntl.flock(self._handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self._handle.close()
            self._handle = None
            raise ProgressError(f"{self.path} is held by another process running this "
                                "battery; wait for it, or stop it first") from None

    def start(self, head: dict) -> None:
        """A new run (its :func:`header`), before any case runs."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._open()
        self._handle.truncate(0)
        self._write(_line(head))

    def resume(self, now: dict) -> tuple[dict, dict[str, dict]]:
        """The run's provenance (its ``date`` naming the day it started and the day of each
        resume, ``now``'s included) and the outcomes already run, by case id;
        :class:`ProgressError` if ``now`` (this process's :func:`header`) is not the run's."""
        self._open()
        text = self.path.read_text(encoding="utf-8")
        lines = text.split("\n")
        try:
            run = json.loads(lines[0])
            run_by, cases = run["run_by"], run["cases"]
        except (json.JSONDecodeError, KeyError, TypeError) as error:
            raise ProgressError(f"{self.path}: its first line is not a battery run's header "
                                f"({type(error).__name__}: {error}); remove the file and run "
                                "the battery again") from None
        commit = run_by.get("commit")
        if not commit or commit.endswith("-dirty"):
            raise ProgressError(
                f"{self.path} was started from a source tree with uncommitted changes "
                f"(commit {commit}): no commit names the code that ran its cases, so it cannot "
                "be resumed; remove it and run the battery again from a committed tree")
        differing = _differing(run, now)
        if differing:
            advice = (f"give the run's own command: {run_by.get('command')}"
                      if differing == ["run_by.command"] else
                      f"resume from a clean clone of commit {commit} with the same "
                      f"environment and the run's command ({run_by.get('command')})")
            raise ProgressError(f"{self.path} is another run than this one (differing: "
                                f"{', '.join(differing)}): {advice}; or remove it and run the "
                                "battery again")
        done, kept = {}, len(lines[0]) + 1
        for number, line in enumerate(lines[1:], start=2):
            if number == len(lines):         # after the last "\n": a write cut short, if any
                break
            try:
                outcome = json.loads(line)
                done[outcome["id"]] = outcome
            except (json.JSONDecodeError, KeyError, TypeError) as error:
                raise ProgressError(f"{self.path}, line {number}: not a case's outcome "
                                    f"({type(error).__name__}: {error}); remove the file and "
                                    "run the battery again") from None
            kept += len(line) + 1
        unknown = sorted(set(done) - set(cases))
        if unknown:
            raise ProgressError(f"{self.path} holds outcomes of cases not in its battery "
                                f"({', '.join(unknown[:3])}); remove it and run the battery "
                                "again")
        dates = set(run_by["date"].split(" and ")) | {now["run_by"]["date"]}
        run_by = {**run_by, "date": " and ".join(sorted(dates))}
        # the header with this resume's day, the finished cases, not a line cut short:
        # written beside and moved in whole, so a stop now leaves the old file or the new
        fresh = self.path.with_name(self.path.name + ".new")
        with fresh.open("w", encoding="utf-8") as handle:
            handle.write(_line({**run, "run_by": run_by}) + text[len(lines[0]) + 1:kept])
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(fresh, self.path)
        self.close()
        self._open()
        return run_by, done

    def _write(self, text: str) -> None:
        self._handle.write(text)
        self._handle.flush()
        os.fsync(self._handle.fileno())

    def add(self, outcome: dict) -> None:
        """One finished case, on disk at once: a stop loses only the cases running."""
        self._write(_line(outcome))

    def close(self) -> None:
        if self._handle is not None:
            self._handle.close()
            self._handle = None

    def remove(self) -> None:
        self.close()
        self.path.unlink(missing_ok=True)
