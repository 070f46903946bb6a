"""Hostile and careless inputs, generated: the one home of the fuzzing strategies and of the
harness that runs a loader on an input and classifies the outcome.

Used by tests/test_hostile_input.py (a few hundred derandomised examples) and by
benchmarks/fuzz_inputs.py (tens of thousands, with the first reproducer of each crash).

An outcome is ``ok`` (accepted), ``clean`` (certkit's own input error: CertkitInputError,
CampaignError, QuantityError) or ``crash`` (anything else: a certkit bug).
"""

from __future__ import annotations

import re
import traceback
from dataclasses import dataclass
from pathlib import Path

from hypothesis import strategies as st

from certkit.errors import CampaignError, CertkitInputError
from certkit.units import KINDS, QuantityError

from .conftest import PHYSICS_SPEC, TIMESERIES_SPEC, analytic_signals, write_csv

CLEAN = (CertkitInputError, CampaignError, QuantityError)

KIND_NAMES = st.sampled_from(sorted(KINDS) + ["weight", "dimensionless"])


def outcome(function, *args) -> str:
    """'ok', 'clean' or 'crash' for ``function(*args)``."""
    try:
        function(*args)
    except CLEAN:
        return "clean"
    except Exception:  # noqa: BLE001 - what the fuzzer looks for
        return "crash"
    return "ok"


# --------------------------------------------------------------------------- values
#: Numbers as people and programs write them, and as no one should.
NUMBER_TOKENS = [
    "0", "-0", "1", "-1", "0.5", ".5", "5.", "1e3", "1E-3", "1e308", "1e309", "-1e308",
    "1e-320", "5e-324", "1e-400", "1e400", "nan", "NaN", "inf", "-inf", "Infinity", "0x1F",
    "0o17", "0b101", "1_000", "1,5", "1.5.2", "+", "-", ".", "e5", "1e", "1e+", "١٢٣", "１２",
    "9" * 400, "9" * 5000, "1" * 20_000 + "!", "0." + "0" * 400 + "1", "1" * 309 + ".0",
]

#: Unit names pint knows (and some it does not), logarithmic and offset units among them.
UNIT_TOKENS = [
    "mm", "m", "km", "in", "ft", "N", "kN", "kgf", "lbf", "kg", "lb", "s", "ms", "us", "min",
    "h", "Hz", "kHz", "deg", "rad", "turn", "rpm", "dB", "dBm", "Np", "B", "decade", "octave",
    "degC", "degF", "K", "delta_degC", "%", "percent", "ppm", "g", "g0", "psi", "Pa", "MPa",
    "bar", "J", "W", "dimensionless", "count", "µm", "Ω", "°", "x", "foo", "m2", "L", "cc",
    "gallon", "mph", "knot", "slug", "Pa_s", "inch_Hg", "UK_gallon", "planck_length",
]
POWERS = ["", "^2", "^-1", "**3", "^0", "^00", "^99", "^-99", "^1.5", "^", "^+2"]
OPERATORS = ["*", "/", "·", " * ", "/ ", "**", "+", "-", " "]

#: Whole values that break YAML, dates and echoes.
SPEC_TOKENS = [
    "~", "null", "[]", "{}", "[1, 2]", "{a: 1}", "''", '""', "'", '"', "|", ">", "- x",
    "!!int A", "!!float x", "!!bool maybe", "!!timestamp 2024-13-15", "!!map A", "!!str x",
    "!!set {a}", "!!binary AAAA", "!!python/object:os.system x", "&a 1", "*a", "? x",
    "yes", "no", "on", "off", "true", "14:05", "2024-13-15", "1903-12-31", "1899-12-31",
    "0001-01-01", "9999-12-31", "20240115", "2024-W03-1", "2024-02-29", "2023-02-29",
    "0x" + "f" * 4000, "\x07bell", "a\x00b", "\x1b[31mred", "\ufeffbom", "line\u2028sep",
    "\ud7ff", "x" * 300, "data/" + "x" * 300 + ".csv", "../outside.csv", "/etc/passwd",
    "data", "data/r1.csv/", "-3 dB", "3 deg*dB", "200 mm^0", "200 mm/dB", "3 km^99*km^99",
    "5e-324 kgf", "1e308 kgf", "1e-12 mm", "1e12 mm", "10 %", "1e400 %", "-5 %", "0 Hz",
    "1e-200 Hz", "1e200 Hz", "45 deg", "-45 deg", "46 deg", "1 rad", "0 s", "1e-9 s",
]


def number_texts() -> st.SearchStrategy[str]:
    return st.one_of(
        st.sampled_from(NUMBER_TOKENS),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.integers(min_value=-(10 ** 500), max_value=10 ** 500).map(str),
        st.from_regex(r"\A[+-]?\d{0,40}(\.\d{0,12})?([eE][+-]?\d{1,4})?\Z"))


def unit_texts() -> st.SearchStrategy[str]:
    name = st.tuples(st.sampled_from(UNIT_TOKENS), st.sampled_from(POWERS)).map("".join)
    return st.one_of(
        name,
        st.lists(st.tuples(name, st.sampled_from(OPERATORS)), min_size=1, max_size=4).map(
            lambda parts: "".join(n + o for n, o in parts)[:-1] or parts[0][0]),
        st.text(max_size=12))


#: Units of each kind a spec holds, so that a share of the generated values are accepted
#: and reach the arithmetic behind the loader.
PLAUSIBLE_UNITS = ["mm", "m", "in", "kg", "lb", "N", "kN", "kgf", "lbf", "Hz", "s", "ms", "m/s",
                   "m/s^2", "g0", "m^2", "ft^2", "cm^3", "L", "kPa", "MPa", "psi", "J", "deg",
                   "rad", "%", "lbf/ft^2", "N/mm", "N*s/m", "s/m", "kg/m^3", ""]


def quantity_texts() -> st.SearchStrategy[str]:
    """Text a user might type where a quantity goes, and text no one should."""
    joined = st.tuples(number_texts(), st.sampled_from(["", " ", "  ", "\t"]), unit_texts())
    plausible = st.tuples(st.floats(allow_nan=False, allow_infinity=False).map("{:g}".format),
                          st.sampled_from(PLAUSIBLE_UNITS)).map(" ".join)
    return st.one_of(plausible, joined.map("".join), st.sampled_from(SPEC_TOKENS),
                     st.text(max_size=40))


def spec_values() -> st.SearchStrategy[str]:
    return st.one_of(quantity_texts(), st.sampled_from(SPEC_TOKENS), number_texts(),
                     st.text(max_size=20))


# --------------------------------------------------------------------------- campaigns
#: The analytic campaign (measured time histories) and the drop-model campaign (no data).
BASES = {"timeseries": TIMESERIES_SPEC, "physics": PHYSICS_SPEC}
WAIVERS = ("      waivers: [{check: gaps, reason: x}, {check: sample_rate, reason: x}, "
           "{check: clipping, reason: x}, {check: implausible_range, reason: x}]\n")
_WAIVER_AFTER = "drop_mass_displacement: {column: x_mm, unit: mm}\n"
#: Where a value stands in a spec: after "key: " in block or flow style, up to a separator.
_VALUE = re.compile(r"(?<=: )[^,{}\[\]\n#]+|(?<=\[)[^,{}\[\]\n#:]+(?=[,\]])")


def campaign_folder(folder: Path) -> Path:
    """A folder with the analytic data file; the spec is written per trial."""
    (folder / "data").mkdir(parents=True, exist_ok=True)
    write_csv(folder / "data" / "r1.csv", analytic_signals())
    return folder


def base_csv() -> bytes:
    import io

    columns = analytic_signals()
    buffer = io.StringIO()
    names = list(columns)
    buffer.write(",".join(names) + "\n")
    for row in zip(*(columns[name] for name in names)):
        buffer.write(",".join(repr(float(v)) for v in row) + "\n")
    return buffer.getvalue().encode()


BASE_CSV = base_csv()


@dataclass(frozen=True)
class SpecMutation:
    """One edit of a base spec: replace the k-th value, insert or delete text, or drop or
    repeat a line (positions are shares of the text, so any draw lands somewhere)."""

    base: str
    operation: str
    where: float
    text: str = ""
    waived: bool = False

    def apply(self) -> str:
        spec = BASES[self.base]
        if self.waived:
            spec = spec.replace(_WAIVER_AFTER, _WAIVER_AFTER + WAIVERS)
        if self.operation == "value":
            spans = [match.span() for match in _VALUE.finditer(spec)]
            start, end = spans[int(self.where * len(spans)) % len(spans)]
            return spec[:start] + self.text + spec[end:]
        position = int(self.where * len(spec))
        if self.operation == "insert":
            return spec[:position] + self.text + spec[position:]
        if self.operation == "delete":
            return spec[:position] + spec[position + len(self.text) + 1:]
        lines = spec.splitlines(keepends=True)
        index = int(self.where * len(lines)) % len(lines)
        if self.operation == "drop-line":
            return "".join(lines[:index] + lines[index + 1:])
        return "".join(lines[:index + 1] + lines[index:])  # repeat-line


def spec_mutations() -> st.SearchStrategy[SpecMutation]:
    share = st.floats(min_value=0, max_value=1, exclude_max=True)
    return st.one_of(
        st.builds(SpecMutation, st.sampled_from(sorted(BASES)), st.just("value"), share,
                  spec_values(), st.booleans()),
        st.builds(SpecMutation, st.sampled_from(sorted(BASES)),
                  st.sampled_from(["insert", "delete", "drop-line", "repeat-line"]), share,
                  st.text(max_size=8), st.booleans()))


#: Cell contents a logger, a spreadsheet or a careless edit can leave.
CELL_TOKENS = ["", " ", "nan", "NaN", "NA", "inf", "-inf", "1e-200", "1e308", "-1e308", "1e309",
               "9" * 400, "abc", "0x10", "1,5", "\x00", "\"", "'", "True", "1e-324", "-0",
               "2024-01-15", "12:00:00", "1.5.2", "١", "𝟙", "\u00a0", "1 2"]


@dataclass(frozen=True)
class DataMutation:
    """One edit of the analytic CSV: a cell or a whole column set to ``text``, bytes
    overwritten, inserted or deleted, the file cut, the time column rescaled; ``waived``
    adds every waiver to the spec, so more of the data reaches the assessment."""

    operation: str
    where: float
    column: int
    text: str = ""
    payload: bytes = b""
    factor: float = 1.0
    waived: bool = False

    def apply(self) -> bytes:
        data = BASE_CSV
        position = int(self.where * len(data))
        if self.operation == "bytes":
            return data[:position] + self.payload + data[position + len(self.payload):]
        if self.operation == "insert":
            return data[:position] + self.payload + data[position:]
        if self.operation == "delete":
            return data[:position] + data[position + len(self.payload) + 1:]
        if self.operation == "cut":
            return data[:position]
        lines = data.decode().split("\n")
        if self.operation == "header":
            names = lines[0].split(",")
            names[self.column % len(names)] = self.text
            lines[0] = ",".join(names)
            return "\n".join(lines).encode("utf-8", "surrogatepass")
        rows = [line.split(",") for line in lines[1:] if line]
        column = self.column % len(rows[0])
        if self.operation == "time":
            for row in rows:
                row[0] = repr(float(row[0]) * self.factor)
        else:  # "cell" or "column"
            chosen = ([int(self.where * len(rows))] if self.operation == "cell"
                      else range(len(rows)))
            for index in chosen:
                rows[index][column] = self.text
        return "\n".join([lines[0]] + [",".join(row) for row in rows]).encode(
            "utf-8", "surrogatepass") + b"\n"


def data_mutations() -> st.SearchStrategy[DataMutation]:
    share = st.floats(min_value=0, max_value=1, exclude_max=True)
    column = st.integers(min_value=0, max_value=5)
    cell = st.one_of(st.sampled_from(CELL_TOKENS), number_texts(), st.text(max_size=6))
    payload = st.binary(min_size=1, max_size=8)
    return st.one_of(
        st.builds(DataMutation, st.sampled_from(["cell", "column", "header"]), share, column,
                  cell, waived=st.booleans()),
        st.builds(DataMutation, st.sampled_from(["bytes", "insert", "delete", "cut"]), share,
                  column, payload=payload, waived=st.booleans()),
        st.builds(DataMutation, st.just("time"), share, column,
                  factor=st.sampled_from([1e-200, 1e-9, 1e-3, 0.5, 2.0, 1e3, 1e200, -1.0]),
                  waived=st.booleans()))


# --------------------------------------------------------------------------- harness
@dataclass(frozen=True)
class Result:
    kind: str                 # ok, clean or crash
    stage: str = ""           # load, assess or simulate: where it ended
    detail: str = ""          # a crash's exception and where certkit raised it

    @property
    def signature(self) -> str:
        """What tells two crashes apart: the stage, the exception type and the place."""
        return self.detail.split("\n", 1)[0]


def _crash(stage: str, error: Exception) -> Result:
    frames = [frame for frame in traceback.extract_tb(error.__traceback__)
              if "/certkit/" in frame.filename]
    where = f"{Path(frames[-1].filename).name}:{frames[-1].lineno}" if frames else "?"
    message = str(error)[:200]
    return Result("crash", stage, f"{stage}: {type(error).__name__} at {where}\n{message}")


def _run(folder: Path, assess: bool, simulate: bool) -> Result:
    from certkit.spec.campaign import load_campaign

    stage = "load"
    try:
        campaign = load_campaign(folder / "campaign.yaml")
        if assess:
            from certkit.compliance.engine import assess as assess_campaign
            from certkit.evidence.audit import audit_rows
            from certkit.evidence.results_document import results_document

            stage = "assess"
            assessment = assess_campaign(campaign)
            audit_rows(assessment)
            results_document(assessment, {})
        if simulate:
            from certkit.physics.synthetic import NO_SENSOR_EFFECTS, simulate_campaign

            stage = "simulate"
            simulate_campaign(campaign, folder / "simulated", seed=0, sensors=NO_SENSOR_EFFECTS)
    except CLEAN:
        return Result("clean", stage)
    except Exception as error:  # noqa: BLE001 - what the fuzzer looks for
        return _crash(stage, error)
    return Result("ok", stage)


def try_spec(folder: Path, mutation: SpecMutation, assess: bool = False,
             simulate: bool = False) -> Result:
    """Load the mutated spec in ``folder`` (and assess or simulate what is accepted)."""
    (folder / "campaign.yaml").write_text(mutation.apply(), encoding="utf-8",
                                          errors="surrogatepass")
    (folder / "data" / "r1.csv").write_bytes(BASE_CSV)
    return _run(folder, assess, simulate and mutation.base == "physics")


def try_data(folder: Path, mutation: DataMutation, assess: bool = False) -> Result:
    """Load the analytic campaign with its data file mutated (and assess it if accepted)."""
    spec = TIMESERIES_SPEC.replace(_WAIVER_AFTER, _WAIVER_AFTER + WAIVERS) if mutation.waived \
        else TIMESERIES_SPEC
    (folder / "campaign.yaml").write_text(spec, encoding="utf-8")
    (folder / "data" / "r1.csv").write_bytes(mutation.apply())
    return _run(folder, assess, False)
