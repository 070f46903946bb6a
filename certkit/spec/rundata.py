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
A sample rate that another time unit would make agree with the declared one (time in ms
declared as s) is a unit slip in the spec, not a rate to waive: an input error naming
the unit that fits.

CSV files: the field separator is read from the header line, a comma (RFC 4180), a
semicolon or a tab, whichever it holds most (see :func:`_csv_layout`).  A file separated
by semicolons or tabs may write its numbers with decimal commas, as spreadsheets in many
locales export them; a comma-separated one cannot (a decimal comma would split every
number in two, so such a file is refused with the line that shows it).  A file that is
not comma-separated with decimal points is read and the layout found is stated in the
data-quality audit (``RunSeries.layout``).
"""

from __future__ import annotations

import csv
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from certkit.display import number
from certkit.errors import (ECHO_LIMIT, CertkitInputError, Problem, escaped, key_path,
                            shown)
from certkit.spec.schema import Column, GearUnit, Run, TimeColumn
from certkit.spec.yamlsource import first_non_utf8, line_of
from certkit.units import SI_RANGE, STANDARD_GRAVITY, convert, scale_to_si

# Plausibility limits (not regulatory): values outside are almost surely a unit,
# scale or sign error in the channel mapping.
PLAUSIBLE_LOAD_FACTOR = 20.0          # peak load above 20 x static weight of the unit
PLAUSIBLE_NEGATIVE_LOAD = 0.10        # load below -10 % of the unit's static weight
PLAUSIBLE_NEGATIVE_TRAVEL = 0.005     # stroke or deflection below -5 mm
PLAUSIBLE_STROKE_OVER_DESIGN = 1.2    # stroke above 1.2 x design stroke
PLAUSIBLE_ACCELERATION = 50.0 * STANDARD_GRAVITY
CLIP_RUN = 5                          # this many equal samples at a channel's maximum
GAP_FACTOR = 1.5                      # a time step 1.5 x the nominal one is a gap
#: Sample rates a drop-test logger records at [Hz]: outside, the time column is not a time
#: base (steps of 1e-200 s), whatever rate was declared or waived.
PLAUSIBLE_RATE = (1.0, 1.0e8)
MIN_ROWS = 3                          # the fewest complete rows a run can be assessed from
SHOWN_COLUMNS = 12                    # column names listed in a message, at most

#: Field separators recognised in a CSV header line, with their names in messages.
SEPARATORS = {",": "comma", ";": "semicolon", "\t": "tab"}
#: Units a time column may be in, tried when its steps disagree with the declared rate.
TIME_UNITS = ("us", "ms", "s", "min", "h")


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
    #: how a CSV file was read when it is not comma-separated with decimal points,
    #: e.g. "semicolon-separated with decimal commas" (None otherwise)
    layout: str | None = None


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


def _number_field(body: str, separator: str, mark: str) -> int | None:
    """Index in ``body`` of the first field that is a number written with the decimal
    ``mark`` (the whole field: ``12,5``, ``-0.5``, ``1,5e3``), or None."""
    if mark not in body:  # the quick answer for most files, which use one mark throughout
        return None
    sep, mark = re.escape(separator), re.escape(mark)
    found = re.search(rf"(?:^|{sep}) *[-+]?(?:\d+{mark}\d*|{mark}\d+)(?:[eE][-+]?\d+)? *"
                      rf"(?={sep}|\r?$)", body, re.MULTILINE)
    return found.start() if found else None


def _csv_layout(path: Path, display: str) -> tuple[str, str]:
    """The field separator and the decimal mark of a CSV file.

    The separator is the one of ',', ';' and tab that the header line holds most often
    (a comma on a tie, so a one-column file is read as RFC 4180 CSV).  A comma-separated
    file has decimal points.  Any other file has decimal commas when one of its fields is
    a number written with a decimal comma; a file that writes some numbers with a decimal
    comma and others with a decimal point is refused, naming both lines.
    """
    with path.open(encoding="utf-8-sig", errors="replace", newline="") as handle:
        header = handle.readline()
        separator = max(SEPARATORS, key=header.count)
        body = "" if separator == "," else handle.read()
    comma, point = (_number_field(body, separator, mark) for mark in (",", "."))
    if comma is not None and point is not None:
        first, second = sorted((comma, point))
        lines = [body.count("\n", 0, index) + 2 for index in (first, second)]
        marks = ("a decimal comma", "a decimal point") if comma < point else (
            "a decimal point", "a decimal comma")
        raise CertkitInputError.single(
            display, lines[1], "", f"this {SEPARATORS[separator]}-separated file writes a "
                                   f"number with {marks[0]} on line {lines[0]} and one with "
                                   f"{marks[1]} on line {lines[1]}: write every number with "
                                   f"the same decimal mark")
    return separator, "," if comma is not None else "."


def _field_count_error(path: Path, display: str, separator: str) -> CertkitInputError | None:
    """The first line with more fields than the header, as an input error (None if none)."""

    with path.open(newline="", encoding="utf-8-sig", errors="replace") as handle:
        reader = csv.reader(handle, delimiter=separator)
        header = next(reader, [])
        for row in reader:
            if len(row) > len(header):
                hint = (" (in a comma-separated file a decimal comma splits a number in two: "
                        "write decimal points, or separate the fields with ';')"
                        if separator == "," else "")
                return CertkitInputError.single(
                    display, reader.line_num, "",
                    f"line {reader.line_num} has {len(row)} fields, the header has "
                    f"{len(header)}: check that row for stray separators or decimal "
                    f"commas{hint}, and the file for preamble lines above the header")
    return None


#: The data-file formats certkit reads (by the file's suffix, any case)
DATA_SUFFIXES = (".csv", ".parquet", ".pq")


def _parquet_reader(display: str):
    """pyarrow's Parquet module, or an input error saying how to get it (an optional extra)."""
    try:
        import pyarrow.parquet as pq
    except ImportError:
        raise CertkitInputError.single(display, None, "", "reading a Parquet file needs "
                                       "pyarrow, which is not installed: install certkit's "
                                       "parquet extra (pip install 'certkit[parquet]') or "
                                       "write the file as CSV") from None
    return pq


def _read_table(path: Path, display: str):
    """Read CSV or Parquet; returns the frame, the file line of its first data row and the
    CSV layout when it is not comma-separated with decimal points (else None)."""
    # pandas is imported here, not at the top: it adds about 0.3 s to every start-up
    # (python -X importtime, median of 3), and a campaign of reported values needs none
    import pandas as pd

    def fail(message: str, line: int | None = None) -> CertkitInputError:
        return CertkitInputError.single(display, line, "", message)

    suffix = path.suffix.lower()
    if suffix not in DATA_SUFFIXES:
        raise fail(f"unsupported data format {suffix!r} (expected one of "
                   f"{', '.join(DATA_SUFFIXES)})")
    separator, decimal = _csv_layout(path, display) if suffix == ".csv" else (",", ".")
    pq = None if suffix == ".csv" else _parquet_reader(display)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", pd.errors.ParserWarning)
            if suffix == ".csv":
                frame = pd.read_csv(path, sep=separator, decimal=decimal, index_col=False)
                first_line = 2
                with path.open(newline="", encoding="utf-8-sig", errors="replace") as handle:
                    header = next(csv.reader(handle, delimiter=separator), [])
            else:   # the names first: pyarrow cannot read a file that repeats one

                header, first_line = pq.read_schema(path).names, 0
                frame = None if len(set(header)) < len(header) else pd.read_parquet(path)
    except (pd.errors.ParserWarning, pd.errors.ParserError) as exc:
        raise (_field_count_error(path, display, separator)
               or fail(f"cannot read data file: {exc}")) from None
    except pd.errors.EmptyDataError:
        raise fail("the data file is empty") from None
    except UnicodeDecodeError:
        if suffix == ".csv":
            raise _not_utf8(path, display) from None
        raise fail("a column name or text value is not UTF-8 text; write the file again "
                   "with UTF-8 strings") from None
    except Exception as exc:  # pandas and pyarrow raise many types for malformed files
        raise fail(f"cannot read data file: {exc}") from None
    repeated = sorted({name for name in header if header.count(name) > 1})
    if repeated:
        raise fail(f"column name(s) repeated in the header: {_names(repeated)}",
                   1 if suffix == ".csv" else None)
    if frame.columns.nlevels > 1:
        raise fail(f"column names must be one level of text; this file has "
                   f"{frame.columns.nlevels}-level column names such as "
                   f"{shown(frame.columns[0]) if len(frame.columns) else '()'}")
    frame.columns = [str(name) for name in frame.columns]
    layout = None
    if separator != ",":
        layout = f"{SEPARATORS[separator]}-separated with decimal " + (
            "commas" if decimal == "," else "points")
    return frame, first_line, layout


def _not_utf8(path: Path, display: str) -> CertkitInputError:
    """A CSV file that is not UTF-8 (a spreadsheet's UTF-16 or Latin-1 export): the line
    and byte of the first character that is not, and what to do."""
    content = path.read_bytes()
    line, byte = first_non_utf8(content) or (1, content[0])
    utf16 = " (a UTF-16 file: it starts with a UTF-16 byte-order mark)" if content[:2] in (
        b"\xff\xfe", b"\xfe\xff") else ""
    return CertkitInputError.single(
        display, line, "", f"expected UTF-8 text, found byte 0x{byte:02x} on line "
                           f"{line}{utf16}; save the file as UTF-8 (in a spreadsheet: CSV "
                           f"UTF-8)")


def _names(names) -> str:
    """Column names for a message: each cut to the echo limit, at most SHOWN_COLUMNS."""
    listed = [escaped(name) if len(name) <= ECHO_LIMIT else shown(name)
              for name in map(str, list(names)[:SHOWN_COLUMNS])]
    more = len(names) - SHOWN_COLUMNS
    return ", ".join(listed) + (f", … and {more} more" if more > 0 else "")


def _numbers(values) -> np.ndarray:
    """A column as floats, NaN where a cell is not a number.  A whole number too large for
    a float (a 400-digit cell, read by pandas as a Python integer) is not a number."""
    import pandas as pd  # lazy, as in _read_table

    try:
        return pd.to_numeric(values, errors="coerce").to_numpy(dtype=float)
    except (OverflowError, TypeError, ValueError):
        return np.array([_number(value) for value in values], dtype=float)


def _number(value) -> float:
    try:
        return float(value)
    except (OverflowError, TypeError, ValueError):
        return float("nan")


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
    data = run.data
    frame, first_line, layout = _read_table(path, display)
    check = _Checker(spec_file, run_index, run, display, lines)
    declared = data.sampling_rate.si if data.sampling_rate else default_rate
    if declared is None:
        check.spec_error(check.key("sampling_rate"),
                         "no sampling rate declared here or in instrumentation.sampling_rate")
    _check_columns(check, frame, data, display)
    time, measured_rate = _time_base(check, frame, first_line, data.time, declared, tolerance)
    gears = {gear_id: _gear_series(check, frame, first_line, gear_id, channels,
                                   gear_units[gear_id])
             for gear_id, channels in data.gears.items()}
    acceleration = displacement = None
    if data.drop_mass_acceleration is not None:
        acceleration = _channel(check, frame, first_line, ("drop_mass_acceleration",),
                                data.drop_mass_acceleration, "acceleration")
        _plausible(check, first_line, ("drop_mass_acceleration",), acceleration,
                   -PLAUSIBLE_ACCELERATION, PLAUSIBLE_ACCELERATION, "m/s^2",
                   data.drop_mass_acceleration.unit)
    if data.drop_mass_displacement is not None:
        displacement = _channel(check, frame, first_line, ("drop_mass_displacement",),
                                data.drop_mass_displacement, "length")
    check.raise_if_errors()
    time, acceleration, displacement = _without_incomplete_rows(
        check, display, time, gears, acceleration, displacement)
    return RunSeries(
        file=display, time=time, gears=gears, acceleration=acceleration,
        acceleration_reference=(data.drop_mass_acceleration.reference
                                if data.drop_mass_acceleration else None),
        displacement=displacement, declared_rate=declared, measured_rate=measured_rate,
        findings=check.findings, layout=layout)


def _check_columns(check: _Checker, frame, data, display: str) -> None:
    """Every column the spec names is in the file, and the file has at least 3 rows."""
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
                             f"(columns: {_names(frame.columns)})")
    check.raise_if_errors()
    if len(frame) < MIN_ROWS:
        check.spec_error(check.key("file"), f"{display} has {len(frame)} data row(s); at "
                                            f"least {MIN_ROWS} are needed")
        check.raise_if_errors()


def _time_base(check: _Checker, frame, first_line: int, column: TimeColumn,
               declared: float | None, tolerance: float) -> tuple[np.ndarray, float]:
    """The time column in s, checked (numbers, increasing, the declared rate, no gaps), and
    the sampling rate its median step gives."""
    import pandas as pd  # lazy, as in _read_table

    if pd.api.types.is_datetime64_any_dtype(frame[column.column]):
        check.spec_error(check.key("time", "column"),
                         f"column {column.column!r} holds timestamps; certkit needs the time "
                         f"as a number in {column.unit}")
        check.raise_if_errors()
    raw_time = _numbers(frame[column.column])
    time = raw_time * scale_to_si(column.unit, "time")
    _within_range(check, first_line, ("time",), time, column.column)
    check.raise_if_errors()
    bad = np.flatnonzero(~np.isfinite(time))
    if bad.size and isinstance(frame[column.column].iloc[int(bad[0])], str):
        sample = frame[column.column].iloc[int(bad[0])]
        check.data_error(_row(first_line, int(bad[0])), check.key("time", "column"),
                         f"column {column.column!r} holds text such as {sample!r}; "
                         f"certkit needs the time as a number in {column.unit}")
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
                         f"time {word}: {raw_time[i]:g} {column.unit} after "
                         f"{raw_time[i - 1]:g} {column.unit}")
        check.raise_if_errors()
    nominal = float(np.median(steps))
    measured_rate = 1.0 / nominal
    slip = bool(declared) and abs(measured_rate - declared) > tolerance * declared and \
        _rate_mismatch(check, column, measured_rate, declared, tolerance)
    if not slip and not PLAUSIBLE_RATE[0] <= measured_rate <= PLAUSIBLE_RATE[1]:
        check.data_error(None, check.key("time", "column"),
                         f"the time steps of column {column.column!r} ({nominal:.3g} s) give a "
                         f"sample rate of {measured_rate:.3g} Hz, outside what a drop-test "
                         f"logger records ({PLAUSIBLE_RATE[0]:g} to {PLAUSIBLE_RATE[1]:g} Hz): "
                         f"check the column and its unit")
        check.raise_if_errors()
    gaps = np.flatnonzero(steps > GAP_FACTOR * nominal)
    if gaps.size:
        i = int(gaps[0]) + 1
        check.waivable("gaps", _row(first_line, i), check.key("time", "column"),
                       f"{gaps.size} gap(s) in time; first: {steps[i - 1] * 1e3:.6g} ms "
                       f"before this row (nominal step {nominal * 1e3:.6g} ms)")
    return time, measured_rate


def _channel(check: _Checker, frame, first_line: int, location: tuple, column: Column,
             kind: str) -> np.ndarray:
    """One channel in SI after sign, scale, offset and unit; missing values and clipping
    are waivable problems."""
    raw = _numbers(frame[column.column])
    missing = np.flatnonzero(~np.isfinite(raw))
    if missing.size == raw.size:  # no waiver makes a channel of no numbers a record
        check.data_error(None, check.key(*location, "column"),
                         f"column {column.column!r} holds no number in its {raw.size} rows; if "
                         f"the sensor failed, the run has no {location[-1].replace('_', ' ')} "
                         f"record: take the channel (or the run's data) out of the spec")
        return raw
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
    with np.errstate(over="ignore", invalid="ignore"):  # overflow is reported by the caller
        values = column.sign * column.scale * (raw - column.offset) * scale_to_si(column.unit,
                                                                                  kind)
    _within_range(check, first_line, location, values, column.column)
    return values


def _within_range(check: _Checker, first_line: int, location: tuple, values: np.ndarray,
                  name: str) -> None:
    """An input error (not waivable) for finite values beyond the magnitudes certkit
    computes with (:data:`~certkit.units.SI_RANGE`): no waiver makes 1e308 N a load.
    (Values that are not finite are the missing values of the 'gaps' check.)"""
    with np.errstate(invalid="ignore"):
        beyond = np.flatnonzero(np.isfinite(values) & (np.abs(values) > SI_RANGE[1]))
    if beyond.size:
        i = int(beyond[0])
        check.data_error(_row(first_line, i), check.key(*location, "column"),
                         f"column {name!r} holds {values[i]:.3g} in SI ({beyond.size} "
                         f"samples), beyond the magnitudes certkit computes with (up to "
                         f"{SI_RANGE[1]:g} in SI)")


def _gear_series(check: _Checker, frame, first_line: int, gear_id: str, channels,
                 unit: GearUnit) -> GearSeries:
    """A gear unit's load, stroke and tyre channels, each checked for plausible values."""
    base = ("gears", gear_id)
    load = _channel(check, frame, first_line, base + ("vertical_load",), channels.vertical_load,
                    "force")
    stroke = tyre = None
    if channels.strut_stroke is not None:
        stroke = _channel(check, frame, first_line, base + ("strut_stroke",),
                          channels.strut_stroke, "length")
    if channels.tyre_deflection is not None:
        tyre = _channel(check, frame, first_line, base + ("tyre_deflection",),
                        channels.tyre_deflection, "length")
    weight = unit.static_weight.si
    _plausible(check, first_line, base + ("vertical_load",), load,
               -PLAUSIBLE_NEGATIVE_LOAD * weight, PLAUSIBLE_LOAD_FACTOR * weight, "N",
               channels.vertical_load.unit)
    if stroke is not None:
        _plausible(check, first_line, base + ("strut_stroke",), stroke,
                   -PLAUSIBLE_NEGATIVE_TRAVEL,
                   PLAUSIBLE_STROKE_OVER_DESIGN * unit.design_stroke.si, "m",
                   channels.strut_stroke.unit)
    if tyre is not None:
        # no deflection reaches the tyre's radius: the declared tyre diameter, else the
        # wheel diameter, else a 1 m tyre (the message says which)
        if unit.tyre.diameter:
            limit, basis = unit.tyre.diameter.si / 2, "half the tyre diameter"
        elif unit.wheel_diameter:
            limit, basis = unit.wheel_diameter.si / 2, "half the wheel diameter"
        else:
            limit, basis = 0.5, ("half a 1 m tyre, assumed: neither tyre.diameter nor "
                                 "wheel_diameter is declared")
        _plausible(check, first_line, base + ("tyre_deflection",), tyre,
                   -PLAUSIBLE_NEGATIVE_TRAVEL, limit, "m", channels.tyre_deflection.unit,
                   f"upper end: {basis}")
    return GearSeries(load, stroke, tyre)


def _without_incomplete_rows(check: _Checker, display: str, time, gears, acceleration,
                             displacement):
    """Rows with a missing value can only reach here when the 'gaps' check was waived:
    drop them everywhere (the gear series in place), and say so in the waived finding."""
    arrays = [time] + [a for g in gears.values() for a in (g.load, g.stroke, g.tyre)
                       if a is not None] + [a for a in (acceleration, displacement) if a is not None]
    keep = np.logical_and.reduce([np.isfinite(a) for a in arrays])
    if keep.all():
        return time, acceleration, displacement
    dropped = int((~keep).sum())
    if keep.sum() < MIN_ROWS:
        check.data_error(None, check.key("file"), f"only {int(keep.sum())} row(s) have a value "
                                                  f"in every channel; at least {MIN_ROWS} are "
                                                  f"needed")
        check.raise_if_errors()
    if "gaps" not in check.waivers:  # non-finite values not from the file (overflow)
        check.data_error(None, check.key("file"), f"{dropped} row(s) are not finite after "
                                                  f"applying unit, scale and offset")
        check.raise_if_errors()
    check.findings.append(DataFinding(
        "gaps", f"{display}: {dropped} row(s) with missing values removed before analysis",
        check.waivers["gaps"]))
    for g in gears.values():
        g.load = g.load[keep]
        g.stroke = None if g.stroke is None else g.stroke[keep]
        g.tyre = None if g.tyre is None else g.tyre[keep]
    return (time[keep], None if acceleration is None else acceleration[keep],
            None if displacement is None else displacement[keep])


def _rate_mismatch(check: _Checker, time: TimeColumn, measured: float, declared: float,
                   tolerance: float) -> bool:
    """A sample rate off the declared one.  When the time steps read in another unit give
    the declared rate within ``tolerance`` (a column in ms declared as s reads 1 Hz for
    1 kHz), the spec's time unit is wrong: an input error naming the unit that fits.
    Otherwise the off rate is the waivable 'sample_rate' problem."""
    factor = scale_to_si(time.unit, "time")
    for unit in TIME_UNITS:
        rate = measured * factor / scale_to_si(unit, "time")
        if abs(rate - declared) <= tolerance * declared:
            check.spec_error(check.key("time", "unit"),
                             f"the time steps of column {time.column!r} in {check.data_file}, "
                             f"read in {time.unit}, give {measured:.6g} Hz against the "
                             f"declared {declared:.6g} Hz: the time unit looks wrong; read in "
                             f"{unit} they give {rate:.6g} Hz (write unit: {unit}, or correct "
                             f"the declared sampling rate)")
            return True
    check.waivable("sample_rate", None, check.key("time", "column"),
                   f"sample rate {measured:.6g} Hz differs from the declared {declared:.6g} Hz "
                   f"by more than {tolerance:.0%}")
    return False


def _longest_run(mask: np.ndarray) -> int:
    best = current = 0
    for flag in mask:
        current = current + 1 if flag else 0
        best = max(best, current)
    return best


def _plausible(check: _Checker, first_line: int, location: tuple, values: np.ndarray,
               low: float, high: float, si_unit: str, column_unit: str,
               basis: str = "") -> None:
    """An input error (waivable) when a channel's SI ``values`` leave [low, high]; the
    message speaks in the column's own unit, the one the user's file is written in."""
    finite = np.isfinite(values)
    outside = np.flatnonzero(finite & ((values < low) | (values > high)))
    if outside.size:
        i = int(outside[0])
        shown = [convert(float(v), si_unit, column_unit) for v in (values[i], low, high)]
        check.waivable("implausible_range", _row(first_line, i), check.key(*location, "column"),
                       f"value {number(shown[0])} {column_unit} (after scale, sign and offset) is "
                       f"outside the plausible range [{number(shown[1])}, {number(shown[2])}] "
                       f"{column_unit}{f' ({basis})' if basis else ''} ({outside.size} "
                       f"samples); check the channel mapping")
