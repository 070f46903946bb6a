"""A campaign's archive: one BagIt bag holding what was tested and what certkit concluded,
so that years later anyone can prove which data gave which verdicts (issue 6).

Payload (under ``data/``)::

    campaign/          the spec and every file it names, at their paths relative to it
    results/           report.html, report.pdf, results.json, tables/*.csv
    environment.json   certkit's version and commit, Python, the platform, every package

bag-info.txt carries the campaign's identity, its dates (the issue date is the bagging
date: nothing in a bag comes from the clock) and its verdict counts, so a catalog can
index the bag without opening the results.  The same inputs and software give a
byte-identical bag.  A bag is built beside its target and moved into place whole; an
existing target is never replaced.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from . import __version__
from .bag import BagError, Change, check_bag, extract_zip, read_info, sha256_of, write_bag, \
    write_zip
from .errors import CertkitInputError
from .provenance import environment

CAMPAIGN = "data/campaign"
RESULTS = "data/results"
ENVIRONMENT = "data/environment.json"
# what results.json says about the software rather than the campaign: a recomputation
# with other software reports these as notes, not as differences
SOFTWARE = ("provenance/certkit_version", "provenance/certkit_commit", "provenance/python",
            "provenance/dependencies")


@dataclass(frozen=True)
class Archived:
    path: Path
    bag_hash: str
    files: int
    octets: int
    outcome: str


@dataclass(frozen=True)
class Recomputed:
    """The archived results against results recomputed from the archived inputs."""

    identical: bool                     # results.json byte for byte
    differences: list[str]              # campaign numbers and texts that did not reproduce
    software: list[str]                 # what differs about the software, for the record

    @property
    def reproduced(self) -> bool:
        return not self.differences


@dataclass
class Verification:
    path: Path
    changes: list[Change]
    info: dict[str, list[str]]
    recomputed: Recomputed | None = None
    notes: list[str] = field(default_factory=list)

    @property
    def intact(self) -> bool:
        return not self.changes

    @property
    def passed(self) -> bool:
        return self.intact and (self.recomputed is None or self.recomputed.reproduced)


def _refuse(target: Path, message: str) -> CertkitInputError:
    return CertkitInputError.single(str(target), None, "--output", message)


def _bag_info(campaign, assessment, model) -> list[tuple[str, str]]:
    spec, document = campaign.spec, campaign.spec.document
    counts, findings = assessment.counts(), assessment.finding_counts()
    info = [
        ("Source-Organization", document.applicant),
        ("External-Identifier", spec.campaign.id),
        ("External-Description", spec.campaign.title),
        ("Bagging-Date", document.date.isoformat()),
        ("Bag-Software-Agent", f"certkit {__version__}"),
        ("Campaign-Id", spec.campaign.id),
        ("Campaign-Spec", f"{CAMPAIGN}/{campaign.inputs[0].name}"),
        ("Aircraft-Model", spec.aircraft.model),
        ("Report-Number", document.report_number),
        ("Report-Revision", document.revision),
        ("Issue-Date", document.date.isoformat()),
        *(("Test-Date", day.isoformat()) for day in sorted(document.test_dates)),
        ("Test-Facility", document.facility),
        ("Campaign-Outcome", assessment.outcome),
        ("Criteria-Passed", str(counts["PASS"])),
        ("Criteria-Failed", str(counts["FAIL"])),
        ("Criteria-Not-Shown", str(counts["NOT SHOWN"])),
        ("Data-Quality-Errors", str(findings["error"])),
        ("Data-Quality-Warnings", str(findings["warning"])),
        ("Drop-Model", "not run (--no-model)" if model is None else "run (report sections "
                                                                    "9 to 11)"),
    ]
    return info


def _copy_inputs(campaign, folder: Path) -> None:
    """The spec and its data files, each checked against the hash it was read with."""
    for item in campaign.inputs:
        destination = folder / item.name
        destination.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(item.path, destination)
        if sha256_of(destination) != item.sha256:
            raise CertkitInputError.single(str(item.path), None, "", "changed while it was "
                                           "being archived; archive again when it is stable")


def _check_new(target: Path) -> None:
    if os.path.lexists(target):
        raise _refuse(target, "already exists; certkit never replaces an archive: give a "
                              "new name")
    if target.suffix.lower() == ".zip" and target.stem in ("", "."):
        raise _refuse(target, "give the zip a name")


def _created_parents(parent: Path) -> list[Path]:
    missing = [p for p in [parent, *parent.parents] if not p.exists()]
    for folder in reversed(missing):
        folder.mkdir()
    return missing


def archive_campaign(spec: str | Path, target: str | Path, *, model: bool = True,
                     progress=None) -> Archived:
    """Assess the campaign at ``spec`` (with the drop model unless ``model`` is False),
    render its report and write everything as a bag at ``target``: a folder, or a zip
    when ``target`` ends in .zip.

    Raises CertkitInputError for bad input or a target that exists; nothing is left
    behind on any failure.
    """
    from .campaign import load_campaign
    from .compliance import assess
    from .report import render_report

    progress = progress or (lambda message: None)
    target = Path(target)
    _check_new(target)
    campaign = load_campaign(spec)
    progress("assessing")
    assessment = assess(campaign)
    evidence = None
    if model:
        from .model_evidence import model_evidence
        progress("calibrating the drop model")
        evidence = model_evidence(campaign)
    final = target.absolute()
    try:
        created = _created_parents(final.parent)
    except OSError as error:
        raise _refuse(target, f"cannot create its folder: {error.strerror or error}") from None
    try:
        staging = Path(tempfile.mkdtemp(prefix=f".{final.name}.tmp-", dir=final.parent))
    except OSError as error:
        for folder in created:
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise _refuse(target, f"cannot write here: {error.strerror or error}") from None
    placed = False
    try:
        bag = staging / "bag"
        (bag / "data").mkdir(parents=True)
        progress("copying the campaign's files")
        _copy_inputs(campaign, bag / CAMPAIGN)
        render_report(assessment, bag / RESULTS, progress, evidence)
        (bag / ENVIRONMENT).write_text(json.dumps(environment(), indent=2) + "\n",
                                       encoding="utf-8")
        progress("writing the manifests")
        digest = write_bag(bag, _bag_info(campaign, assessment, evidence))
        info = read_info(bag)
        octets, files = (int(x) for x in info["Payload-Oxum"][0].split("."))
        source = bag
        if final.suffix.lower() == ".zip":
            source = staging / "bag.zip"
            write_zip(bag, source, final.stem, campaign.spec.document.date)
        if os.path.lexists(final):   # appeared while the bag was being made
            raise _refuse(target, "appeared while the archive was being written; it was "
                                  "left as it is")
        os.replace(source, final) if source.is_dir() else os.link(source, final)
        placed = True
    except FileExistsError:
        raise _refuse(target, "appeared while the archive was being written; it was left "
                              "as it is") from None
    finally:
        shutil.rmtree(staging, ignore_errors=True)
        if not placed:
            for folder in created:
                with contextlib.suppress(OSError):
                    folder.rmdir()
    return Archived(target, digest, files, octets, assessment.outcome)


# --------------------------------------------------------------------------- reading
@contextlib.contextmanager
def opened_bag(path: str | Path):
    """The bag at ``path`` as a folder: itself, or a zip's bag extracted (safely) into a
    temporary folder removed afterwards.  Raises BagError when it cannot be read."""
    path = Path(path)
    if path.is_file():
        with tempfile.TemporaryDirectory(prefix="certkit-bag-") as scratch:
            yield extract_zip(path, Path(scratch))
    elif path.is_dir():
        yield path
    else:
        raise BagError(f"{path}: not found (expected a bag folder or a .zip of one)")


def _flatten(node, prefix: str, out: dict) -> None:
    if isinstance(node, dict):
        for key, value in node.items():
            _flatten(value, f"{prefix}/{key}" if prefix else str(key), out)
    elif isinstance(node, list):
        for index, value in enumerate(node):
            _flatten(value, f"{prefix}/{index}", out)
        if not node:
            out[prefix] = []
    else:
        out[prefix] = node


def _agree(a, b, tolerance: float) -> bool:
    numbers = (int, float)
    if isinstance(a, bool) or isinstance(b, bool) or not (isinstance(a, numbers)
                                                         and isinstance(b, numbers)):
        return a == b
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return a == b or abs(a - b) <= tolerance * max(abs(a), abs(b))


def compare_results(archived: dict, recomputed: dict, tolerance: float
                    ) -> tuple[list[str], list[str]]:
    """(differences, software notes) between two results documents: every value by its
    path; numbers agree within ``tolerance`` relative, everything else exactly."""
    then, now = {}, {}
    _flatten(archived, "", then)
    _flatten(recomputed, "", now)
    differences, software = [], []
    for path in sorted(set(then) | set(now)):
        a, b = then.get(path, "(absent)"), now.get(path, "(absent)")
        if _agree(a, b, tolerance):
            continue
        line = f"{path}: archived {a!r}, recomputed {b!r}"
        (software if path.startswith(SOFTWARE) else differences).append(line)
    return differences, software


def _archived_spec(folder: Path, info: dict[str, list[str]]) -> Path:
    named = (info.get("Campaign-Spec") or [""])[0]
    parts = PurePosixPath(named).parts
    if not named.startswith(CAMPAIGN + "/") or ".." in parts:
        raise BagError(f"{folder}: bag-info.txt names no campaign spec under {CAMPAIGN}/ "
                       f"(Campaign-Spec: {named!r})")
    return folder / named


def recompute(folder: Path, info: dict[str, list[str]], tolerance: float,
              progress=None) -> Recomputed:
    """Re-run the assessment (and the drop model, when the archive has it) from the
    archived inputs and compare the results with the archived results.json."""
    from .campaign import load_campaign
    from .compliance import assess
    from .report import results_json

    archived_bytes = (folder / RESULTS / "results.json").read_bytes()
    try:
        archived = json.loads(archived_bytes)
    except ValueError as error:
        return Recomputed(False, [f"{RESULTS}/results.json: not JSON ({error})"], [])
    campaign = load_campaign(_archived_spec(folder, info))
    assessment = assess(campaign)
    evidence = None
    if archived.get("model") is not None:
        from .model_evidence import model_evidence
        (progress or (lambda m: None))("calibrating the drop model")
        evidence = model_evidence(campaign)
    recomputed_bytes = results_json(assessment, evidence)
    differences, software = compare_results(archived, json.loads(recomputed_bytes), tolerance)
    return Recomputed(recomputed_bytes == archived_bytes, differences, software)


def verify_archive(path: str | Path, *, recompute_results: bool = False,
                   tolerance: float = 1e-9, progress=None) -> Verification:
    """Check the bag at ``path`` (a folder or a .zip) against its manifests and, with
    ``recompute_results``, that its results reproduce from its inputs.

    Raises BagError when ``path`` is not a readable bag.
    """
    with opened_bag(path) as folder:
        changes = check_bag(folder)
        result = Verification(Path(path), changes, read_info(folder))
        if recompute_results:
            if changes:
                result.notes.append("not recomputed: the bag is not intact, so its inputs "
                                    "are not the ones archived")
            else:
                result.recomputed = recompute(folder, result.info, tolerance, progress)
    return result
