"""Reading a run's logger file into SI channels, with the data checks a test engineer expects.

Sign conventions after a column's ``sign``/``scale``/``offset`` are applied:

* vertical load: positive when the tyre presses on the platform [N];
* strut stroke, tyre deflection: positive in compression [m];
* drop-mass acceleration: positive upward [m/s^2] (a decelerating falling mass reads positive);
* drop-mass displacement: positive downward, i.e. distance fallen [m].

Problems that make a file unusable (missing column, time not increasing, unreadable
file) are input errors.  Problems a test engineer may knowingly accept (sample rate
off, gaps, clipping, implausible values) are input errors too unless the run lists a
waiver for that check with a reason; a waived problem becomes a data-quality finding.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import CertkitInputError, Problem, key_path
from .spec import Column, GearUnit, Run
from .units import STANDARD_GRAVITY, scale_to_si
from .yamlsource import line_of

# Plausibility limits (not regulatory): values outside are almost surely a unit,
# scale or sign error in the channel mapping.
PLAUSIBLE_LOAD_FACTOR = 20.0          # peak load above 20 x static weight of the unit
PLAUSIBLE_NEGATIVE_LOAD = 0.10        # load below -10 % of the unit's static weight
PLAUSIBLE_NEGATIVE_TRAVEL = 0.005     # stroke or deflection below -5 mm
PLAUSIBLE_STROKE_OVER_DESIGN = 1.2    # stroke above 1.2 x design stroke
PLAUSIBLE_ACCELERATION = 50.0 * STANDARD_GRAVITY
CLIP_RUN = 5                          # this many equal samples at a channel's maximum
GAP_FACTOR = 1.5                      # a time step 1.5 x the nominal one is a gap


#: The recorded channels of a gear unit, as reports and messages name them.
CHANNEL_LABELS = {"load": "vertical load", "stroke": "strut stroke", "tyre": "tyre deflection"}


@dataclass
class GearSeries:
    """One gear unit's channels in SI (None where the run does not record it)."""

    load: np.ndarray
    stroke: np.ndarray | None
    tyre: np.ndarray | None


@dataclass
class DataFinding:
    """A waived data problem, kept for the data-quality audit."""

    check: str
    message: str
    reason: str


@dataclass
class RunSeries:
    file: str
    time: np.ndarray
    gears: dict[str, GearSeries]
    acceleration: np.ndarray | None
    acceleration_reference: str | None
    displacement: np.ndarray | None
    declared_rate: float
    measured_rate: float
    findings: list[DataFinding] = field(default_factory=list)


class _Checker:
    """Collects problems for one run; waivable ones become findings when waived."""

    def __init__(self, spec_file: str, run_index: int, run: Run, data_file: str, lines):
        self.spec_file, self.run_index, self.run = spec_file, run_index, run
        self.data_file, self.lines = data_file, lines
        self.errors: list[Problem] = []
        self.findings: list[DataFinding] = []
        self.waivers = {w.check: w.reason for w in run.data.waivers}

    def key(self, *parts) -> tuple:
        return ("runs", self.run_index, "data") + parts

    def spec_error(self, location: tuple, message: str) -> None:
        self.errors.append(Problem(self.spec_file, line_of(self.lines, location),
                                   key_path(location), message))

    def data_error(self, row: int | None, location: tuple, message: str) -> None:
        self.errors.append(Problem(self.data_file, row, key_path(location), message))

    def waivable(self, check: str, row: int | None, location: tuple, message: str) -> None:
        if check in self.waivers:
            where = f"{self.data_file}:{row}" if row else self.data_file
            self.findings.append(DataFinding(check, f"{where}: {message}", self.waivers[check]))
        else:
            self.data_error(row, location, f"{message} (if this is known and accepted, add "
                                           f"a waiver {{check: {check}, reason: ...}} to "
                                           f"runs[{self.run_index}].data.waivers)")

    def raise_if_errors(self) -> None:
        if self.errors:
            raise CertkitInputError(self.errors)


def _read_table(path: Path, display: str):
    """Read CSV or Parquet; returns the frame and the file line of its first data row."""
    import warnings

    import pandas as pd  # imported here: a campaign of reported values needs no pandas

    def fail(message: str, line: int | None = None) -> CertkitInputError:
        return CertkitInputError.single(display, line, "", message)

    suffix = path.suffix.lower()
    if suffix not in (".csv", ".parquet", ".pq"):
        raise fail(f"unsupported data format {suffix!r} (expected .csv or .parquet)")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", pd.errors.ParserWarning)
            if suffix == ".csv":
                frame, first_line = pd.read_csv(path, index_col=False), 2
            else:
                frame, first_line = pd.read_parquet(path), 0
    except pd.errors.ParserWarning:
        raise fail("the data rows have more fields than the header line") from None
    except pd.errors.EmptyDataError:
        raise fail("the data file is empty") from None
    except pd.errors.ParserError as exc:
        match = re.search(r"Expected (\d+) fields in line (\d+), saw (\d+)", str(exc))
        if match:
            header, line, seen = match.groups()
            raise fail(f"line {line} has {seen} fields, the header has {header}: check that "
                       f"row for stray or decimal commas, and the file for preamble lines "
                       f"above the header", int(line)) from None
        raise fail(f"cannot read data file: {exc}") from None
    except Exception as exc:  # pandas and pyarrow raise many types for malformed files
        raise fail(f"cannot read data file: {exc}") from None
    if len(frame.columns) == 1 and ";" in str(frame.columns[0]):
        raise fail("the file appears to use ';' as separator; certkit reads comma-separated "
                   "CSV")
    if suffix == ".csv":
        import csv

        with path.open(newline="", encoding="utf-8-sig", errors="replace") as handle:
            header = next(csv.reader(handle), [])
        repeated = sorted({name for name in header if header.count(name) > 1})
        if repeated:
            raise fail(f"column name(s) repeated in the header: {', '.join(repeated)}", 1)
    return frame, first_line


def _row(first_line: int, index: int) -> int | None:
    """File line of data row ``index`` (CSV), or None for formats without lines."""
    return first_line + index if first_line else None


def read_run(path: Path, display: str, spec_file: str, run_index: int, run: Run,
             gear_units: dict[str, GearUnit], default_rate: float | None, lines,
             tolerance: float) -> RunSeries:
    """Read and check one run's data file; returns SI channels.

    Raises
    ------
    CertkitInputError
        Naming the data file and row, or the spec line and key, for every problem.
    """
    import pandas as pd

    data = run.data
    frame, first_line = _read_table(path, display)
    check = _Checker(spec_file, run_index, run, display, lines)

    declared = data.sampling_rate.si if data.sampling_rate else default_rate
    if declared is None:
        check.spec_error(check.key("sampling_rate"),
                         "no sampling rate declared here or in instrumentation.sampling_rate")

    # --- columns present
    wanted: list[tuple[tuple, Column]] = [(("time",), data.time)]
    for gear_id, channels in data.gears.items():
        for name in ("vertical_load", "strut_stroke", "tyre_deflection"):
            column = getattr(channels, name)
            if column is not None:
                wanted.append((("gears", gear_id, name), column))
    for name in ("drop_mass_acceleration", "drop_mass_displacement"):
        column = getattr(data, name)
        if column is not None:
            wanted.append(((name,), column))
    for location, column in wanted:
        if column.column not in frame.columns:
            check.spec_error(check.key(*location, "column"),
                             f"column {column.column!r} not found in {display} "
                             f"(columns: {', '.join(map(str, frame.columns))})")
    check.raise_if_errors()
    if len(frame) < 3:
        check.spec_error(check.key("file"), f"{display} has {len(frame)} data row(s); at "
                                            f"least 3 are needed")
        check.raise_if_errors()

    # --- time base
    if pd.api.types.is_datetime64_any_dtype(frame[data.time.column]):
        check.spec_error(check.key("time", "column"),
                         f"column {data.time.column!r} holds timestamps; certkit needs the time "
                         f"as a number in {data.time.unit}")
        check.raise_if_errors()
    raw_time = pd.to_numeric(frame[data.time.column], errors="coerce").to_numpy(dtype=float)
    time = raw_time * scale_to_si(data.time.unit, "time")
    bad = np.flatnonzero(~np.isfinite(time))
    if bad.size and isinstance(frame[data.time.column].iloc[int(bad[0])], str):
        sample = frame[data.time.column].iloc[int(bad[0])]
        check.data_error(_row(first_line, int(bad[0])), check.key("time", "column"),
                         f"column {data.time.column!r} holds text such as {sample!r}; "
                         f"certkit needs the time as a number in {data.time.unit}")
        check.raise_if_errors()
    if bad.size:
        check.data_error(_row(first_line, int(bad[0])), check.key("time", "column"),
                         f"time is missing or not a number ({bad.size} rows)")
        check.raise_if_errors()
    steps = np.diff(time)
    not_increasing = np.flatnonzero(steps <= 0)
    if not_increasing.size:
        i = int(not_increasing[0]) + 1
        word = "duplicated" if steps[i - 1] == 0 else "not increasing"
        check.data_error(_row(first_line, i), check.key("time", "column"),
                         f"time {word}: {raw_time[i]:g} {data.time.unit} after "
                         f"{raw_time[i - 1]:g} {data.time.unit}")
        check.raise_if_errors()
    nominal = float(np.median(steps))
    measured_rate = 1.0 / nominal
    if declared and abs(measured_rate - declared) > tolerance * declared:
        check.waivable("sample_rate", None, check.key("time", "column"),
                       f"sample rate {measured_rate:.6g} Hz differs from the declared "
                       f"{declared:.6g} Hz by more than {tolerance:.0%}")
    gaps = np.flatnonzero(steps > GAP_FACTOR * nominal)
    if gaps.size:
        i = int(gaps[0]) + 1
        check.waivable("gaps", _row(first_line, i), check.key("time", "column"),
                       f"{gaps.size} gap(s) in time; first: {steps[i - 1] * 1e3:.6g} ms "
                       f"before this row (nominal step {nominal * 1e3:.6g} ms)")

    def channel(location: tuple, column: Column, kind: str) -> np.ndarray:
        raw = pd.to_numeric(frame[column.column], errors="coerce").to_numpy(dtype=float)
        missing = np.flatnonzero(~np.isfinite(raw))
        if missing.size:
            check.waivable("gaps", _row(first_line, int(missing[0])), check.key(*location, "column"),
                           f"{missing.size} missing or non-numeric value(s) in column "
                           f"{column.column!r}")
        if column.full_scale is not None:
            at_limit = np.flatnonzero(np.abs(raw) >= abs(column.full_scale) * 0.999)
            if at_limit.size:
                check.waivable("clipping", _row(first_line, int(at_limit[0])),
                               check.key(*location, "column"),
                               f"column {column.column!r} reaches its full scale "
                               f"{column.full_scale:g} {column.unit} ({at_limit.size} samples)")
        finite = raw[np.isfinite(raw)]
        if finite.size and column.full_scale is None:
            top = finite.max()
            run_length = _longest_run(raw == top)
            if run_length >= CLIP_RUN and top != 0:
                first = int(np.flatnonzero(raw == top)[0])
                check.waivable("clipping", _row(first_line, first), check.key(*location, "column"),
                               f"column {column.column!r} is flat at its maximum {top:g} "
                               f"{column.unit} for {run_length} samples (clipped or saturated?)")
        with np.errstate(over="ignore", invalid="ignore"):  # overflow is reported below
            values = column.sign * column.scale * (raw - column.offset) * scale_to_si(
                column.unit, kind)
        return values

    gears: dict[str, GearSeries] = {}
    for gear_id, channels in data.gears.items():
        unit = gear_units[gear_id]
        base = ("gears", gear_id)
        load = channel(base + ("vertical_load",), channels.vertical_load, "force")
        stroke = tyre = None
        if channels.strut_stroke is not None:
            stroke = channel(base + ("strut_stroke",), channels.strut_stroke, "length")
        if channels.tyre_deflection is not None:
            tyre = channel(base + ("tyre_deflection",), channels.tyre_deflection, "length")
        weight = unit.static_weight.si
        _plausible(check, first_line, base + ("vertical_load",), load,
                   -PLAUSIBLE_NEGATIVE_LOAD * weight, PLAUSIBLE_LOAD_FACTOR * weight, "N")
        if stroke is not None:
            _plausible(check, first_line, base + ("strut_stroke",), stroke,
                       -PLAUSIBLE_NEGATIVE_TRAVEL,
                       PLAUSIBLE_STROKE_OVER_DESIGN * unit.design_stroke.si, "m")
        if tyre is not None:
            limit = unit.tyre.diameter.si / 2 if unit.tyre.diameter else 0.5
            _plausible(check, first_line, base + ("tyre_deflection",), tyre,
                       -PLAUSIBLE_NEGATIVE_TRAVEL, limit, "m")
        gears[gear_id] = GearSeries(load, stroke, tyre)

    acceleration = displacement = None
    if data.drop_mass_acceleration is not None:
        acceleration = channel(("drop_mass_acceleration",), data.drop_mass_acceleration,
                               "acceleration")
        _plausible(check, first_line, ("drop_mass_acceleration",), acceleration,
                   -PLAUSIBLE_ACCELERATION, PLAUSIBLE_ACCELERATION, "m/s^2")
    if data.drop_mass_displacement is not None:
        displacement = channel(("drop_mass_displacement",), data.drop_mass_displacement, "length")

    check.raise_if_errors()

    # Rows with a missing value can only reach here when the 'gaps' check was waived:
    # drop them everywhere, and say so in the waived finding.
    arrays = [time] + [a for g in gears.values() for a in (g.load, g.stroke, g.tyre)
                       if a is not None] + [a for a in (acceleration, displacement) if a is not None]
    keep = np.logical_and.reduce([np.isfinite(a) for a in arrays])
    if not keep.all():
        dropped = int((~keep).sum())
        if "gaps" not in check.waivers:  # non-finite values not from the file (overflow)
            check.data_error(None, check.key("file"), f"{dropped} row(s) are not finite after "
                                                      f"applying unit, scale and offset")
            check.raise_if_errors()
        check.findings.append(DataFinding(
            "gaps", f"{display}: {dropped} row(s) with missing values removed before analysis",
            check.waivers["gaps"]))
        time = time[keep]
        for g in gears.values():
            g.load = g.load[keep]
            g.stroke = None if g.stroke is None else g.stroke[keep]
            g.tyre = None if g.tyre is None else g.tyre[keep]
        acceleration = None if acceleration is None else acceleration[keep]
        displacement = None if displacement is None else displacement[keep]
    return RunSeries(
        file=display, time=time, gears=gears, acceleration=acceleration,
        acceleration_reference=(data.drop_mass_acceleration.reference
                                if data.drop_mass_acceleration else None),
        displacement=displacement, declared_rate=declared, measured_rate=measured_rate,
        findings=check.findings)


def _longest_run(mask: np.ndarray) -> int:
    best = current = 0
    for flag in mask:
        current = current + 1 if flag else 0
        best = max(best, current)
    return best


def _plausible(check: _Checker, first_line: int, location: tuple, values: np.ndarray,
               low: float, high: float, unit: str) -> None:
    finite = np.isfinite(values)
    outside = np.flatnonzero(finite & ((values < low) | (values > high)))
    if outside.size:
        i = int(outside[0])
        check.waivable("implausible_range", _row(first_line, i), check.key(*location, "column"),
                       f"value {values[i]:.6g} {unit} (after unit, scale, sign and offset) is "
                       f"outside the plausible range [{low:.6g}, {high:.6g}] {unit} "
                       f"({outside.size} samples); check the channel mapping")
