"""Shared fixtures: the example campaign and a small campaign with analytic time series.

The analytic run is built so that its energies are known in closed form:

* stroke      s(τ) = s_max·sin(πτ/2T)             for 0 ≤ τ ≤ T, τ = t − t_0
* tyre        δ = δ_max·sin(π s/(2 s_max))
* load        F = F_0·δ/δ_max

so on the loading stroke F is linear in δ (E_t = F_0·δ_max/2) and a quarter sine of s
(E_s = ∫ F_0 sin(π s/2s_max) ds = 2·F_0·s_max/π).  After T the load and travel relax
smoothly.  The drop mass falls freely before touchdown (x = v_0 τ + g τ²/2) and its
kinematic acceleration peaks at A_peak.
"""

from __future__ import annotations

import importlib.util
import math
import os
import shutil
import textwrap
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parent.parent
SEED = REPO / "campaigns" / "seed-amphibian" / "campaign.yaml"

#: The seed paper's published figures (the first example's reference results): none may
#: appear in the report of a campaign that does not declare them.
SEED_FIGURES = ("9.7364", "11.3473", "0.88522", "0.48805", "0.71204", "0.38246")

G = 9.80665
RATE = 1000.0
T0 = 0.100          # touchdown [s]
T_LOAD = 0.060      # loading time to maximum stroke [s]
S_MAX = 0.080       # [m]
D_MAX = 0.040       # [m]
F0 = 12000.0        # [N]
V0 = 2.2            # [m/s]
DROP_MASS = 250.0   # [kg]
A_PEAK = F0 / DROP_MASS - G   # [m/s^2], kinematic, upward: what the platform load implies
DURATION = 0.600    # [s]


def analytic_signals(rate: float = RATE) -> dict[str, np.ndarray]:
    t = np.arange(0.0, DURATION, 1.0 / rate)
    tau = t - T0
    s = np.zeros_like(t)
    loading = (tau >= 0) & (tau <= T_LOAD)
    s[loading] = S_MAX * np.sin(math.pi * tau[loading] / (2 * T_LOAD))
    after = tau > T_LOAD
    # relax to 60 % of the maximum stroke with a smooth cosine over 0.2 s, then hold
    relax = np.clip((tau[after] - T_LOAD) / 0.2, 0, 1)
    s[after] = S_MAX * (1 - 0.4 * (1 - np.cos(math.pi * relax)) / 2)
    delta = D_MAX * np.sin(math.pi * s / (2 * S_MAX))
    load = F0 * delta / D_MAX
    x = np.where(tau < 0, V0 * tau + 0.5 * G * tau ** 2, V0 * tau)  # free fall, then anything
    a = np.where(tau < 0, -G, 0.0)
    a[loading] = A_PEAK * np.sin(math.pi * tau[loading] / T_LOAD)
    return {"t_s": t, "Fz_kN": load / 1000.0, "stroke_mm": s * 1000.0,
            "tyre_mm": delta * 1000.0, "acc_ms2": a, "x_mm": x * 1000.0}


ANALYTIC_STRUT_ENERGY = 2 * F0 * S_MAX / math.pi
ANALYTIC_TYRE_ENERGY = F0 * D_MAX / 2


def saturating_plant(n: int, seed: int, pole: float) -> tuple[np.ndarray, np.ndarray]:
    """A first-order plant with a saturating input, y_t = pole·y_{t−1} + tanh(2·u_{t−1}),
    driven by uniform noise on [−1, 1], its output measured with noise of 0.01 (seeded):
    a record for the identification library's tuning checks."""
    rng = np.random.default_rng(seed)
    u = rng.uniform(-1.0, 1.0, n)
    y = np.zeros(n)
    for t in range(1, n):
        y[t] = pole * y[t - 1] + np.tanh(2.0 * u[t - 1])
    return u, y + 0.01 * rng.standard_normal(n)


def write_csv(path: Path, columns: dict[str, np.ndarray]) -> None:
    names = list(columns)
    rows = np.column_stack([columns[name] for name in names])
    with path.open("w", encoding="utf-8") as handle:
        handle.write(",".join(names) + "\n")
        for row in rows:
            handle.write(",".join(repr(float(v)) for v in row) + "\n")


TIMESERIES_SPEC = textwrap.dedent("""\
    certkit: 1
    campaign: {id: TS-TEST, title: Analytic single-gear campaign}
    document:
      report_number: TS-0001
      revision: "1"
      date: 2025-03-01
      applicant: Test applicant
      facility: Test rig
      test_dates: [2025-02-27]
      signatories: [{role: prepared, name: A. Tester}]
    certification_basis:
      - requirement_set: 14CFR23-amdt62
    aircraft:
      model: Test aircraft
      maximum_weight: 600 kg
      wing_area: 12 m^2
      wing_lift_ratio: 0.667
      design_limit_inertia_load_factor: 5.5
    gear_units:
      - id: left-main
        position: main
        static_weight: 2600 N
        static_weight_basis: level-attitude-nose-wheel-clear
        shock_absorber: oleo-pneumatic
        design_stroke: 120 mm
        tyre: {size: 5.00-5, pressure: 30 psi, pressure_reference: gauge, diameter: 380 mm}
        # the analytic load is the strut's force: no unsprung mass, a vertical strut
        strut: {unsprung_mass: 0 kg, inclination: 0 deg}
    instrumentation:
      sampling_rate: 1000 Hz
    runs:
      - id: R1
        test_type: limit
        gear_units: [left-main]
        drop_height: 300 mm
        drop_mass: 250 kg
        lift: {method: reduced_mass, ratio: 0.667}
        data:
          file: data/r1.csv
          time: {column: t_s, unit: s}
          gears:
            left-main:
              vertical_load: {column: Fz_kN, unit: kN}
              strut_stroke: {column: stroke_mm, unit: mm}
              tyre_deflection: {column: tyre_mm, unit: mm}
          drop_mass_acceleration: {column: acc_ms2, unit: m/s^2, reference: kinematic}
          drop_mass_displacement: {column: x_mm, unit: mm}
        inspection: {failure: false}
    """)


def report_html(assessment, model=None) -> str:
    """The report's HTML as render_report writes it, without making the PDF (seconds a
    test that reads only the page need not spend)."""
    from certkit.evidence.provenance import provenance
    from certkit.evidence.render import render_html
    from certkit.evidence.view import build_view

    return render_html(build_view(assessment, provenance(assessment.campaign.inputs), model))


def load_script(path: Path, name: str):
    """A campaign folder's script (synthesise.py) imported as a module."""
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def write_campaign(folder: Path, text: str) -> Path:
    """Write a spec into its own folder; returns the spec path."""
    folder.mkdir(parents=True, exist_ok=True)
    spec = folder / "campaign.yaml"
    spec.write_text(text, encoding="utf-8")
    return spec


@pytest.fixture
def timeseries_campaign(tmp_path: Path) -> Path:
    """A campaign folder with one analytic run; returns the spec path."""
    folder = tmp_path / "campaign"
    (folder / "data").mkdir(parents=True)
    write_csv(folder / "data" / "r1.csv", analytic_signals())
    return write_campaign(folder, TIMESERIES_SPEC)


@pytest.fixture
def small_campaign(tmp_path: Path) -> Path:
    """The analytic campaign with the run's reported values instead of its logger file: a
    report of nine pages in under two seconds, for checks of how outputs are written."""
    import yaml

    raw = yaml.safe_load(TIMESERIES_SPEC)
    run = raw["runs"][0]
    run.pop("data")
    run["reported"] = {"gears": {"left-main": {
        "strut_stroke": "80 mm", "tyre_deflection": "40 mm", "peak_vertical_load": "12 kN",
        "strut_energy": "611 J", "tyre_energy": "240 J"}}}
    return write_campaign(tmp_path / "small", yaml.safe_dump(raw, sort_keys=False))


@pytest.fixture
def seed_copy(tmp_path: Path) -> Path:
    """A writable copy of the example campaign folder; returns the spec path."""
    folder = tmp_path / "seed"
    shutil.copytree(SEED.parent, folder)
    return folder / "campaign.yaml"


# The seed gear of tests/test_drop_model.py typed as a spec: 60 mm piston, so
# A_a = A_h = pi*60^2/4 = 2827.433388 mm^2; V0 = A_a*230 mm = 650.3096792 cm^3; tyre
# f = 7.2e5*delta^1.26 N written as 7.2e5*0.04^1.26 = 12471.77 N at 40 mm.
PHYSICS_SPEC = textwrap.dedent("""\
    certkit: 1
    campaign: {id: PHYS-TEST, title: Simulated single-gear campaign}
    document:
      report_number: PHYS-0001
      revision: "1"
      date: 2025-04-01
      applicant: Test applicant
      facility: Simulation
      test_dates: [2025-04-01]
      signatories: [{role: prepared, name: A. Tester}]
    certification_basis:
      - requirement_set: 14CFR23-amdt62
    aircraft:
      model: Seed amphibian (one main gear)
      maximum_weight: 650 kg
      wing_area: 140.85 ft^2
      wing_lift_ratio: 0.667
    gear_units:
      - id: left-main
        position: main
        static_weight: 292.5 kgf
        static_weight_basis: assumed
        shock_absorber: oleo-pneumatic
        design_stroke: 200 mm
        tyre:
          size: 240 mm wheel
          pressure: 25 psi
          pressure_reference: gauge
          load_deflection: {reference_load: 12471.77 N, reference_deflection: 40 mm, exponent: 1.26}
          damping: 0.05 s/m
        strut:
          gas_precharge_pressure: 0.8 MPa
          pressure_reference: gauge
          pneumatic_area: 2827.433388 mm^2
          hydraulic_area: 2827.433388 mm^2
          gas_volume: 650.3096792 cm^3
          polytropic_exponent: 1.2
          orifice_diameter: 9.4 mm
          rebound_orifice_diameter: 6.65 mm
          discharge_coefficient: 0.6
          oil_density: 860 kg/m^3
          unsprung_mass: 9 kg
          seal_friction: {constant: 80 N, pressure_factor: 0.03}
    model:
      effects: [rebound-orifice, seal-friction]
    instrumentation:
      sampling_rate: 1000 Hz
    runs:
      - {id: D200, test_type: build-up, gear_units: [left-main], drop_height: 200 mm, drop_mass: 292.5 kg, lift: {method: none}}
      - {id: D250, test_type: build-up, gear_units: [left-main], drop_height: 250 mm, drop_mass: 292.5 kg, lift: {method: none}}
      - {id: D300, test_type: limit, gear_units: [left-main], drop_height: 300 mm, drop_mass: 292.5 kg, lift: {method: none}}
    """)


@pytest.fixture
def physics_campaign(tmp_path: Path) -> Path:
    """A campaign whose gear has every parameter the drop model needs; returns the spec path."""
    return write_campaign(tmp_path / "physics", PHYSICS_SPEC)


@pytest.fixture(scope="session", autouse=True)
def evidence_cache(tmp_path_factory) -> Path:
    """The drop-model evidence cache of this test session (the processes the tests start
    inherit it): never the user's own, and empty at the start."""
    folder = tmp_path_factory.mktemp("evidence-cache")
    previous = os.environ.get("CERTKIT_CACHE")
    os.environ["CERTKIT_CACHE"] = str(folder)
    yield folder
    if previous is None:
        os.environ.pop("CERTKIT_CACHE", None)
    else:
        os.environ["CERTKIT_CACHE"] = previous


@pytest.fixture(scope="session")
def full_report_run(tmp_path_factory) -> tuple[Path, tuple[int, str, str]]:
    """The seed example's full report (drop-model appendices included), made once per test
    session (by one of its pytest-xdist workers, the others wait for it and take it:
    tests/full_reports.made_once) by the command line in a fresh process with one thread,
    its drop-model evidence made afresh (tests/full_reports.made): the output folder and
    the run's (exit code, stdout, stderr).  About a minute: only slow checks use it
    (tests/test_full_report_seed.py, test_thread_counts.py, test_archive.py,
    test_rendering.py, test_report.py), and only to read it."""
    from .full_reports import made_once

    return made_once(SEED, tmp_path_factory, "full-report")


@pytest.fixture(scope="session")
def full_report(full_report_run) -> Path:
    """The output folder of :func:`full_report_run`, which must have succeeded."""
    out, (code, _, stderr) = full_report_run
    assert code == 0, stderr
    return out


# ------------------------------------------------------------------ the catalog's databases
#: An administrator's URL of a PostgreSQL server on which the catalog tests create a
#: database each (.ci/run starts one with .ci/postgresql and sets it).
POSTGRESQL_URL = "CERTKIT_TEST_POSTGRESQL_URL"


def in_ci() -> bool:
    return os.environ.get("CI", "").lower() not in ("", "0", "false", "no")


def skip_or_fail(reason: str) -> None:
    """Skip with ``reason`` on a developer's machine; fail in CI, which must run it."""
    if in_ci():
        pytest.fail(f"{reason} (CI=true: CI must run the PostgreSQL catalog tests)")
    pytest.skip(reason)


def database_url(admin_url: str, name: str) -> str:
    """The admin URL naming database ``name`` instead."""
    from urllib.parse import urlsplit

    return urlsplit(admin_url)._replace(path="/" + name).geturl()


@pytest.fixture(scope="session")
def postgresql_server() -> str:
    """The admin URL of the test PostgreSQL server (skips without one, fails in CI)."""
    url = os.environ.get(POSTGRESQL_URL)
    if not url:
        skip_or_fail(f"no PostgreSQL server: set {POSTGRESQL_URL}; .ci/run starts one "
                     f"(or `make test-postgresql`)")
    if importlib.util.find_spec("psycopg") is None:
        skip_or_fail("psycopg is not installed: pip install 'certkit[postgresql]'")
    import psycopg

    try:
        psycopg.connect(url, connect_timeout=10).close()
    except psycopg.Error as error:
        pytest.fail(f"{POSTGRESQL_URL} names a server certkit cannot reach: {error}")
    return url


def admin_execute(admin_url: str, *statements: str) -> None:
    import psycopg

    with psycopg.connect(admin_url, autocommit=True) as connection:
        for statement in statements:
            connection.execute(statement)


@pytest.fixture
def postgresql_database(postgresql_server) -> str:
    """The URL of a new, empty database of its own on the test server, dropped after."""
    import uuid

    name = f"certkit_test_{uuid.uuid4().hex[:16]}"
    admin_execute(postgresql_server, f"CREATE DATABASE {name}")
    yield database_url(postgresql_server, name)
    admin_execute(postgresql_server, f"DROP DATABASE IF EXISTS {name} WITH (FORCE)")


@pytest.fixture(params=["sqlite", "postgresql"])
def catalog(request, tmp_path):
    """A catalog that does not exist yet, on each backend: an SQLite file's path (a Path),
    or the URL of an empty database (a str)."""
    if request.param == "sqlite":
        return tmp_path / "catalog.sqlite"
    return request.getfixturevalue("postgresql_database")
