"""certkit's own equations (those not written in a clause), numbered so every value can cite one.

The report prints this table in its methods section; a value whose source is
``certkit E1`` is traceable to the line ``E1`` here.
"""

from certkit.compliance.measures import (AXLE_POLYORDER, AXLE_WINDOW, FINAL_SHARE, SETTLING_BAND,
                                         TOUCHDOWN_SHARE, TOUCHDOWN_SIGMAS, VELOCITY_WINDOW,
                                         window_samples)


def _share(value: float) -> str:
    return f"{100 * value:g} %"


#: Polynomial order of the Savitzky-Golay filter in words.
_ORDER = {2: "quadratic", 3: "cubic", 4: "quartic"}.get(AXLE_POLYORDER, f"order {AXLE_POLYORDER}")

EQUATIONS: dict[str, str] = {
    "M1": "F_peak = max F_V(t) after touchdown (platform vertical load of the gear unit)",
    "M2": "d_s = max s(t), d_t = max δ(t); d = max(δ(t) + s(t)·cos θ) "
          "(tyre deflection plus vertical axle travel, 23.725(b)); from reported values "
          "d = d_t + d_s·cos θ (an upper bound: the maxima need not coincide)",
    "M3": "touchdown: first sample where F_V exceeds its pre-contact median by the larger of "
          f"{_share(TOUCHDOWN_SHARE)} of the unit's static weight and {TOUCHDOWN_SIGMAS:g} robust "
          f"standard deviations of the pre-contact noise",
    "E1": "E = ∫ F d(travel) from touchdown to maximum travel; tyre: F_V over δ; strut: the "
          "axial force F_s over s, F_s/cos θ = F_V − m2·(g − δ̈) (lower-mass equation, m2 the "
          f"declared unsprung mass or 0, δ̈ a Savitzky-Golay second derivative of δ, {_ORDER}, over "
          f"{AXLE_WINDOW * 1e3:g} ms, the odd number of samples spanning it at the run's rate: "
          f"{window_samples(AXLE_WINDOW, 1e-3)} at 1 kHz, {window_samples(AXLE_WINDOW, 5e-4)} at "
          f"2 kHz); cubic "
          f"splines in time, Gauss-Legendre per sample interval",
    "E2": "η = E/(F·δ_max) with F the peak force through the element (tyre: F_peak; strut: "
          "F_peak·cos θ)",
    "E3": "E_avail = W_drop·(h + d) − L_dev·W_drop·d: potential energy of the drop through h + d, "
          "less the work of a lift force L_dev·W_drop applied by a lift device (L_dev = 0 when "
          "lift is not simulated or is represented by a reduced drop mass, which applies no force)",
    "E4": "W_implied = E_d/(h + (1 − L_dev)·d): the drop weight the absorbed energy E_d (E5) "
          "implies; not computable from reported values alone",
    "E5": "E_d = E_s(t_d) + E_t(t_d): the work strut and tyre have absorbed at t_d, the instant "
          "of maximum total travel d (each integral of E1 taken to t_d, not to the element's own "
          "maximum: the element that peaks first gives energy back before t_d). The audit checks "
          "E_d ≤ E_avail (E3): the upper mass is at rest at t_d, so without lift E_d = "
          "W_drop·(h + d) − m2·g·(d − δ(t_d)) − ½·m2·δ̇(t_d)². From reported values E_d is not "
          "known (E_s and E_t each run to their own maximum, so their sum counts twice what the "
          "first-peaking element gives back); the audit then checks each of E_s and E_t alone "
          "against E_avail, which holds for any drop, and their sum with a wider tolerance",
    "W1": "W_drop = m_drop·g for a single-unit drop; for a drop of the complete airplane each "
          "unit's share W_drop = W_unit·m_drop·g/W_max",
    "G1": "ground-reaction factor F_peak/W_unit",
    "G2": "combined ground-reaction factor ΣF_peak(main units)/(m_drop·g) (sum of the main-unit "
          "peaks, whether or not they coincide in time; nose unit not included)",
    "V1": "v_0 = √(2·g·h), free drop without losses",
    "V2": "v_0 measured: derivative at touchdown of a parabola fitted to the drop-mass "
          f"displacement over the {VELOCITY_WINDOW * 1e3:g} ms before touchdown",
    "B1": "bottoming margin = design stroke − d_s",
    "R1": "rebound: minimum stroke after the maximum; lift-off: time the load stays below "
          f"{_share(TOUCHDOWN_SHARE)} of the static weight after the peak",
    "S1": f"settling time: from touchdown until the stroke stays within ±{_share(SETTLING_BAND)} "
          f"of its maximum around its final value (mean of the last {_share(FINAL_SHARE)} of the "
          f"record)",
}

#: Standard gravity used for kgf and weight conversions.
GRAVITY_NOTE = "g = 9.80665 m/s² (standard gravity; 1 kgf = 9.80665 N)"
