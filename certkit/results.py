"""The evidence record: computed values with their source, verdicts and findings.

Every number certkit reports is a :class:`Value`: SI magnitude, SI unit, the
clause or equation it comes from and the inputs it was computed from.  The report,
results.json and the CSV tables are all rendered from these records.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

PASS, FAIL, NOT_SHOWN = "PASS", "FAIL", "NOT SHOWN"
#: Relative tolerance at which a criterion's value and limit count as equal ("not less
#: than" holds at equality).  It absorbs the float64 round-off of unit conversions (645 lb·g0
#: against 645 lbf, each taken through N: about 10^-16 per operation) and is coarser than
#: that by seven orders; a criterion never applies more than half a unit in the last digit
#: of the typed value it turns on (compliance.at_least), so a value typed with more than nine
#: significant figures is still resolved to its last digit.
EQUALITY_TOLERANCE = 1e-9
#: The ``format`` of results.json; a baseline or an archive of another format is refused.
RESULTS_FORMAT = "certkit-results/1"


@dataclass(frozen=True)
class Value:
    """One computed or declared number with its provenance.

    Attributes
    ----------
    key : str
        Stable machine name (``h_req``).
    label : str
        What it is, in words.
    symbol : str
        Symbol used in the formula.
    value : float or None
        Magnitude in ``unit`` (SI); None when it cannot be computed (``note`` says why).
    unit : str
        SI unit of ``value`` ("1" for ratios).
    kind : str
        Physical kind, selects the display unit (length, force, ...; "ratio").
    source : str
        Clause or equation: ``14 CFR 23.725(a)``, ``certkit E1 (energy integral)``,
        ``spec`` for a declared input, ``reported`` for a value quoted from a source.
    formula : str
        The formula as written in the report.
    inputs : dict
        Symbol -> where the input came from (spec key or another value's key).
    note : str or None
        Bound applied, reason it is missing, assumption made.
    typed : str or None
        For a value typed in the spec (declared or reported), the text as typed
        (``"831.92 kgf"``): a person reads it as typed, never re-rounded.
    """

    key: str
    label: str
    symbol: str
    value: float | None
    unit: str
    kind: str
    source: str
    formula: str = ""
    inputs: dict = field(default_factory=dict)
    note: str | None = None
    typed: str | None = None

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class Verdict:
    """The outcome of one criterion, for one run/gear or for the campaign."""

    id: str
    requirement_set: str
    criterion: str
    clause: str
    title: str
    formula: str
    run: str | None
    gear: str | None
    verdict: str
    value: float | None = None
    limit: float | None = None
    margin: float | None = None
    unit: str = "1"
    kind: str = "ratio"
    comparison: str = "≥"
    reason: str = ""
    to_confirm: bool = False
    #: for a verdict other than PASS: what is missing or short, in a few words shared by
    #: every verdict it holds back (the cover page lists each once), and what would show it
    shortfall: str = ""
    remedy: str = ""
    #: the margin's measurement uncertainty and the statement of conformity under the
    #: campaign's decision rule (certkit.compliance.verdict_uncertainty.VerdictUncertainty)
    uncertainty: object | None = None

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class Finding:
    """A data-quality or audit observation a reviewer would raise."""

    id: str
    check: str
    severity: str  # "error", "warning" or "info"
    run: str | None
    gear: str | None
    message: str
    values: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class Unchecked:
    """A data-quality check that could not run on what the campaign gives, and why."""

    check: str
    where: str | None   # the run, gear unit or run/gear it could not run for; None: anywhere
    reason: str

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class Comparison:
    """A value a source reported beside certkit's recomputation of it."""

    run: str | None
    gear: str | None
    quantity: str
    kind: str
    unit: str
    reported: float
    reported_text: str
    recomputed: float | None
    difference: float | None
    tolerance: float | None
    agrees: bool | None
    basis: str

    def as_dict(self) -> dict:
        return asdict(self)
