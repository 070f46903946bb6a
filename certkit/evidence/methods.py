"""What certkit does, in words, for the report's method paragraphs: the one home of that
prose, every number in it taken from the constants of the code that applies it.

The equations themselves are numbered in :mod:`certkit.compliance.equations`; the sections'
views (:mod:`certkit.evidence.model_view`, :mod:`certkit.evidence.gap_view`) take their
method text from here.
"""

from __future__ import annotations

import math

from certkit.display import parameter, percent, with_unit
from certkit.physics.drops import MIDDLE_FROM

#: Appendix A: the governing-equation model and its calibration.
MODEL_METHOD = ("The two-mass governing equations of a gear drop (airframe mass above the "
                "strut, unsprung mass between strut and tyre), with the usual errors of their "
                "published form corrected (hydraulic force ∝ ṡ|ṡ|, absolute gas pressures, "
                "strut force F_s/cos θ between the masses, tyre force clipped at zero, end "
                "stops), simulated for each gear unit and calibrated against its training runs "
                "jointly by bounded least squares on residuals normalised by each channel's "
                "range; the held-out runs are simulated with the calibrated parameters and "
                "play no part in the fit.")


def fit_step_method() -> str:
    """How every drop-model fit differences its residuals
    (:data:`certkit.physics.calibration.FIT_STEP`), in words."""
    from certkit.physics.calibration import FIT_STEP
    return (f"Every fit of the drop model takes its derivatives by finite differences over "
            f"{percent(FIT_STEP, 1)} of each parameter's size (the magnitude of its nominal "
            f"value; of a candidate effect's strength, the strength its score is taken at; "
            f"of a form's own shape parameter, where its refit starts by default), or of the "
            f"parameter's value when that is larger: the simulation's force laws "
            f"switch (seal friction's sign, the end stops, the tyre leaving the ground), so "
            f"the residuals are smooth only between kinks, and a step near the rounding limit "
            f"would difference the kinks, not the slope.")


def model_method(starts: int) -> str:
    """Appendix A's method: :data:`MODEL_METHOD`, the fits' step and where the fit starts
    from (``model.calibration.starts``)."""
    if not starts:
        return (f"{MODEL_METHOD} {fit_step_method()} The fit starts from the spec's values only "
                f"(model.calibration.starts is 0); a fit can stop at a local best fit (no "
                f"small change of the parameters improves it) short of the best one, which "
                f"further starts might find.")
    return (f"{MODEL_METHOD} {fit_step_method()} The fit starts from the spec's values and "
            f"{starts_method(starts, 'model.calibration.starts')}.")


def starts_method(count: int, setting: str = "") -> str:
    """How ``count`` further starts of a calibration are placed and chosen, in words
    (:mod:`certkit.physics.starts`); ``setting``: the spec key that sets ``count``."""
    from certkit.physics.starts import KEEP_MARGIN, START_EVALUATIONS
    margin = percent(KEEP_MARGIN, 1)
    return (f"from {count} further starts{f' ({setting})' if setting else ''} spread over "
            f"the parameters' bounds (points 1 to {count} of Sobol's sequence, a fixed set "
            f"of points that fills the box of the bounds more evenly the more there are, "
            f"the same on every machine; on a log scale between two positive bounds, a "
            f"linear one otherwise). Each start is fitted with forward differences within "
            f"{START_EVALUATIONS} evaluations of the residuals (finite-difference points "
            f"not counted); the "
            f"start with the lowest training cost (the earliest within {margin} of it) is "
            f"fitted again from where it stopped (central differences), and that fit is "
            f"kept when its training cost is more than {margin} below the fit from the "
            f"spec's values; a start whose fit fails is passed over")


def held_out_drops(held_at_middle: bool, declared: bool) -> str:
    """Which drops the held-out protocol simulates, as the split rule chose them."""
    if declared:
        return ("train and tune on the other drops, simulate the drops the spec holds out "
                "(model.identification.held_out), which are used for nothing else")
    if held_at_middle:
        return (f"train and tune on the other drops, simulate the drops at the highest and at "
                f"the middle drop height (held out from {MIDDLE_FROM} heights up), which are "
                f"used for nothing else")
    return ("train and tune on the lower drops, simulate the highest drop, which is used for "
            "nothing else")


def identification_method(window: str, paper_samples: str, force_unit: str, length_unit: str,
                          held_out: str) -> str:
    """Appendix B: the identification's inputs, outputs and protocols."""
    return (f"Input: the platform's vertical load; outputs: strut stroke and tyre deflection, "
            f"one SISO model each, from touchdown over {window} (models are fitted in kN and "
            f"mm; every number and figure here is in {force_unit} and {length_unit}). Two "
            f"protocols: short training (train on the first {paper_samples} after touchdown of "
            f"the highest drop, simulate that whole drop: in-sample for its first part) and the "
            f"held-out one ({held_out}). All figures are free-run simulations; one-step-ahead "
            f"errors are listed apart. RBF kernel K(x, z) = exp(−‖x − z‖²/σ²) (LS-SVMlab "
            f"convention; some authors write 2σ²); γ and σ² tuned by cross-validation on the "
            f"training runs.")


def unit_size(candidate, units) -> str:
    """What strength 1 of a candidate form means, its quantities in the display units."""
    words = candidate.unit_size
    for text, value, si_unit in candidate.quantities:
        words = words.replace(text, " ".join(filter(None, parameter(value, si_unit, units))))
    return words


def gap_method(units) -> dict:
    """Appendix C: the method in words, every threshold taken from the code that applies it
    (the gap stage is imported here, not at the top: a report without the drop model does
    not load it, about 0.66 s of start-up)."""
    from certkit.compliance.measures import AXLE_WINDOW
    from certkit.gap.attribution import STARTS
    from certkit.gap.missing_force import SEEN, STEP_VELOCITY
    from certkit.gap.phases import BREAKOUT_TRAVEL, BREAKOUT_WINDOW, REBOUND_DROP
    from certkit.gap.residuals import BANDS, MAX_LAG, TIMING_LAG
    from certkit.gap.selection import (CANDIDATES, DETECTABLE, FLOOR_CHANNEL, GAIN, LEADING,
                                       NOMINAL_STARTS, PULSE_SHARE, RECALIBRATE, RELEVANT,
                                       RESTARTS, TIE_COST,
                                       TIMING_SHARE)
    from certkit.physics.effects.load_cell_gain import MAX_SKEW
    from certkit.physics.effects.tyre_hysteresis import ONSET_RANGE

    bands = ", ".join(f"{name} ({low:g}-{high:g} Hz)" if math.isfinite(high)
                      else f"{name}" for name, low, high in BANDS)
    return {
        "split": (f"The bare drop model (no optional effects) is calibrated on the training "
                  f"runs only, from the spec's values and {starts_method(NOMINAL_STARTS)}: "
                  f"a fit can stop at a local best fit far from the best one, which would "
                  f"leave a model-to-test difference caused by the fitting, not by missing "
                  f"physics. The held-out runs are used for nothing but the errors reported "
                  f"as held out: by default every drop at the highest drop height (the "
                  f"certification case is extrapolation), and the middle height's drops too "
                  f"when there are {MIDDLE_FROM} heights or more; the spec's model.gap.held_out "
                  f"overrides the default."),
        "where": (f"Where: the residual (measured − model) of each channel is cut by the "
                  f"measured run's phases: free fall; tyre-only contact from touchdown; strut "
                  f"breakout, the first {with_unit(BREAKOUT_WINDOW, 'time', units)} after the "
                  f"stroke exceeds {with_unit(BREAKOUT_TRAVEL, 'length', units)}; compression "
                  f"to peak load; rebound to the end of the extension (the first stroke "
                  f"minimum once the stroke has come down {percent(REBOUND_DROP, 0)} of its "
                  f"travel); settling. Per channel, "
                  f"phase and run: RMS, bias (mean of measured − model) and timing lag (the "
                  f"cross-correlation peak within ±{with_unit(MAX_LAG, 'time', units)}; "
                  f"positive: the model is late). The residual's energy from touchdown is split "
                  f"into bands: {bands}."),
        "which": (f"Which: each candidate effect has one or more forms (friction proportional "
                  f"to a constant or to the gas force, a tyre loop scaling with the static "
                  f"curve or of constant amplitude, …), each a one-parameter family that nests "
                  f"the bare model (strength 0: the effect is absent). Each form's score "
                  f"(Lagrange-multiplier) statistic LM is computed on the training runs after "
                  f"projecting out what re-tuning the bare model's parameters can absorb, and "
                  f"converted into the RMS of the residual it would remove, √(LM/N), in units "
                  f"of the noise σ. Because the test looks only at zero strength, each "
                  f"candidate is also profiled: its training cost at the strengths "
                  f"{', '.join(f'{v:g}' for v in STARTS)}, with what re-tuning the bare model's "
                  f"parameters absorbs projected out (an effect strongly nonlinear in its "
                  f"strength can point the wrong way at zero and still explain the gap). "
                  f"A form is relevant when it belongs to one of the {LEADING} effects with "
                  f"the best scores and would remove at least {RELEVANT:g} σ, or when its "
                  f"profile already cuts the training cost by {percent(GAIN, 0)}. The "
                  f"best-profiled form of each of the {LEADING} relevant effects with the best profiles is refitted together with "
                  f"the bare model's parameters on the training runs, from its profile's best "
                  f"strength. {fit_step_method()} "
                  f"When the bare model's parameters a first-step refit reached, "
                  f"its effect left out, fit the training runs more than "
                  f"{percent(RECALIBRATE, 0)} better than the calibration, the calibration "
                  f"had not reached the best fit of those parameters and an effect would be "
                  f"credited with what they can do: the bare model is calibrated again from "
                  f"the parameters of the refit that fits best so, the new calibration is "
                  f"kept when it too is more than {percent(RECALIBRATE, 0)} better, and the "
                  f"step is repeated against it; after {RESTARTS} such calibrations, or when "
                  f"the new one is not better, a better fit that remains names no effect at "
                  f"that step. The statement says so first. "
                  f"The refit that cuts the training cost (RMS of the residuals "
                  f"divided by each channel's range) most, by at least {percent(GAIN, 0)}, and "
                  f"leaves no training channel worse beyond its noise (its RMSE grown by more "
                  f"than the noise σ in quadrature, σ estimated from the channel's second "
                  f"differences) and removes at least {DETECTABLE:g} noise variances from the "
                  f"training records (Σ over the channels of (RMSE before² − RMSE after²)/σ²; "
                  f"less is not told apart from the floor the bare model's own "
                  f"imperfection leaves) is named, with its form. Two forms are refitted "
                  f"with a shape of their own beside their strength, as no spec states it: the "
                  f"load-cell gain with its channel's skew (within "
                  f"±{with_unit(MAX_SKEW, 'time', units)} of the other channels), a tyre loop "
                  f"with memory with its onset (the deflection over which it switches, "
                  f"{with_unit(ONSET_RANGE[0], 'length', units)} to "
                  f"{with_unit(ONSET_RANGE[1], 'length', units)}). A model whose load "
                  f"record lags the other channels by a skew τ, on a run whose contact "
                  f"velocity is read on the drop-mass displacement, starts from the "
                  f"velocity τ before the touchdown read on the load (its contact came τ "
                  f"earlier; in free fall it was slower by g·τ). A form that changes one "
                  f"recorded channel (the load-cell gain) must also fit that channel's "
                  f"residual at the same instant, its skew included: when its correction, "
                  f"shifted by up to ±{with_unit(TIMING_LAG, 'time', units)}, would remove "
                  f"{percent(TIMING_SHARE, 0)} or more of the channel's remaining mean square, "
                  f"what is missing changes the record's timing beyond a skew (a delayed "
                  f"crosstalk, for example) and the form is not named. When the other effect's "
                  f"refit comes "
                  f"within a ratio of {TIE_COST:g} of its training cost, the fits cannot tell "
                  f"the two apart: the model-free missing force (below) decides when it shows "
                  f"the mark of one and not of the other, and otherwise the diagnosis says they "
                  f"cannot be told apart instead of naming one. A second effect is "
                  f"then looked for the same way; when none is named, one whose refit fails "
                  f"only the rule of no training channel worse is stated undecided beside the "
                  f"named effects (whether it is present too cannot be told). A named "
                  f"load-cell gain ε with a skew τ of the same sign is, to first order, the "
                  f"record a share ε of the load arriving τ·(1 + ε)/ε earlier would make "
                  f"(crosstalk through the frame); when the two records, computed from the "
                  f"named model's load, differ by less than the load's noise over the load "
                  f"pulse of the training runs (where the load is at least "
                  f"{percent(PULSE_SHARE, 0)} of its peak), the statement says so. The "
                  f"held-out "
                  f"errors are computed after the "
                  f"choice and play no part in it: the statement gives the share of the "
                  f"held-out {FLOOR_CHANNEL} error beyond its noise that the named effects "
                  f"close and the share that stays unexplained, and names every held-out "
                  f"channel they make worse beyond its noise."),
        "missing_force": (
            f"The missing force, without a model of any effect: on the first compression "
            f"and rebound of each training run the strut's force balance is inverted "
            f"(F_s = cos θ·(F_V − m2·(g − δ̈)) from the measured load and tyre deflection) and "
            f"the calibrated bare model's strut law at the measured stroke and stroke rate is "
            f"subtracted; the tyre's likewise (measured load less its tyre law at the "
            f"measured deflection and rate). Rates are Savitzky-Golay derivatives over "
            f"{with_unit(AXLE_WINDOW, 'time', units)}. Each missing force is fitted by least "
            f"squares with shapes that mark an effect (a step with sign(ṡ) over "
            f"{with_unit(STEP_VELOCITY, 'velocity', units)}: friction; ṡ|ṡ| on extension only: "
            f"rebound damping; loops in δ scaling with the static curve or of constant width: "
            f"tyre hysteresis) beside shapes re-tuning absorbs (gas stiffness, an offset, "
            f"damping both ways, tyre stiffness and damping). A mark is seen when its "
            f"coefficient has the effect's sign and removing it alone loses at least "
            f"{percent(SEEN, 0)} of the missing force's variance (partial R²)."),
        "candidates": [{"name": c.name, "form": c.form or "—",
                        "unit_size": unit_size(c, units)} for c in CANDIDATES],
    }
