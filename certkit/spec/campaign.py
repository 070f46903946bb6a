"""Loading a campaign: spec file -> validated spec -> checked run data, with input hashes."""

from __future__ import annotations

import difflib
import hashlib
import math
import posixpath
import types
import typing
from dataclasses import dataclass
from pathlib import Path

from pydantic import BaseModel, ValidationError

from certkit.errors import CertkitInputError, Problem, key_path, shown
from certkit.spec import requirement_sets
from certkit.spec.blind_record import BlindCheckRecord, BlindRecordError, read_blind_check
from certkit.spec.rundata import DATA_SUFFIXES, RunSeries, read_run
from certkit.spec.schema import CampaignSpec, GearUnit
from certkit.spec.uncertainty import UNCERTAIN_CHANNELS
from certkit.spec.yamlsource import LineMap, line_of, load_yaml

#: Wing loadings above this are typing errors (the heaviest airliners are near 9 kPa).
MAX_WING_LOADING = 1.0e5  # Pa


@dataclass(frozen=True)
class InputFile:
    """A file the results depend on, named relative to the campaign folder."""

    name: str
    sha256: str
    size: int
    path: Path


@dataclass
class Campaign:
    """A validated campaign with its run data loaded (SI inside)."""

    spec: CampaignSpec
    spec_path: Path
    root: Path
    lines: LineMap
    series: dict[str, RunSeries | None]
    inputs: list[InputFile]
    blind_check: BlindCheckRecord | None = None   # model.gap.blind_check, read and checked
    sealed_blind_check: BlindCheckRecord | None = None   # model.gap.sealed_blind_check

    @property
    def gear_units(self) -> dict[str, GearUnit]:
        return {gear.id: gear for gear in self.spec.gear_units}

    def line(self, *location) -> int | None:
        return line_of(self.lines, location)


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _message(error: dict) -> str:
    kind = error["type"]
    if kind == "extra_forbidden":
        return "unknown key (not part of the campaign spec; check the spelling)"
    if kind == "missing":
        return "required key is missing"
    message = error["msg"]
    found = error.get("input")
    if kind in ("quantity", "unit", "date", "scale"):
        return message
    if kind == "string_type" and isinstance(found, (int, float)) and not isinstance(found, bool):
        return f'expected text, got the number {shown(found)}; write it in quotes, e.g. "{found}"'
    if kind == "too_short":
        return "at least one entry is required"
    if kind in ("model_type", "dict_type", "model_attributes_type"):
        return f"expected a mapping of keys and values (such as {{method: none}}), got " \
               f"{shown(found)}"
    if kind == "finite_number":
        return f"expected a finite number, got {shown(found)}"
    if isinstance(found, (str, int, float, bool)) or found is None:
        return f"{message[0].lower()}{message[1:]}; got {shown(found)}"
    return message[0].lower() + message[1:]


def _unwrap(kind):
    """The type inside Annotated[...] and ``... | None``."""
    while typing.get_origin(kind) in (typing.Annotated, typing.Union, types.UnionType):
        kind = next(arg for arg in typing.get_args(kind) if arg is not type(None))
    return kind


def _is_model(kind) -> bool:
    return isinstance(kind, type) and issubclass(kind, BaseModel)


def _keys_allowed(location: tuple) -> set[str]:
    """The keys the spec model takes at ``location`` (a mapping's path), from its fields;
    empty where the spec holds no model there."""
    kind = CampaignSpec
    for part in location:
        kind = _unwrap(kind)
        if _is_model(kind) and part in kind.model_fields:
            kind = kind.model_fields[part].annotation
        elif typing.get_origin(kind) in (list, dict):
            kind = typing.get_args(kind)[-1]   # list[item] or dict[key, value]
        else:
            return set()
    kind = _unwrap(kind)
    return set(kind.model_fields) if _is_model(kind) else set()


def _misspelt_keys(items: list[tuple[tuple, dict]], lines: LineMap) -> dict[tuple, str]:
    """Unknown keys that look like a key the model takes there and the spec lacks:
    location of the unknown key -> the likely key (difflib's closest match)."""
    likely = {}
    for location, item in items:
        if item["type"] != "extra_forbidden" or not isinstance(location[-1], str):
            continue
        parent = location[:-1]
        written = {path[-1] for path in lines if path and path[:-1] == parent}
        match = difflib.get_close_matches(location[-1],
                                          sorted(_keys_allowed(parent) - written), n=1)
        if match:
            likely[location] = match[0]
    return likely


def _without_tags(location: tuple) -> tuple:
    """``location`` without the tag pydantic puts after the index of a discriminated union's
    item (uncertainty.channels[i].<channel>), which is no key of the file."""
    for index in range(2, len(location) - 1):
        if (location[index - 2:index] == ("uncertainty", "channels")
                and isinstance(location[index], int)
                and location[index + 1] in UNCERTAIN_CHANNELS):
            return location[:index + 1] + location[index + 2:]
    return location


def _validation_problems(error: ValidationError, display: str, lines: LineMap) -> list[Problem]:
    """One problem per validation error, at the line of its key.  A misspelt key gives one
    problem at its own line naming the likely key, not a second one for that key missing."""
    items = [(_without_tags(tuple(part for part in item["loc"]
                                  if not (isinstance(part, str)
                                          and part.startswith("function-")))), item)
             for item in error.errors()]
    likely = _misspelt_keys(items, lines)
    meant = {location[:-1] + (key,) for location, key in likely.items()}
    problems = []
    for location, item in items:
        if item["type"] == "missing" and location in meant:
            continue
        message = (f"unknown key {location[-1]!r}: did you mean {likely[location]!r}?"
                   if location in likely else _message(item))
        problems.append(Problem(display, line_of(lines, location), key_path(location), message))
    return problems


def _cross_references(spec: CampaignSpec, display: str, lines: LineMap) -> list[Problem]:
    """Checks that need the whole spec: unique ids, references between sections."""
    problems: list[Problem] = []

    def add(location: tuple, message: str) -> None:
        problems.append(Problem(display, line_of(lines, location), key_path(location), message))

    for index, entry in enumerate(spec.certification_basis):
        if entry.requirement_set not in requirement_sets.available():
            add(("certification_basis", index, "requirement_set"),
                f"unknown requirement set {entry.requirement_set!r}; available: "
                f"{', '.join(requirement_sets.available())}")
    gear_ids = [gear.id for gear in spec.gear_units]
    for index, gear_id in enumerate(gear_ids):
        if gear_ids.index(gear_id) != index:
            add(("gear_units", index, "id"), f"duplicate gear unit id {gear_id!r}")
    loading = spec.aircraft.maximum_weight.si / spec.aircraft.wing_area.si
    if not math.isfinite(loading) or loading > MAX_WING_LOADING:
        add(("aircraft", "maximum_weight"),
            f"the wing loading W/S = {spec.aircraft.maximum_weight.text} / "
            f"{spec.aircraft.wing_area.text} is not a plausible number ({loading:.3g} Pa)")
    run_ids = [run.id for run in spec.runs]
    for index, run in enumerate(spec.runs):
        if run_ids.index(run.id) != index:
            add(("runs", index, "id"), f"duplicate run id {run.id!r}")
        for position, gear_id in enumerate(run.gear_units):
            if gear_id not in gear_ids:
                add(("runs", index, "gear_units", position),
                    f"unknown gear unit {gear_id!r}; declared: {', '.join(gear_ids)}")
        if run.lift.method == "none" and run.lift.ratio is not None and run.lift.ratio.si != 0:
            add(("runs", index, "lift", "ratio"), "lift method 'none' takes no lift ratio")
        if run.lift.method != "none":
            if run.lift.ratio is None:
                add(("runs", index, "lift", "ratio"),
                    f"lift method {run.lift.method!r} needs the lift ratio L")
            elif run.lift.ratio.si <= 0:
                add(("runs", index, "lift", "ratio"),
                    f"expected a ratio above 0, got {run.lift.ratio.text!r}")
        for section, mapping in (("data", run.data), ("reported", run.reported)):
            for gear_id in (mapping.gears if mapping is not None else {}):
                if gear_id not in run.gear_units:
                    add(("runs", index, section, "gears", gear_id),
                        f"gear unit {gear_id!r} is not among this run's gear_units "
                        f"({', '.join(run.gear_units)})")
    references = [(("model", "identification", "held_out"), spec.model.identification.held_out),
                  (("model", "gap", "held_out"), spec.model.gap.held_out)]
    if spec.model.calibration is not None:
        references.append((("model", "calibration", "runs"), spec.model.calibration.runs))
    for location, chosen in references:
        for position, run_id in enumerate(chosen):
            if run_id not in run_ids:
                add(location + (position,),
                    f"unknown run {run_id!r}; declared: {', '.join(run_ids)}")
    stated: dict[tuple, int] = {}
    for index, item in enumerate(spec.uncertainty.channels if spec.uncertainty else []):
        for position, gear_id in enumerate(item.gear_units or []):
            if gear_id not in gear_ids:
                add(("uncertainty", "channels", index, "gear_units", position),
                    f"unknown gear unit {gear_id!r}; declared: {', '.join(gear_ids)}")
        for gear_id in (item.gear_units or (gear_ids if item.gear_units is None
                                            and item.channel != "drop_mass_acceleration"
                                            else [None])):
            key = (item.channel, gear_id)
            if key in stated:
                add(("uncertainty", "channels", index, "channel"),
                    f"the {item.channel} channel{f' of {gear_id}' if gear_id else ''} already "
                    f"has its uncertainty in uncertainty.channels[{stated[key]}]")
            stated.setdefault(key, index)
    reference = spec.reference_results
    if reference is not None and reference.gear is not None and reference.gear not in gear_ids:
        add(("reference_results", "gear"),
            f"unknown gear unit {reference.gear!r}; declared: {', '.join(gear_ids)}")
    if reference is not None and reference.run is not None and reference.run not in run_ids:
        add(("reference_results", "run"),
            f"unknown run {reference.run!r}; declared: {', '.join(run_ids)}")
    return problems


def _resolve_data_path(root: Path, relative: str, display: str, location: tuple,
                       lines: LineMap, what: str = "data file", suffixes: tuple = ()) -> Path:
    """The file ``relative`` names, inside the campaign folder, a regular file (and, when
    ``suffixes`` are given, with one of them), else an input error at the spec's key."""
    def fail(message: str) -> CertkitInputError:
        return CertkitInputError.single(display, line_of(lines, location), key_path(location),
                                        message)

    name = shown(relative)
    given = root / relative
    try:
        candidate = given.resolve(strict=False)
        if given.is_symlink() and not given.exists():
            raise fail(f"{what} {name} is a broken link")
        if not candidate.is_relative_to(root):
            raise fail(f"{what} {name} is outside the campaign folder {root}")
        if candidate.is_dir():
            raise fail(f"{what} {name} is a folder, not a file")
        if candidate.exists() and not candidate.is_file():
            raise fail(f"{what} {name} is not a regular file (a pipe, socket or device); "
                       f"certkit reads files it can hash and archive")
        if not candidate.is_file():
            hint = ("; write the path relative to the spec's folder with '/' (the same spec "
                    "is read on every system), as data/run1.csv" if "\\" in relative else "")
            raise fail(f"{what} {name} not found (looked for {shown(str(candidate))}){hint}")
        if suffixes and candidate.suffix.lower() not in suffixes:
            raise fail(f"{what} {name} is not in a format certkit reads: expected a name "
                       f"ending in {', '.join(suffixes)}, found "
                       f"{repr(candidate.suffix) if candidate.suffix else 'no suffix'}")
    except (OSError, RuntimeError, ValueError) as error:  # a name too long, a link loop, NUL
        reason = error.strerror if isinstance(error, OSError) and error.strerror else error
        raise fail(f"{what} {name} cannot be resolved: {reason}") from None
    return candidate


def _input_name(relative: str, resolved: Path, root: Path) -> str:
    """The name an input is recorded (and archived) under: the path the spec gives,
    normalised, so that it reads the same through a symbolic link; the resolved path when
    the given one leaves the folder on its way."""
    given = posixpath.normpath(relative)
    if given.startswith("../") or given == ".." or posixpath.isabs(given):
        return resolved.relative_to(root).as_posix()
    return given


def _blind_check(spec: CampaignSpec, root: Path, display: str, lines: LineMap,
                 key: str = "blind_check") -> tuple[BlindCheckRecord | None, Path | None]:
    """A blind-check record the spec names (model.gap.blind_check, or ``key``), read and
    checked."""
    relative = getattr(spec.model.gap, key)
    if relative is None:
        return None, None
    location = ("model", "gap", key)
    path = _resolve_data_path(root, relative, display, location, lines,
                              what="blind-check record")
    try:
        return read_blind_check(path), path
    except BlindRecordError as error:
        line = line_of(lines, location)
        raise CertkitInputError([
            Problem(display, line, key_path(location),
                    f"{relative}{': ' + key if key else ''}: {message}")
            for key, message in error.problems]) from None


def load_campaign(path: str | Path) -> Campaign:
    """Read, validate and load a campaign spec and its run data.

    Parameters
    ----------
    path : str or Path
        The campaign YAML file.  Data files are resolved relative to its folder
        and must lie inside it.

    Raises
    ------
    CertkitInputError
        Listing every problem with file, line, key, what was expected and what was found.
    """
    spec_path = Path(path).resolve()
    display = str(path)
    raw, lines = load_yaml(spec_path, display)
    if raw is None:
        raise CertkitInputError.single(
            display, 1, "", "the file is empty (or only comments); expected the sections "
                            "certkit, campaign, document, certification_basis, aircraft, "
                            "gear_units and runs (see `certkit schema`)")
    if not isinstance(raw, dict):
        raise CertkitInputError.single(display, 1, "", "expected a mapping of campaign sections "
                                                        f"at the top level, got {type(raw).__name__}")
    try:
        spec = CampaignSpec.model_validate(raw)
    except ValidationError as error:
        raise CertkitInputError(_validation_problems(error, display, lines)) from None
    problems = _cross_references(spec, display, lines)
    if problems:
        raise CertkitInputError(problems)

    root = spec_path.parent
    inputs = [InputFile(spec_path.name, _sha256(spec_path), spec_path.stat().st_size, spec_path)]
    gear_units = {gear.id: gear for gear in spec.gear_units}
    default_rate = spec.instrumentation.sampling_rate.si if spec.instrumentation else None
    series: dict[str, RunSeries | None] = {}
    errors: list[Problem] = []
    for index, run in enumerate(spec.runs):
        if run.data is None:
            series[run.id] = None
            continue
        location = ("runs", index, "data", "file")
        try:
            data_path = _resolve_data_path(root, run.data.file, display, location, lines,
                                           suffixes=DATA_SUFFIXES)
            series[run.id] = read_run(
                data_path, run.data.file, display, index, run, gear_units, default_rate, lines,
                spec.audit.sample_rate_tolerance.si)
        except CertkitInputError as error:
            errors.extend(error.problems)
            continue
        name = _input_name(run.data.file, data_path, root)
        if name not in {item.name for item in inputs}:
            inputs.append(InputFile(name, _sha256(data_path), data_path.stat().st_size, data_path))
    records = {}
    for key in ("blind_check", "sealed_blind_check"):
        try:
            record, record_path = _blind_check(spec, root, display, lines, key)
        except CertkitInputError as error:
            errors.extend(error.problems)
            record, record_path = None, None
        records[key] = record
        if record_path is not None:
            name = _input_name(getattr(spec.model.gap, key), record_path, root)
            if name not in {item.name for item in inputs}:
                inputs.append(InputFile(name, _sha256(record_path), record_path.stat().st_size,
                                        record_path))
    if errors:
        raise CertkitInputError(errors)
    return Campaign(spec, spec_path, root, lines, series, inputs, records["blind_check"],
                    records["sealed_blind_check"])
