"""The record of a blind check of the gap diagnosis, as a campaign input.

The batteries in benchmarks/ (``blind_independent.py``, ``blind_own.py``) run the diagnosis
on synthetic campaigns whose withheld effect is known and write what they measured as JSON
(``kind: "certkit blind check"``).  A campaign
names that file in ``model.gap.blind_check``; it is then an input like a data file (hashed,
attached to the PDF) and the report's gap section summarises it.  This module is the
record's schema: one place that reads and checks it.

Fractions are fractions here (0.9, not 90 %); the report shows them as percentages.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from certkit.errors import shown
from certkit.spec.jsonsource import JsonSourceError, load_json

KIND = "certkit blind check"

#: Metric key -> (label, definition in words), in the order the report shows them.
METRICS = {
    "top1": ("top-1 accuracy",
             "share of the single-effect cases (effect/noise ≥ 2) whose first named effect is "
             "the withheld one"),
    "exact": ("exact answer",
              "share of the same cases whose answer is the withheld effect and nothing else"),
    "false_attribution": ("false attribution",
                          "share of the no-effect cases that did not end in an abstention "
                          "(an effect named, a tie declared, or a failure)"),
    "set_precision": ("set precision",
                      "on the two-effect cases, share of the named effects that are among the "
                      "withheld ones"),
    "set_recall": ("set recall",
                   "on the two-effect cases, share of the withheld effects that were named"),
    "set_recall_or_tie": ("set recall or stated undecided",
                          "on the two-effect cases, share of the withheld effects that were "
                          "named or stated undecided beside the named one (the answer says "
                          "the records cannot tell whether it is present too)"),
    "median_shrink": ("median held-out shrink",
                      "median over the single-effect cases (effect/noise ≥ 2) of the held-out "
                      "load RMSE shrink 1 − RMSE(with the named effects)/RMSE(nominal), "
                      "against the noisy measurement; an abstention shrinks 0"),
    "median_gap_closed": ("median share of the gap closed",
                          "as the shrink, with the held-out load RMSE taken against the "
                          "noise-free truth: the part of the error a model can remove"),
    "median_shrink_pairs": ("median held-out shrink, two-effect cases",
                            "as the median shrink, over the two-effect cases"),
    "harm_rate": ("harm rate",
                  "of the cases in which an effect was named, the share in which it made the "
                  "held-out load error worse"),
    "harm_any_channel": ("harm on any channel",
                         "as the harm rate, counting a case when the held-out error of any "
                         "channel (load, stroke, tyre) grew"),
    "abstention_out_of_library": ("abstention outside the library",
                                  "share of the cases whose withheld effect has no candidate "
                                  "in the library (abstaining is right) that ended in an "
                                  "abstention"),
    "outside_library_answered": ("outside the library, answered right",
                                 "share of the cases whose withheld effect has no candidate "
                                 "in the library that ended in an abstention or, where the "
                                 "record defines it so, in the library effect the withheld "
                                 "one reads as within the noise"),
    "median_own_gap_closed": ("median share of its own gap closed",
                              "median over the single-effect cases named right (effect/noise "
                              "≥ 2) of the share of the held-out load gap the withheld effect "
                              "makes (against the noise-free truth, beyond the floor the "
                              "nuisance physics leaves) that the named effect closes"),
}


def template_fingerprint(campaign) -> str:
    """SHA-256 of the spec's content (canonical JSON of the validated spec) without
    ``model.gap.blind_check`` and ``model.gap.sealed_blind_check``, without the data-quality
    audit's thresholds (``audit``) and without the measurement uncertainties and decision
    rule (``uncertainty``), none of which the diagnosis reads: the same before and after the
    spec names its blind-check records, or after a threshold of the audit or a stated
    uncertainty is added or changed, different after any other change to the spec."""
    content = campaign.spec.model_dump(mode="json")
    content.pop("audit", None)
    content.pop("uncertainty", None)
    gap = (content.get("model") or {}).get("gap")
    if isinstance(gap, dict):
        gap.pop("blind_check", None)
        gap.pop("sealed_blind_check", None)
    text = json.dumps(content, sort_keys=True, ensure_ascii=False, separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


class _Record(BaseModel):
    # written by another program, possibly a newer certkit: extra keys are ignored, the
    # documented ones must be present and of the right type
    model_config = ConfigDict(extra="ignore", frozen=True, strict=True, allow_inf_nan=False)


class Template(_Record):
    spec: str
    sha256: str
    gear: str
    code: str | None = None     # certkit.gap.code.code_fingerprint() of the certkit that made it


class Provenance(_Record):
    """Who ran a blind check's cases, or scored them: certkit's version and commit, the
    diagnosis code's fingerprint and per-file hashes (:mod:`certkit.gap.code`), the battery
    code's per-file hashes (under benchmarks/), the date and the command."""

    certkit: str
    code: str | None
    commit: str | None = None
    files: dict[str, str] | None = None
    battery_files: dict[str, str] | None = None
    date: str | None = None
    command: str | None = None


class Metric(_Record):
    value: float | None
    count: int | None = Field(ge=0)
    cases: int = Field(ge=0)
    target: float | None
    direction: Literal["at least", "at most"] | None
    met: bool | None
    interval: list[float] | None = None   # 95 % Wilson interval of count/cases: [low, high]

    @model_validator(mode="after")
    def _consistent(self):
        if self.interval is not None and not (len(self.interval) == 2 and
                                              0 <= self.interval[0] <= self.interval[1] <= 1):
            raise ValueError(f"interval must be (low, high) with 0 ≤ low ≤ high ≤ 1, got "
                             f"{list(self.interval)}")
        if (self.target is None) != (self.direction is None):
            raise ValueError("target and direction go together (both or neither)")
        if self.met is not None and self.met != self.judged:
            raise ValueError(f"met is {str(self.met).lower()}, but the value {self.value} is "
                             f"{'not ' if self.met else ''}{self.direction} the target "
                             f"{self.target}")
        return self

    @property
    def judged(self) -> bool | None:
        """Whether the value meets its target (None: no target, or no value)."""
        if self.target is None or self.value is None:
            return None
        return (self.value >= self.target if self.direction == "at least"
                else self.value <= self.target)


class CurvePoint(_Record):
    ratio: float = Field(gt=0)
    cases: int = Field(ge=0)
    top1: float | None
    median_shrink: float | None


class Confusion(_Record):
    truths: list[str]
    named: list[str]
    counts: list[list[int]]

    @model_validator(mode="after")
    def _shape(self):
        if len(self.counts) != len(self.truths) or any(len(row) != len(self.named)
                                                       for row in self.counts):
            raise ValueError(f"counts must have one row per truth ({len(self.truths)}) and "
                             f"one column per answer ({len(self.named)})")
        return self


class FormRow(_Record):
    form: str
    label: str
    effect: str | None          # the library effect it belongs to; None: outside the library
    cases: int = Field(ge=0)
    right: int = Field(ge=0)
    scored: int = Field(ge=0)
    right_scored: int = Field(ge=0)
    median_peak_load_change_N: float | None = None
    median_peak_load_change_share: float | None = None


class BlindCheckRecord(_Record):
    kind: Literal["certkit blind check"]
    certkit: str
    #: what the withheld truths were simulated by (None: certkit's own battery, its own
    #: force laws in other forms)
    truths: str | None = None
    template: Template
    command: str
    settings: dict[str, Any]
    metrics: dict[str, Metric]
    curve: list[CurvePoint]
    confusion: Confusion
    cases: list[dict[str, Any]] = []
    #: which battery the cases come from: "development" (the battery the diagnosis's rules
    #: were tuned on, so its figures are in-sample) or "sealed" (drawn from ranges never run
    #: before, run once per release of the diagnosis); None: not stated (older records)
    battery: Literal["development", "sealed"] | None = None
    #: who ran the cases; a rescore keeps it (absent from records made before it was kept
    #: apart: :attr:`cases_run_by` then falls back on the template's code)
    run_by: Provenance | None = None
    #: who computed the metrics from the cases (the same as run_by unless rescored)
    scored_by: Provenance | None = None
    #: per truth form of an independent battery: its cases and how many were answered
    #: right (absent from certkit's own battery)
    forms: list[FormRow] = []
    #: metric key -> its definition as this record counts it, where that is not (or no
    #: longer) the general one of :data:`METRICS`
    definitions: dict[str, str] = {}

    @property
    def cases_run_by(self) -> Provenance:
        """Who ran the cases: ``run_by``, or for an older record what its template says
        (the code fingerprint, without per-file hashes, date or commit)."""
        if self.run_by is not None:
            return self.run_by
        return Provenance(certkit=self.certkit, code=self.template.code, command=self.command)

    @model_validator(mode="after")
    def _scored_from(self):
        value = self.settings.get("scored_from")
        if value is not None and (isinstance(value, bool) or
                                  not isinstance(value, (int, float))):
            raise ValueError(f"settings.scored_from must be a number, got {value!r}")
        return self


class BlindRecordError(ValueError):
    """The file is not a readable blind-check record; ``problems``: (key, message)."""

    def __init__(self, problems: list[tuple[str, str]]):
        self.problems = problems
        super().__init__("; ".join(f"{k}: {m}" if k else m for k, m in problems))


def read_blind_check(path: Path) -> BlindCheckRecord:
    """Read and check a blind-check record.

    Raises
    ------
    BlindRecordError
        Naming each key that is missing or wrong.
    """
    try:
        raw = load_json(path)
    except JsonSourceError as error:
        raise BlindRecordError([("", error.message)]) from None
    if not isinstance(raw, dict) or raw.get("kind") != KIND:
        found = raw.get("kind") if isinstance(raw, dict) else type(raw).__name__
        raise BlindRecordError([("kind", f"expected {KIND!r} (a file written by "
                                         f"benchmarks/blind_independent.py), got {shown(found)}")])
    try:
        return BlindCheckRecord.model_validate(raw)
    except ValidationError as error:
        problems = []
        for item in error.errors():
            key = ".".join(str(part) for part in item["loc"])
            message = item["msg"]
            if message.startswith("Value error, "):
                message = message.removeprefix("Value error, ")
            problems.append((key, message[0].lower() + message[1:]))
        raise BlindRecordError(problems) from None
