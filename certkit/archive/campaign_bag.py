"""A campaign's archive: one BagIt bag holding what was tested and what certkit concluded,
so that years later anyone can prove which data gave which verdicts.

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
import os
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from certkit.archive.bag import (TAGMANIFEST, BagError, Change, bag_hash, check_bag, extract_zip,
                                 read_info, sha256_of, write_bag, write_zip)
from certkit.errors import CertkitInputError
from certkit.evidence.comparison import differences
from certkit.evidence.provenance import environment
from certkit.evidence.pipeline import make_evidence, report_campaign
from certkit.evidence.results_document import results_json
from certkit.outputs import beside, rename_no_replace
from certkit.results import RESULTS_FORMAT
from certkit.spec.jsonsource import JsonSourceError, parse_json
from certkit.spec.campaign import load_campaign
from certkit.version import VERSION

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
    bag_hash: str
    expected_hash: str | None = None
    recomputed: Recomputed | None = None
    notes: list[str] = field(default_factory=list)

    @property
    def intact(self) -> bool:
        return not self.changes

    @property
    def hash_as_expected(self) -> bool:
        return self.expected_hash is None or self.bag_hash == self.expected_hash

    @property
    def passed(self) -> bool:
        return self.intact and self.hash_as_expected and (
            self.recomputed is None or self.recomputed.reproduced)


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
        ("Bag-Software-Agent", f"certkit {VERSION}"),
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
        ("Drop-Model", "not run (--no-model)" if model is None else "run (report appendices "
                                                                    "A to C)"),
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


def _staged_campaign(campaign, folder: Path):
    """The campaign loaded again from its archived copy; refused unless it names the
    same files with the same bytes (a layout the archive cannot reproduce, such as a
    path through a link that leaves the folder, is caught here, not years later)."""
    try:
        staged = load_campaign(folder / campaign.inputs[0].name)
    except CertkitInputError as error:
        raise CertkitInputError.single(
            str(campaign.spec_path), None, "", f"the archived copy of the campaign does not "
            f"load as the original does ({error.problems[0].message}); keep the data files "
            f"inside the campaign folder, not behind links that leave it") from None
    before = [(i.name, i.sha256) for i in campaign.inputs]
    after = [(i.name, i.sha256) for i in staged.inputs]
    if before != after:
        raise CertkitInputError.single(str(campaign.spec_path), None, "",
                                       f"the archived copy names other files than the "
                                       f"original: {after} instead of {before}")
    return staged


def _check_new(target: Path) -> None:
    if os.path.lexists(target):
        raise _refuse(target, "already exists; certkit never replaces an archive: give a "
                              "new name")
    if target.suffix.lower() == ".zip" and target.stem in ("", "."):
        raise _refuse(target, "give the zip a name")


def archive_campaign(spec: str | Path, target: str | Path, *, model: bool = True,
                     progress=None) -> Archived:
    """Archive the campaign at ``spec`` as a bag at ``target``: a folder, or a zip when
    ``target`` ends in .zip.  Its files are copied into the bag first; the assessment
    (with the drop model unless ``model`` is False) and the report are then made from
    those copies, so what the bag concludes is what its own inputs give.

    Raises CertkitInputError for bad input or a target that exists, EnvironmentFailure
    when the machine refuses (no space, no permission, another run writing it); nothing
    is left behind on any failure (see :func:`certkit.outputs.beside`).
    """
    progress = progress or (lambda message: None)
    target = Path(target)
    _check_new(target)
    campaign = load_campaign(spec)
    zipped = target.suffix.lower() == ".zip"
    if zipped and campaign.spec.document.date.year < 1980:
        raise _refuse(target, f"a zip cannot carry a date before 1980 (document.date "
                              f"{campaign.spec.document.date}); archive to a folder")
    final = target.resolve()
    with beside(target) as staging:
        bag = staging / "bag"
        (bag / "data").mkdir(parents=True)
        progress("copying the campaign's files")
        _copy_inputs(campaign, bag / CAMPAIGN)
        campaign = _staged_campaign(campaign, bag / CAMPAIGN)
        assessment, evidence = report_campaign(campaign, bag / RESULTS, model=model,
                                               progress=progress)
        (bag / ENVIRONMENT).write_text(json.dumps(environment(), indent=2) + "\n",
                                       encoding="utf-8")
        progress("writing the manifests")
        try:
            digest = write_bag(bag, _bag_info(campaign, assessment, evidence))
        except BagError as error:
            raise _refuse(target, str(error)) from None
        octets, files = (int(x) for x in read_info(bag)["Payload-Oxum"][0].split("."))
        source = bag
        if zipped:
            source = staging / "bag.zip"
            write_zip(bag, source, final.stem, campaign.spec.document.date)
        try:
            rename_no_replace(source, final)
        except FileExistsError:
            raise _refuse(target, "appeared while the archive was being written; it was "
                                  "left as it is") from None
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


def compare_results(archived: dict, recomputed: dict, tolerance: float
                    ) -> tuple[list[str], list[str]]:
    """(differences, software notes) between two results documents: every value by its
    path, compared by :func:`certkit.evidence.comparison.agree`."""
    found, software = [], []
    for path, a, b in differences(archived, recomputed, tolerance):
        line = f"{path}: archived {a!r}, recomputed {b!r}"
        (software if path.startswith(SOFTWARE) else found).append(line)
    return found, software


def archived_results(folder: Path) -> tuple[bytes, dict]:
    """The archived results.json, bytes and document; BagError when the bag is not a
    certkit archive (another tool's bag, or results that are not certkit's)."""
    path = folder / RESULTS / "results.json"
    try:
        data = path.read_bytes() if path.is_file() else None
        document = parse_json(data) if data is not None else None
    except OSError as error:
        raise BagError(f"{folder}: {RESULTS}/results.json cannot be read: "
                       f"{error.strerror or error}") from None
    except JsonSourceError as error:
        raise BagError(f"{folder}: {RESULTS}/results.json: {error.message}") from None
    if not isinstance(document, dict) or document.get("format") != RESULTS_FORMAT:
        raise BagError(f"{folder}: not a certkit archive (no certkit results at "
                       f"{RESULTS}/results.json)")
    return data, document


def _archived_spec(folder: Path, results: dict) -> Path:
    """The archived spec: the first input results.json records, inside data/campaign/."""
    try:
        named = results["provenance"]["inputs"][0]["file"]
    except (KeyError, IndexError, TypeError):
        named = None
    if not isinstance(named, str) or named.startswith("/") or ".." in PurePosixPath(named).parts:
        raise BagError(f"{folder}: results.json names no campaign spec (provenance.inputs)")
    return folder / CAMPAIGN / named


def recompute(folder: Path, tolerance: float, progress=None) -> Recomputed:
    """Re-run the assessment (and the drop model, when the archive has it) from the
    archived inputs and compare the results with the archived results.json."""
    archived_bytes, archived = archived_results(folder)
    try:
        campaign = load_campaign(_archived_spec(folder, archived))
    except CertkitInputError as error:   # e.g. a spec this certkit no longer accepts
        return Recomputed(False, [f"the archived campaign does not load: {problem}"
                                  for problem in error.problems], [])
    # a recomputation makes the drop model's evidence again, never from the cache
    assessment, evidence = make_evidence(campaign, model=archived.get("model") is not None,
                                         cache=False, progress=progress)
    recomputed_bytes = results_json(assessment, evidence)
    found, software = compare_results(archived, json.loads(recomputed_bytes), tolerance)
    return Recomputed(recomputed_bytes == archived_bytes, found, software)


def verify_archive(path: str | Path, *, recompute_results: bool = False,
                   tolerance: float = 1e-9, expected_hash: str | None = None,
                   progress=None) -> Verification:
    """Check the bag at ``path`` (a folder or a .zip) against its manifests, its hash
    against ``expected_hash`` (kept elsewhere: a bag changed and re-hashed is intact by
    its own manifests but has another hash) and, with ``recompute_results``, that its
    results reproduce from its inputs.

    Raises BagError when ``path`` is not a readable bag.
    """
    with opened_bag(path) as folder:
        changes = check_bag(folder)
        digest = bag_hash(folder) if os.path.isfile(folder / TAGMANIFEST) else ""
        expected = expected_hash.strip().lower() if expected_hash else None
        result = Verification(Path(path), changes, read_info(folder), digest, expected)
        if recompute_results:
            if changes:
                result.notes.append("not recomputed: the bag is not intact, so its inputs "
                                    "are not the ones archived")
            else:
                result.recomputed = recompute(folder, tolerance, progress)
    return result
