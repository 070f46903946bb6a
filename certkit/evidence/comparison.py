"""Two results documents (results.json, ``format: certkit-results/1``) compared: the one
home of that comparison and of its tolerance rule (:func:`agree`).

Two uses.  :func:`compare` says what moved since a baseline, so that a change to the spec,
the data or certkit itself cannot silently move a certified number (the audit's
``--baseline``).  :func:`differences` compares every value of two documents by its path (an
archive's results recomputed from its inputs, ``certkit verify --recompute``).

Every number is addressed by a stable path: ``design/<key>``, ``basis/<set>/<key>``,
``runs/<run>/<key>``, ``runs/<run>/<gear>/<key>``, ``verdicts/<id>/value|limit|margin`` and
``verdicts/<id>/uncertainty/expanded|conformance`` (a changed uncertainty is a change as a
changed value is; each value's ``standard_uncertainty`` is ``<path>#u``);
verdicts and data-quality findings by their id.  A number drifts when it differs from
the baseline's by more than the relative tolerance (of the baseline's magnitude); numbers,
criteria and findings that appear or disappear, units, verdicts, finding severities and
the campaign's outcome that change, are changes whatever the tolerance.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path

from certkit.errors import CertkitInputError, shown
from certkit.results import RESULTS_FORMAT
from certkit.spec.jsonsource import JsonSourceError, load_json

FORMAT = RESULTS_FORMAT


@dataclass(frozen=True)
class Change:
    kind: str          # "drifted", "added", "removed", "unit changed", "verdict changed"
    path: str
    before: object
    after: object
    detail: str


def numbers(results: dict) -> dict[str, tuple[float | None, str]]:
    """Every number of a results document: path -> (SI value or None, unit)."""
    out = {}

    def take(prefix: str, values: list) -> None:
        for v in values:
            out[f"{prefix}/{v['key']}"] = (v.get("value"), v.get("unit", ""))
            if v.get("standard_uncertainty") is not None:
                out[f"{prefix}/{v['key']}#u"] = (v["standard_uncertainty"], v.get("unit", ""))

    take("design", results.get("design", []))
    for basis in results.get("requirement_sets", []):
        take(f"basis/{basis['id']}", basis.get("values", []))
    for run in results.get("runs", []):
        take(f"runs/{run['id']}", run.get("values", []))
        for gear in run.get("gears", []):
            take(f"runs/{run['id']}/{gear['gear']}", gear.get("values", []))
    for verdict in results.get("verdicts", []):
        for field in ("value", "limit", "margin"):
            out[f"verdicts/{verdict['id']}/{field}"] = (verdict.get(field),
                                                       verdict.get("unit", ""))
        found = verdict.get("uncertainty") or {}
        for field, unit in (("expanded", verdict.get("unit", "")), ("conformance", "1")):
            if found.get(field) is not None:
                out[f"verdicts/{verdict['id']}/uncertainty/{field}"] = (found[field], unit)
    return out


def verdicts(results: dict) -> dict[str, str]:
    return {v["id"]: v["verdict"] for v in results.get("verdicts", [])}


def findings(results: dict) -> dict[str, str]:
    """Every data-quality finding: id -> severity."""
    return {f["id"]: f["severity"] for f in results.get("findings", [])}


def _compare_labels(changes: list, what: str, old: dict, new: dict, changed: str) -> None:
    for key in sorted(set(old) | set(new)):
        if key not in old:
            changes.append(Change("added", f"{what} {key}", None, new[key],
                                  f"a {what} not in the baseline"))
        elif key not in new:
            changes.append(Change("removed", f"{what} {key}", old[key], None,
                                  f"a {what} only in the baseline"))
        elif old[key] != new[key]:
            changes.append(Change(changed, f"{what} {key}", old[key], new[key],
                                  f"{old[key]} → {new[key]}"))


def agree(earlier, later, tolerance: float) -> bool:
    """Two values agree: numbers when they differ by at most ``tolerance`` relative to the
    earlier one's magnitude (NaN only with NaN), anything else when equal."""
    numeric = (int, float)
    if isinstance(earlier, bool) or isinstance(later, bool) or not (
            isinstance(earlier, numeric) and isinstance(later, numeric)):
        return earlier == later
    if math.isnan(earlier) or math.isnan(later):
        return math.isnan(earlier) and math.isnan(later)
    return earlier == later or abs(later - earlier) <= tolerance * abs(earlier)


def _flatten(node, prefix: str, out: dict) -> None:
    if isinstance(node, dict):
        for key, value in node.items():
            _flatten(value, f"{prefix}/{key}" if prefix else str(key), out)
        if not node:
            out[prefix] = {}
    elif isinstance(node, list):
        for index, value in enumerate(node):
            _flatten(value, f"{prefix}/{index}", out)
        if not node:
            out[prefix] = []
    else:
        out[prefix] = node


ABSENT = "(absent)"


def differences(earlier: dict, later: dict, tolerance: float) -> list[tuple[str, object, object]]:
    """Every value of two documents that does not :func:`agree`, by its path
    (``runs/0/gears/1/values/3/value``), in path order: (path, earlier, later), with
    :data:`ABSENT` for a value only one of them has."""
    then, now = {}, {}
    _flatten(earlier, "", then)
    _flatten(later, "", now)
    return [(path, then.get(path, ABSENT), now.get(path, ABSENT))
            for path in sorted(set(then) | set(now))
            if not agree(then.get(path, ABSENT), now.get(path, ABSENT), tolerance)]


def compare(current: dict, baseline: dict, tolerance: float) -> list[Change]:
    """The changes from ``baseline`` to ``current`` (both results documents), in path order."""
    changes = []
    now, then = numbers(current), numbers(baseline)
    for path in sorted(set(now) | set(then)):
        if path not in then:
            changes.append(Change("added", path, None, now[path][0], "not in the baseline"))
        elif path not in now:
            changes.append(Change("removed", path, then[path][0], None, "only in the baseline"))
        else:
            (a, unit_a), (b, unit_b) = now[path], then[path]
            if unit_a != unit_b:
                changes.append(Change("unit changed", path, f"{b} {unit_b}", f"{a} {unit_a}",
                                      "the unit changed"))
            elif (a is None) != (b is None):
                changes.append(Change("drifted", path, b, a, "a value appeared or vanished"))
            elif a is not None and not agree(b, a, tolerance):
                relative = (a - b) / abs(b) if b else math.inf
                changes.append(Change("drifted", path, b, a,
                                      f"{100 * relative:+.4g} % (tolerance "
                                      f"{100 * tolerance:g} %)"))
    _compare_labels(changes, "criterion", verdicts(baseline), verdicts(current),
                    "verdict changed")
    _compare_labels(changes, "finding", findings(baseline), findings(current),
                    "severity changed")
    _compare_labels(changes, "campaign", {"outcome": baseline.get("outcome")},
                    {"outcome": current.get("outcome")}, "outcome changed")
    return changes


def read_baseline(path: str | Path) -> dict:
    """A results document from ``path``; bad input names the file and what is wrong."""
    path = Path(path)
    try:
        document = load_json(path)
    except JsonSourceError as error:
        raise CertkitInputError.single(str(path), error.line, "--baseline",
                                       f"the baseline: {error.message}") from None
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        found = document.get("format") if isinstance(document, dict) else type(document).__name__
        raise CertkitInputError.single(str(path), None, "format",
                                       f"expected a certkit results file ({FORMAT}), found "
                                       f"{shown(found)}")
    for key in ("design", "requirement_sets", "runs", "verdicts", "findings"):
        if not isinstance(document.get(key, []), list):
            raise CertkitInputError.single(str(path), None, key,
                                           f"expected a list, found "
                                           f"{type(document[key]).__name__}")
    try:
        values = numbers(document)
        verdicts(document)
        findings(document)
    except (KeyError, TypeError, AttributeError) as error:
        raise CertkitInputError.single(str(path), None, "--baseline",
                                       f"not a complete certkit results file: {error!r} is "
                                       f"missing or malformed") from None
    for key, (value, _) in values.items():
        number = isinstance(value, (int, float)) and not isinstance(value, bool)
        # NaN and ±inf fail the comparison, and so does an integer beyond any float
        if value is not None and not (number and abs(value) <= sys.float_info.max):
            raise CertkitInputError.single(str(path), None, key,
                                           f"expected a finite number or null, found "
                                           f"{value!r}")
    for key in ("verdicts", "findings"):
        for item in document.get(key, []):
            if not isinstance(item.get("id"), str):
                raise CertkitInputError.single(str(path), None, f"{key}[].id",
                                               f"expected text, found {item.get('id')!r}")
    return document
