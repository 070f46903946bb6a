"""Hostile and careless inputs, generated: the one home of the fuzzing strategies and of the
harness that runs a loader on an input and classifies the outcome.

Used by tests/test_hostile_input.py (a few hundred derandomised examples) and by
benchmarks/fuzz_inputs.py (tens of thousands, with the first reproducer of each crash).

An outcome is ``ok`` (accepted), ``clean`` (certkit's own input error: CertkitInputError,
CampaignError, QuantityError) or ``crash`` (anything else: a certkit bug).
"""

from __future__ import annotations

import functools
import io
import re
import traceback
from dataclasses import dataclass
from pathlib import Path

import numpy as np
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
_WAIVED = ("waivers: [{check: gaps, reason: x}, {check: sample_rate, reason: x}, "
           "{check: clipping, reason: x}, {check: implausible_range, reason: x}]\n")
WAIVERS = "      " + _WAIVED
_WAIVER_AFTER = "drop_mass_displacement: {column: x_mm, unit: mm}\n"
# the same place in the simulated campaign's spec (block style, data keys 4 deep)
_MODELLED_WAIVER_AFTER = "      column: x_mm\n      unit: mm\n"

#: The drop-model campaign with time histories: PHYSICS_SPEC simulated (no sensor noise),
#: so what ``certkit report`` runs after the assessment (calibration, identification, gap
#: diagnosis) has data to work on.  Made cheaper than the defaults, or a trial would take a
#: minute: 250 Hz, two calibrated parameters, low orders with fixed hyper-parameters.
MODELLED_SETTINGS = (
    "  calibration: {parameters: [discharge-coefficient, gas-precharge]}\n"
    "  identification:\n"
    "    hammerstein: {na: 2, nb: 2, gamma: 100, sigma2: 1}\n"
    "    wiener: {na: 2, nb: 2, gamma: 100, sigma2: 1}\n"
    "    narx: {na: 1, nb: 1, gamma: 100, sigma2: 1}\n")


@functools.cache
def modelled_campaign() -> tuple[str, dict[str, bytes]]:
    """The simulated drop-model campaign: its spec's text and its data files' bytes (by
    path relative to the spec), made once per process."""
    import tempfile

    from certkit.physics.synthetic import NO_SENSOR_EFFECTS, simulate_campaign
    from certkit.spec.campaign import load_campaign

    text = PHYSICS_SPEC.replace("sampling_rate: 1000 Hz", "sampling_rate: 250 Hz").replace(
        "  effects: [rebound-orifice, seal-friction]\n",
        "  effects: [rebound-orifice, seal-friction]\n" + MODELLED_SETTINGS)
    with tempfile.TemporaryDirectory() as scratch:
        spec = Path(scratch) / "truth" / "campaign.yaml"
        spec.parent.mkdir()
        spec.write_text(text, encoding="utf-8")
        written = simulate_campaign(load_campaign(spec), Path(scratch) / "simulated", seed=0,
                                    sensors=NO_SENSOR_EFFECTS)
        data = {path.relative_to(written.parent).as_posix(): path.read_bytes()
                for path in sorted((written.parent / "data").iterdir())}
        return written.read_text(encoding="utf-8"), data


def base_spec(name: str, waived: bool = False) -> str:
    """The text of base spec ``name`` ('timeseries', 'physics' or 'modelled'), with every
    data-quality waiver on each run that has data when ``waived``."""
    if name == "modelled":
        spec = modelled_campaign()[0]
        return spec.replace(_MODELLED_WAIVER_AFTER, _MODELLED_WAIVER_AFTER + "    " + _WAIVED) \
            if waived else spec
    spec = BASES[name]
    return spec.replace(_WAIVER_AFTER, _WAIVER_AFTER + WAIVERS) if waived else spec
#: Where a value stands in a spec: after "key: " in block or flow style, up to a separator.
_VALUE = re.compile(r"(?<=: )[^,{}\[\]\n#]+|(?<=\[)[^,{}\[\]\n#:]+(?=[,\]])")


def campaign_folder(folder: Path) -> Path:
    """A folder with the analytic data file; the spec is written per trial."""
    (folder / "data").mkdir(parents=True, exist_ok=True)
    write_csv(folder / "data" / "r1.csv", analytic_signals())
    return folder


def base_csv() -> bytes:
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
        spec = base_spec(self.base, self.waived)
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


def spec_mutations(bases: tuple[str, ...] = tuple(sorted(BASES))
                   ) -> st.SearchStrategy[SpecMutation]:
    share = st.floats(min_value=0, max_value=1, exclude_max=True)
    return st.one_of(
        st.builds(SpecMutation, st.sampled_from(bases), st.just("value"), share,
                  spec_values(), st.booleans()),
        st.builds(SpecMutation, st.sampled_from(bases),
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
    file: str = "data/r1.csv"   # of the modelled campaign: which run's file is mutated

    def apply(self, data: bytes = BASE_CSV) -> bytes:
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


# --------------------------------------------------------------------------- Parquet
#: What a Parquet writer can make of a column (pandas dtypes and pyarrow types).
PARQUET_TYPES = ["int8", "int64", "uint64", "float16", "float32", "bool", "string", "object",
                 "category", "Int64", "Float64", "decimal", "timedelta", "datetime",
                 "datetime-tz", "date", "bytes", "list", "struct", "large-list", "dictionary",
                 "null"]
#: Column names no logger should write, and some a careless script does.
PARQUET_NAMES = ["", " ", "t_s ", "T_S", "\x00", "\x1b[31m", "x" * 300, "1", "None", "nan",
                 "Fz_kN", "a.b", "(a, b)", "__index_level_0__", "é", "\ufefft_s"]


@dataclass(frozen=True)
class ParquetMutation:
    """One change to the analytic run written as Parquet: a column's type, nulls in it, its
    name (odd, repeated, not text, two-level), the time column as timestamps, zero rows,
    row groups of one row or one group of all rows, bytes overwritten or the file cut."""

    operation: str
    column: int
    choice: int = 0
    where: float = 0.0
    payload: bytes = b""
    waived: bool = False

    def apply(self) -> bytes:
        import pandas as pd
        import pyarrow as pa
        import pyarrow.parquet as pq

        frame = pd.DataFrame(analytic_signals())
        name = frame.columns[self.column % frame.shape[1]]
        rows = len(frame)
        row_group = None
        if self.operation == "type":
            frame[name] = _parquet_column(frame[name], PARQUET_TYPES[self.choice
                                                                     % len(PARQUET_TYPES)])
        elif self.operation == "nulls":
            count = max(1, int(self.where * rows)) if self.choice % 3 else rows
            frame.loc[frame.index[:count], name] = None
        elif self.operation == "name":
            names = list(frame.columns)
            names[self.column % len(names)] = PARQUET_NAMES[self.choice % len(PARQUET_NAMES)]
            frame.columns = names
        elif self.operation == "non-text-name":
            frame.columns = [[0, 1.5, None, ("a", "b"), True, -1][self.choice % 6]
                             if column == name else column for column in frame.columns]
        elif self.operation == "two-level":
            frame.columns = pd.MultiIndex.from_tuples([(c, "v") for c in frame.columns])
        elif self.operation == "time-stamps":
            frame["t_s"] = pd.Timestamp("2025-02-27T10:00", tz="UTC" if self.choice % 2
                                        else None) + pd.to_timedelta(frame["t_s"], unit="s")
        elif self.operation == "index":
            frame = frame.set_index(name)
        elif self.operation == "zero-rows":
            frame = frame.iloc[:0]
        elif self.operation == "row-groups":
            row_group = 1 if self.choice % 2 else rows
        buffer = io.BytesIO()
        if isinstance(frame.columns, pd.MultiIndex):
            frame.to_parquet(buffer)
        else:
            if frame.columns.duplicated().any():   # pandas refuses; Parquet holds them
                table = pa.Table.from_arrays([pa.Array.from_pandas(frame.iloc[:, i])
                                              for i in range(frame.shape[1])],
                                             names=[str(c) for c in frame.columns])
            else:
                table = pa.Table.from_pandas(frame, preserve_index=self.operation == "index")
            pq.write_table(table, buffer, row_group_size=row_group)
        data = buffer.getvalue()
        position = int(self.where * len(data))
        if self.operation == "bytes":
            return data[:position] + self.payload + data[position + len(self.payload):]
        if self.operation == "cut":
            return data[:position]
        return data


def _parquet_column(values, kind: str):
    """``values`` (floats) as a column of type ``kind``."""
    import decimal

    import pandas as pd
    import pyarrow as pa

    arrow = {"decimal": lambda: pa.array([decimal.Decimal(repr(v)[:12]) for v in values]),
             "bytes": lambda: pa.array([repr(v).encode() for v in values]),
             "list": lambda: pa.array([[v] for v in values]),
             "large-list": lambda: pa.array([[v, v] for v in values],
                                            type=pa.large_list(pa.float64())),
             "struct": lambda: pa.array([{"value": v} for v in values]),
             "dictionary": lambda: pa.array(values.round(1)).dictionary_encode(),
             "null": lambda: pa.nulls(len(values))}
    if kind in arrow:
        return pd.Series(pd.arrays.ArrowExtensionArray(arrow[kind]()), index=values.index)
    if kind == "timedelta":
        return pd.to_timedelta(values, unit="s")
    if kind in ("datetime", "datetime-tz", "date"):
        stamps = pd.Timestamp("2025-02-27", tz="UTC" if kind == "datetime-tz" else None) + \
            pd.to_timedelta(values, unit="s")
        return stamps.dt.date if kind == "date" else stamps
    if kind in ("category", "string", "object"):
        return values.round(3).astype(str).astype(kind)
    if "int" in kind.lower():   # whole numbers (wrapped around in the narrow ones)
        values = values.abs().round() if kind.startswith("u") else values.round()
        if kind[0].islower():
            return pd.Series(values.to_numpy().astype(np.int64).astype(kind), index=values.index)
    return values.astype(kind)


def parquet_mutations() -> st.SearchStrategy[ParquetMutation]:
    share = st.floats(min_value=0, max_value=1, exclude_max=True)
    column = st.integers(min_value=0, max_value=5)
    choice = st.integers(min_value=0, max_value=len(PARQUET_TYPES) - 1)
    return st.one_of(
        st.builds(ParquetMutation, st.sampled_from(
            ["type", "nulls", "name", "non-text-name", "two-level", "time-stamps", "index",
             "zero-rows", "row-groups"]), column, choice, share, waived=st.booleans()),
        st.builds(ParquetMutation, st.sampled_from(["bytes", "cut"]), column, choice, share,
                  st.binary(min_size=1, max_size=8), st.booleans()))


# --------------------------------------------------------------------------- model stages
@dataclass(frozen=True)
class ModelMutation:
    """A mutation of the simulated drop-model campaign: of its spec (``spec``) or of one
    run's data file (``data``, its ``file`` naming which)."""

    spec: SpecMutation | None = None
    data: DataMutation | None = None


def model_mutations() -> st.SearchStrategy[ModelMutation]:
    files = st.sampled_from(["data/D200.csv", "data/D250.csv", "data/D300.csv"])
    data = st.builds(lambda m, file: DataMutation(**{**m.__dict__, "file": file}),
                     data_mutations(), files)
    return st.one_of(st.builds(ModelMutation, spec=spec_mutations(("modelled",))),
                     st.builds(ModelMutation, data=data))


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


def _run(folder: Path, assess: bool, simulate: bool, model: bool = False,
         gap: bool = False) -> Result:
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
        if model:   # what report adds after the assessment, as it runs it
            from certkit.evidence.model_evidence import model_evidence
            from certkit.evidence.results_document import results_document

            def progress(message: str) -> None:
                nonlocal stage
                stage = message.split(" ")[0]   # calibrating, diagnosing, identifying

            stage = "model"
            evidence = model_evidence(campaign, gap=gap, progress=progress)
            stage = "model results"
            results_document(assessment, evidence)
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


def try_data(folder: Path, mutation: DataMutation | ParquetMutation,
             assess: bool = False) -> Result:
    """Load the analytic campaign with its data file mutated (CSV, or Parquet for a
    ParquetMutation) and assess it if accepted."""
    spec = base_spec("timeseries", mutation.waived)
    name = "r1.csv"
    if isinstance(mutation, ParquetMutation):
        name = "r1.parquet"
        spec = spec.replace("file: data/r1.csv", f"file: data/{name}")
    (folder / "campaign.yaml").write_text(spec, encoding="utf-8")
    (folder / "data" / name).write_bytes(mutation.apply())
    return _run(folder, assess, False)


def try_model(folder: Path, mutation: ModelMutation, gap: bool = False) -> Result:
    """The simulated drop-model campaign with ``mutation`` applied, through load, assess and
    the drop model's evidence as ``certkit report`` makes it (calibration, identification
    and, with ``gap``, the gap diagnosis: about 6 s per accepted input, 40 s more with
    ``gap``)."""
    spec, files = modelled_campaign()
    files = dict(files)
    if mutation.spec is not None:
        spec = mutation.spec.apply()
    else:
        spec = base_spec("modelled", mutation.data.waived)
        files[mutation.data.file] = mutation.data.apply(files[mutation.data.file])
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "campaign.yaml").write_text(spec, encoding="utf-8", errors="surrogatepass")
    for name, data in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_bytes(data)
    return _run(folder, True, False, model=True, gap=gap)
