"""A campaign with time histories whose energies and peaks are known in closed form."""

import numpy as np
import pytest

from certkit import assess, load_campaign
from certkit.results import PASS

from .conftest import (A_PEAK, ANALYTIC_STRUT_ENERGY, ANALYTIC_TYRE_ENERGY, D_MAX, F0, G, S_MAX,
                       T0, V0)


@pytest.fixture
def assessment(timeseries_campaign):
    return assess(load_campaign(timeseries_campaign))


def test_energies_from_time_series_match_the_analytic_areas(assessment):
    gear = assessment.runs[0].gears[0]
    # 60 samples over the loading stroke; spline-in-time integration is 4th order
    assert gear.get("E_t") == pytest.approx(ANALYTIC_TYRE_ENERGY, rel=1e-6)
    assert gear.get("E_s") == pytest.approx(ANALYTIC_STRUT_ENERGY, rel=1e-5)
    assert gear.get("eta_t") == pytest.approx(0.5, rel=1e-6)
    assert gear.get("eta_s") == pytest.approx(2 / 3.141592653589793, rel=1e-5)


def test_peaks_travel_and_touchdown(assessment):
    gear = assessment.runs[0].gears[0]
    assert gear.get("F_peak") == pytest.approx(F0, rel=1e-9)
    assert gear.get("d_s") == pytest.approx(S_MAX, rel=1e-9)
    assert gear.get("d_t") == pytest.approx(D_MAX, rel=1e-9)
    assert gear.get("d") == pytest.approx(S_MAX + D_MAX, rel=1e-9)
    # the first sample above 2 % of W is 1 ms after contact
    assert gear.get("t0") == pytest.approx(T0 + 0.001, abs=1e-9)


def test_drop_mass_load_factor_and_contact_velocity(assessment):
    run = assessment.runs[0]
    assert run.get("n_j") == pytest.approx(A_PEAK / G + 1, rel=1e-3)
    # parabola fit of the free fall ends 1 ms after contact (x = V0*tau there)
    assert run.get("v0_measured") == pytest.approx(V0, rel=0.02)


def test_effective_weight_and_load_factor_of_23_725(assessment):
    gear = assessment.runs[0].gears[0]
    # W_e = 2600*(0.3 + 0.333*0.12)/0.42 = 2104.5 N
    assert gear.get("W_e") == pytest.approx(2104.51, abs=0.01)
    # the accelerometer reads F0/m - g, so n_j = F0/(m g) and n = n_j*W_drop/W + L = F0/W + L
    # = 12000/2600 + 0.667 = 5.28238
    assert gear.get("n") == pytest.approx(5.28238, abs=1e-5)
    verdicts = {v.id: v for v in assessment.verdicts}
    effective = verdicts["CFR23.725b-effective-weight/R1/left-main"]
    assert effective.verdict == PASS and effective.margin == pytest.approx(2451.66 - 2104.51, abs=0.01)
    assert verdicts["CFR23.725b-effective-weight/R1"].verdict == PASS  # L = 0.667 <= 0.667
    load_factor = verdicts["CFR23.725f-load-factor/R1/left-main"]
    assert load_factor.verdict == PASS and load_factor.margin == pytest.approx(5.5 - 5.28238, abs=1e-5)


def test_reduced_mass_drop_has_no_lift_work_in_its_energy_budget(assessment):
    # a reduced drop mass represents lift with no force acting: E_avail = W_drop*(h + d)
    # = 250*9.80665*(0.3 + 0.12) = 1029.70 J, more than E_s + E_t = 611.15 + 240 J
    gear = assessment.runs[0].gears[0]
    assert gear.get("E_avail") == pytest.approx(1029.698, abs=1e-3)
    assert not any(f.check == "energy-exceeds-available" for f in assessment.findings)
    assert not any(f.check == "acceleration-vs-load" for f in assessment.findings)
    assert assessment.finding_counts()["error"] == 0
    # only the reserve drop is missing from this one-run campaign, besides 23.725(c), which
    # certkit never assesses
    not_shown = {v.criterion for v in assessment.verdicts if v.verdict == "NOT SHOWN"}
    assert not_shown == {"CFR23.727a-reserve-drop-height", "CFR23.723b-reserve-no-failure",
                         "CFR23.727b-reserve-effective-weight", "CFR23.725c-attitude-and-drag"}


def test_parquet_data_give_the_same_results_as_csv(timeseries_campaign):
    import pandas as pd

    folder = timeseries_campaign.parent
    pd.read_csv(folder / "data" / "r1.csv").to_parquet(folder / "data" / "r1.parquet")
    from_csv = assess(load_campaign(timeseries_campaign)).runs[0].gears[0]
    text = timeseries_campaign.read_text(encoding="utf-8").replace("data/r1.csv", "data/r1.parquet")
    timeseries_campaign.write_text(text, encoding="utf-8")
    from_parquet = assess(load_campaign(timeseries_campaign)).runs[0].gears[0]
    for key in ("F_peak", "d_s", "d_t", "E_s", "E_t", "t0"):
        assert from_parquet.get(key) == from_csv.get(key), key


def test_without_pyarrow_a_parquet_file_is_an_input_error_saying_how_to_read_it(
        timeseries_campaign, monkeypatch):
    # Parquet is an optional extra: without pyarrow the campaign's data file is named, with
    # the extra to install, exit 2 through the command line; CSV campaigns need nothing more
    import sys

    import pandas as pd

    from certkit.cli import app
    from certkit.errors import CertkitInputError
    from typer.testing import CliRunner

    folder = timeseries_campaign.parent
    pd.read_csv(folder / "data" / "r1.csv").to_parquet(folder / "data" / "r1.parquet")
    text = timeseries_campaign.read_text(encoding="utf-8").replace("data/r1.csv", "data/r1.parquet")
    timeseries_campaign.write_text(text, encoding="utf-8")
    for name in [m for m in sys.modules if m == "pyarrow" or m.startswith("pyarrow.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "pyarrow", None)       # import pyarrow -> ImportError
    with pytest.raises(CertkitInputError) as raised:
        load_campaign(timeseries_campaign)
    message = str(raised.value)
    assert "r1.parquet" in message and "needs pyarrow" in message
    assert "pip install 'certkit[parquet]'" in message and "Traceback" not in message
    result = CliRunner().invoke(app, ["validate", str(timeseries_campaign)])
    assert result.exit_code == 2 and "certkit[parquet]" in result.output


LAYOUTS = [
    # (separator, decimal mark, layout the audit states)
    (";", ",", "semicolon-separated with decimal commas"),
    (";", ".", "semicolon-separated with decimal points"),
    ("\t", ".", "tab-separated with decimal points"),
    ("\t", ",", "tab-separated with decimal commas"),
]


@pytest.mark.parametrize("separator, decimal, layout", LAYOUTS, ids=[c[2] for c in LAYOUTS])
def test_semicolon_and_tab_files_give_the_same_results_as_csv(timeseries_campaign, separator,
                                                              decimal, layout):
    path = timeseries_campaign.parent / "data" / "r1.csv"
    from_csv = assess(load_campaign(timeseries_campaign))
    text = path.read_text(encoding="utf-8").replace(",", separator).replace(".", decimal)
    path.write_text(text, encoding="utf-8")
    assessment = assess(load_campaign(timeseries_campaign))
    for key in ("F_peak", "d_s", "d_t", "E_s", "E_t", "t0"):
        assert assessment.runs[0].gears[0].get(key) == from_csv.runs[0].gears[0].get(key), key
    stated = [f for f in assessment.findings if f.check == "data-layout"]
    message = (f"data/r1.csv was read as {layout} (found from its header line and its "
               f"numbers; not the comma-separated CSV of RFC 4180)")
    assert [(f.severity, f.message) for f in stated] == [("info", message)]
    assert not any(f.check == "data-layout" for f in from_csv.findings)


def test_travel_zero_is_read_before_contact_not_on_the_last_sample_below_the_threshold(
        timeseries_campaign):
    from .conftest import analytic_signals, write_csv

    # the tyre channel one sample ahead of the load (it deflects before the load clears the
    # touchdown threshold): on the last sample below the threshold, t = 0.100 s, it reads
    # δ(τ = 1 ms) = 40·sin(π/2·sin(π·0.001/0.12)) = 1.644 mm, more than the 1 mm tolerance,
    # although the channel reads exactly zero before contact
    signals = analytic_signals()
    signals["tyre_mm"] = np.append(signals["tyre_mm"][1:], signals["tyre_mm"][-1])
    assert signals["tyre_mm"][100] == pytest.approx(1.644, abs=1e-3)
    write_csv(timeseries_campaign.parent / "data" / "r1.csv", signals)
    assessment = assess(load_campaign(timeseries_campaign))
    assert assessment.runs[0].gears[0].measures.tyre_at_touchdown == 0.0
    assert not any(f.check == "tyre-not-zero-at-touchdown" for f in assessment.findings)


def test_a_lift_device_drop_states_the_load_factor_formula_it_used(timeseries_campaign):
    # with the lift applied by a device, n = n_j·W_drop/W (the lift is already in n_j): the
    # verdict's basis must say that formula, not the reduced-mass one with + L
    text = timeseries_campaign.read_text(encoding="utf-8")
    timeseries_campaign.write_text(text.replace("lift: {method: reduced_mass, ratio: 0.667}",
                                                "lift: {method: lift_device, ratio: 0.5}"),
                                   encoding="utf-8")
    assessment = assess(load_campaign(timeseries_campaign))
    verdict = next(v for v in assessment.verdicts if v.id == "CFR23.725f-load-factor/R1/left-main")
    assert verdict.reason == "n = n_j·W_drop/W (lift applied by a device is already in n_j)"
