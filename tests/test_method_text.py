"""The method text is the method: every figure the report's methods state is the constant
the code applies (issue 12, defect 5)."""

from __future__ import annotations

import html
import importlib

from certkit import assess, load_campaign
from certkit.compliance import equations
from certkit.compliance import measures

from .conftest import report_html


def test_equation_texts_change_with_the_constants_they_state(monkeypatch):
    monkeypatch.setattr(measures, "VELOCITY_WINDOW", 0.033)
    monkeypatch.setattr(measures, "TOUCHDOWN_SHARE", 0.015)
    monkeypatch.setattr(measures, "TOUCHDOWN_SIGMAS", 5.0)
    monkeypatch.setattr(measures, "SETTLING_BAND", 0.03)
    monkeypatch.setattr(measures, "FINAL_SHARE", 0.1)
    monkeypatch.setattr(measures, "AXLE_WINDOW", 0.030)
    try:
        text = importlib.reload(equations).EQUATIONS
        assert "over the 33 ms before touchdown" in text["V2"]
        assert "1.5 % of the unit's static weight and 5 robust standard deviations" in text["M3"]
        assert "below 1.5 % of the static weight" in text["R1"]
        assert "within ±3 % of its maximum" in text["S1"] and "last 10 % of the record" in text["S1"]
        # 30 ms at 1 kHz: 31 samples (odd, centred)
        assert "over 30 ms, the odd number of samples spanning it at the run's rate: 31 at 1 kHz, " \
               "61 at 2 kHz" in text["E1"]
    finally:
        monkeypatch.undo()
        importlib.reload(equations)


def test_the_report_states_the_windows_and_thresholds_the_measures_use(timeseries_campaign,
                                                                       tmp_path):
    assessment = assess(load_campaign(timeseries_campaign))
    page = html.unescape(report_html(assessment))
    for key, text in equations.EQUATIONS.items():
        assert text in page, key
    # the value rows' own formulas, from the same constants
    assert (f"parabola fitted over the {measures.VELOCITY_WINDOW * 1e3:g} ms before it"
            in page)
    assert f"time with F_V < {100 * measures.TOUCHDOWN_SHARE:g} % W after the peak" in page
    assert f"±{100 * measures.SETTLING_BAND:g} % band" in page
    # what the report said before the text was taken from the code (the code used 50 ms)
    assert "over the 20 ms before" not in page


def test_the_gap_method_states_the_timing_rule_the_diagnosis_applies(monkeypatch):
    from certkit.evidence.methods import gap_method
    from certkit.gap import residuals, selection

    from .conftest import SEED

    monkeypatch.setattr(selection, "TIMING_SHARE", 0.17)
    monkeypatch.setattr(residuals, "TIMING_LAG", 0.045)
    units = load_campaign(SEED).spec.report.units
    text = " ".join(str(v) for v in gap_method(units).values())
    assert "shifted by up to ±45.00 ms, would remove 17 % or more" in text
    # in the campaign's time unit, like the other durations of the method
    seconds = units.model_copy(update={"time": "s"})
    text = " ".join(str(v) for v in gap_method(seconds).values())
    assert "shifted by up to ±0.04500 s, would remove" in text     # 4 significant digits


def test_the_method_text_states_the_fits_step_as_the_code_sets_it(monkeypatch):
    """Appendix A's method and the gap method state the fits' step from FIT_STEP: 0.3 % for
    3e-3, and another figure when the constant changes."""
    import certkit.physics.calibration as calibration
    from certkit.evidence.methods import fit_step_method, gap_method, model_method

    from .conftest import SEED

    assert "finite differences over 0.3 % of each parameter's size" in fit_step_method()
    assert fit_step_method() in model_method(0) and fit_step_method() in model_method(16)
    assert fit_step_method() in gap_method(load_campaign(SEED).spec.report.units)["which"]
    monkeypatch.setattr(calibration, "FIT_STEP", 1e-2)
    assert "over 1.0 % of each parameter's size" in fit_step_method()
