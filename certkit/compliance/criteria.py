"""The criteria of a requirement set, one check each: verdicts from an assessment's values.

A requirement set (:mod:`certkit.spec.requirement_sets`) names, for each criterion, the
check here that evaluates it (``CHECKS``).  Every comparison against a limit goes through
:func:`at_least` or :func:`at_most`: one rule for ties and typed resolution.
"""

from __future__ import annotations

from dataclasses import dataclass

from certkit.compliance.assessment import Assessment, BasisResult, RunResult
from certkit.results import EQUALITY_TOLERANCE, FAIL, NOT_SHOWN, PASS, Verdict
from certkit.spec.requirement_sets import Criterion, RequirementSet


@dataclass
class _Context:
    assessment: Assessment
    basis: BasisResult

    @property
    def rules(self) -> RequirementSet:
        return self.basis.rules

    def verdict(self, criterion: Criterion, run: str | None, gear: str | None, state: str,
                **fields) -> Verdict:
        parts = [criterion.id] + [part for part in (run, gear) if part]
        return Verdict(id="/".join(parts), requirement_set=self.rules.id, criterion=criterion.id,
                       clause=criterion.clause, title=criterion.title, formula=criterion.formula,
                       run=run, gear=gear, verdict=state, to_confirm=self.rules.to_confirm,
                       **fields)


#: What holds back a verdict that needs the design limit inertia load factor, and what
#: would show it (one cover line for every such verdict).
NO_DESIGN_LOAD_FACTOR = {
    "shortfall": "the design limit inertia load factor is not declared",
    "remedy": "declare aircraft.design_limit_inertia_load_factor (from the loads report)"}
LOAD_FACTOR_EXCEEDED = {
    "shortfall": "the load factor exceeds the design limit inertia load factor",
    "remedy": "the airframe is loaded beyond its design: revisit the design load factor or "
              "the shock absorber"}
#: The drop each test type needs, as the cover page asks for it.
_NEEDED_DROP = {"limit": ("limit", "from at least h_req (23.725(a))"),
                "reserve": ("reserve energy", "from at least 1.44·h_req (23.727(a))"),
                "dynamic": ("ground load dynamic", "from at least 2.25·h_req (23.726(a))")}


def _no_drop(test_type: str) -> dict:
    """Shortfall and remedy of a verdict that has no drop of ``test_type`` to look at."""
    what, height = _NEEDED_DROP[test_type]
    return {"shortfall": f"no {what} drop in the test matrix",
            "remedy": f"add a {what} drop (runs[].test_type: {test_type}) {height}"}


def _runs_of(assessment: Assessment, test_type: str) -> list[RunResult]:
    return [run for run in assessment.runs if run.run.test_type == test_type]


def _slack(value: float, limit: float, resolution: float | None) -> float:
    slack = EQUALITY_TOLERANCE * max(abs(value), abs(limit))
    return slack if resolution is None else min(slack, resolution)


def at_least(value: float, limit: float, resolution: float | None = None) -> str:
    """PASS when ``value`` is not less than ``limit``: equality holds, as "not less than" in
    14 CFR 23.725-23.727.  Equal means within :data:`~certkit.results.EQUALITY_TOLERANCE`
    (relative), and never more than ``resolution``: half a unit in the last digit of the
    typed value the criterion turns on (its ``stated_resolution_si``)."""
    return PASS if value >= limit - _slack(value, limit, resolution) else FAIL


def at_most(value: float, limit: float, resolution: float | None = None) -> str:
    """PASS when ``value`` does not exceed ``limit``, equality included (as :func:`at_least`)."""
    return PASS if value <= limit + _slack(value, limit, resolution) else FAIL


def _typed_resolution(quantity, value: float) -> float | None:
    """Half a unit in the last typed digit of ``quantity``, scaled to ``value`` (the same
    relative resolution), None for a quantity not typed."""
    if quantity is None or quantity.si == 0:
        return None
    return abs(value) * quantity.stated_resolution_si / abs(quantity.si)


def _height_check(ctx: _Context, criterion: Criterion, test_type: str, required_key: str,
                  what: str) -> list[Verdict]:
    required = ctx.basis.values.get(required_key)
    runs = _runs_of(ctx.assessment, test_type)
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, limit=required.value, unit="m",
                            kind="length", reason=f"no {what} drop in the test matrix",
                            **_no_drop(test_type))]
    verdicts = []
    for run in runs:
        h = run.get("h")
        verdicts.append(ctx.verdict(
            criterion, run.run.id, None,
            at_least(h, required.value, run.run.drop_height.stated_resolution_si), value=h,
            limit=required.value, margin=h - required.value, unit="m", kind="length",
            reason=f"{what} drop from {run.run.drop_height.text}",
            shortfall=f"the {what} drop height is below the required height",
            remedy="repeat the drop from at least the required height"))
    return verdicts


def check_limit_drop_height(ctx, criterion):
    return _height_check(ctx, criterion, "limit", "h_req", "limit")


def check_reserve_drop_height(ctx, criterion):
    return _height_check(ctx, criterion, "reserve", "h_reserve", "reserve energy")


def check_dynamic_drop_height(ctx, criterion):
    """23.726(a): 2.25·h_req, or (option 2) a height developing 1.5 times the limit load factor."""
    required = ctx.basis.values["h_dynamic"]
    runs = _runs_of(ctx.assessment, "dynamic")
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, limit=required.value, unit="m",
                            kind="length", reason="no ground load dynamic drop in the test matrix",
                            **_no_drop("dynamic"))]
    n_limit = ctx.assessment.design["n_limit"].value
    n_limit_typed = ctx.assessment.campaign.spec.aircraft.design_limit_inertia_load_factor
    verdicts = []
    for run in runs:
        h = run.get("h")
        if at_least(h, required.value, run.run.drop_height.stated_resolution_si) == PASS:
            verdicts.append(ctx.verdict(criterion, run.run.id, None, PASS, value=h,
                                        limit=required.value, margin=h - required.value,
                                        unit="m", kind="length", reason="option (1): 2.25·h_req"))
            continue
        factors = [gear.get("n") for gear in run.gears]
        if n_limit is None or None in factors:
            verdicts.append(ctx.verdict(
                criterion, run.run.id, None, NOT_SHOWN, value=h, limit=required.value,
                margin=h - required.value, unit="m", kind="length",
                reason="below 2.25·h_req; option (2) needs n measured and n_limit declared",
                shortfall="the dynamic drop is below 2.25·h_req and option (2) lacks the "
                          "measured n or the declared n_limit",
                remedy="record the drop-mass acceleration and declare "
                       "aircraft.design_limit_inertia_load_factor, or drop from 2.25·h_req"))
            continue
        n = max(factors)
        verdicts.append(ctx.verdict(
            criterion, run.run.id, None,
            at_least(n, 1.5 * n_limit, _typed_resolution(n_limit_typed, 1.5 * n_limit)), value=n,
            limit=1.5 * n_limit, margin=n - 1.5 * n_limit,
            reason="option (2): height developing 1.5 times the limit load factor",
            shortfall="the dynamic drop develops less than 1.5 times the limit load factor",
            remedy="drop from 2.25·h_req, or from a height developing 1.5·n_limit"))
    return verdicts


def check_reserve_no_failure(ctx, criterion):
    runs = _runs_of(ctx.assessment, "reserve")
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN,
                            reason="no reserve energy drop in the test matrix",
                            **_no_drop("reserve"))]
    verdicts = []
    for run in runs:
        inspection = run.run.inspection
        if ctx.assessment.planning:
            verdicts.append(ctx.verdict(criterion, run.run.id, None, NOT_SHOWN,
                                        reason="a planning campaign: whether the gear fails is "
                                               "found by inspecting it after the drop, which no "
                                               "simulation predicts",
                                        shortfall="a planning campaign cannot show that the "
                                                  "gear does not fail",
                                        remedy="inspect the gear after the real reserve drop "
                                               "(runs[].inspection.failure)"))
        elif inspection is None or inspection.failure is None:
            verdicts.append(ctx.verdict(criterion, run.run.id, None, NOT_SHOWN,
                                        reason="post-test inspection result not recorded",
                                        shortfall="the post-test inspection of the reserve "
                                                  "drop is not recorded",
                                        remedy="record runs[].inspection.failure (and "
                                               "yielding) of the reserve drop"))
        else:
            verdicts.append(ctx.verdict(
                criterion, run.run.id, None, FAIL if inspection.failure else PASS,
                reason=("failure reported" if inspection.failure else "no failure reported")
                + (f"; yielding: {'yes' if inspection.yielding else 'no'}"
                   if inspection.yielding is not None else ""),
                shortfall="the gear failed in the reserve drop",
                remedy="repair or redesign the gear and repeat the reserve drop"))
    return verdicts


def _effective_weight_check(ctx, criterion, test_type: str, what: str) -> list[Verdict]:
    """W_drop ≥ W_e per gear unit of each ``test_type`` drop (W_e: the gear's W1 share
    against the clause's effective weight, computed with the measured d)."""
    maximum = ctx.rules.number("wing_lift_ratio_maximum")
    runs = _runs_of(ctx.assessment, test_type)
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, unit="N", kind="force",
                            reason=f"no {what} drop in the test matrix",
                            **_no_drop(test_type))]
    verdicts = []
    for run in runs:
        lift = run.get("L")
        method = run.run.lift.method
        if method != "none" and test_type == "limit":
            verdicts.append(ctx.verdict(
                criterion, run.run.id, None,
                at_most(lift, maximum, _typed_resolution(run.run.lift.ratio, lift)), value=lift,
                limit=maximum, margin=maximum - lift, comparison="≤",
                reason=f"wing-lift ratio L represented in the drop ({method})",
                shortfall="the wing lift represented in the drop exceeds the maximum",
                remedy="represent no more wing lift than the maximum and repeat the drop"))
        reason = {"none": "no lift simulated: W_e = W",
                  "lift_device": "lift by a device: the full weight W is dropped",
                  "reduced_mass": ("reserve drop, W_e = W·h/(h + d), d as recorded"
                                   if test_type == "reserve" else
                                   f"reduced mass, L = {lift:g}, d as recorded (23.725(d))")}[method]
        for gear in run.gears:
            w_e, w_drop = gear.get("W_e"), gear.get("W_drop")
            static_weight = ctx.assessment.campaign.gear_units[gear.gear_id].static_weight
            if w_e is None:
                verdicts.append(ctx.verdict(criterion, run.run.id, gear.gear_id, NOT_SHOWN,
                                            unit="N", kind="force",
                                            reason="d (tyre deflection + axle travel) unknown",
                                            shortfall="d (tyre deflection + axle travel) is "
                                                      "not known, so W_e cannot be computed",
                                            remedy="record or report the strut stroke and the "
                                                   "tyre deflection of the drop"))
                continue
            verdicts.append(ctx.verdict(
                criterion, run.run.id, gear.gear_id,
                at_least(w_drop, w_e, min(_typed_resolution(run.run.drop_mass, w_drop),
                                          _typed_resolution(static_weight, w_e))),
                value=w_drop,
                limit=w_e, margin=w_drop - w_e, unit="N", kind="force", reason=reason,
                shortfall="the weight dropped is below the effective weight W_e",
                remedy="ballast the drop to at least W_e and repeat it"))
    return verdicts


def check_effective_weight(ctx, criterion):
    """23.725(b),(d): limit drops."""
    return _effective_weight_check(ctx, criterion, "limit", "limit")


def check_reserve_effective_weight(ctx, criterion):
    """23.727(b): reserve energy drops, W_e = W·h/(h + d) when lift is simulated."""
    return _effective_weight_check(ctx, criterion, "reserve", "reserve energy")


def check_inertia_load_factor(ctx, criterion):
    n_limit = ctx.assessment.design["n_limit"].value
    n_limit_typed = ctx.assessment.campaign.spec.aircraft.design_limit_inertia_load_factor
    runs = _runs_of(ctx.assessment, "limit")
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, limit=n_limit,
                            reason="no limit drop in the test matrix", **_no_drop("limit"))]
    verdicts = []
    for run in runs:
        for gear in run.gears:
            n = gear.get("n")
            if n is None:
                verdicts.append(ctx.verdict(criterion, run.run.id, gear.gear_id, NOT_SHOWN,
                                            limit=n_limit, comparison="≤",
                                            reason="drop-mass acceleration not recorded, so n_j "
                                                   "(23.725(e)) is unknown",
                                            shortfall="the drop-mass acceleration is not "
                                                      "recorded, so n_j (23.725(e)) is unknown",
                                            remedy="record the drop-mass acceleration in the "
                                                   "limit drops (runs[].data."
                                                   "drop_mass_acceleration)"))
            elif n_limit is None:
                verdicts.append(ctx.verdict(criterion, run.run.id, gear.gear_id, NOT_SHOWN,
                                            value=n, comparison="≤",
                                            reason="design limit inertia load factor not declared",
                                            **NO_DESIGN_LOAD_FACTOR))
            else:
                verdicts.append(ctx.verdict(
                    criterion, run.run.id, gear.gear_id,
                    at_most(n, n_limit, _typed_resolution(n_limit_typed, n_limit)),
                    value=n, limit=n_limit, margin=n_limit - n, comparison="≤",
                    reason=gear.values["n"].formula, **LOAD_FACTOR_EXCEEDED))
    return verdicts


def check_energy_method_load_factor(ctx, criterion):
    rules = ctx.rules
    lift = rules.number("energy_method_wing_lift_ratio")
    eta_t, eta_s = rules.number("tyre_efficiency"), rules.number("shock_absorber_efficiency")
    n_limit = ctx.assessment.design["n_limit"].value
    n_limit_typed = ctx.assessment.campaign.spec.aircraft.design_limit_inertia_load_factor
    runs = _runs_of(ctx.assessment, "limit")
    if not runs:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, limit=n_limit, comparison="≤",
                            reason="no limit drop in the test matrix", **_no_drop("limit"))]
    verdicts = []
    for run in runs:
        for gear in run.gears:
            n = gear.get(f"n_energy[{rules.id}]")
            if n is None:
                verdicts.append(ctx.verdict(criterion, run.run.id, gear.gear_id, NOT_SHOWN,
                                            limit=n_limit, comparison="≤",
                                            reason="strut and tyre travel needed",
                                            shortfall="the strut stroke and the tyre "
                                                      "deflection of the limit drop are not "
                                                      "known",
                                            remedy="record or report the strut stroke and the "
                                                   "tyre deflection of the limit drop"))
            elif n_limit is None:
                verdicts.append(ctx.verdict(
                    criterion, run.run.id, gear.gear_id, NOT_SHOWN, value=n, comparison="≤",
                    reason=f"design limit inertia load factor not declared "
                           f"(n = n_j + L with L = {lift:.4g}, η_t = {eta_t}, η_s = {eta_s})",
                    **NO_DESIGN_LOAD_FACTOR))
            else:
                verdicts.append(ctx.verdict(
                    criterion, run.run.id, gear.gear_id,
                    at_most(n, n_limit, _typed_resolution(n_limit_typed, n_limit)),
                    value=n, limit=n_limit, margin=n_limit - n, comparison="≤",
                    reason=f"n = n_j + L, L = {lift:.4g}, η_t = {eta_t}, η_s = {eta_s}",
                    **LOAD_FACTOR_EXCEEDED))
    return verdicts


def check_design_load_factor_minimum(ctx, criterion):
    n_limit = ctx.assessment.design["n_limit"].value
    n_limit_typed = ctx.assessment.campaign.spec.aircraft.design_limit_inertia_load_factor
    lift = ctx.assessment.design["L_design"].value
    minimum = max(ctx.rules.number("inertia_load_factor_minimum"),
                  ctx.rules.number("ground_reaction_factor_minimum") + lift)
    if n_limit is None:
        return [ctx.verdict(criterion, None, None, NOT_SHOWN, limit=minimum,
                            reason="design limit inertia load factor not declared",
                            **NO_DESIGN_LOAD_FACTOR)]
    return [ctx.verdict(criterion, None, None,
                        at_least(n_limit, minimum, _typed_resolution(n_limit_typed, n_limit)),
                        value=n_limit,
                        limit=minimum, margin=n_limit - minimum,
                        reason=f"minimum = max(2.67, 2.0 + L) with L = {lift:g}",
                        shortfall="the declared design limit inertia load factor is below "
                                  "the minimum of 23.473(g)",
                        remedy="design the landing cases for at least the minimum load "
                               "factor")]


def check_attitude_and_drag(ctx, criterion):
    """14 CFR 23.725(c): the attitude and the drag loads of the drops must represent the
    landing conditions.  certkit has no measure of either, so the verdict is NOT SHOWN
    always; its reason quotes what the spec's ``setup`` states, for the reviewer to judge."""
    setup = ctx.assessment.campaign.spec.setup
    stated = [f"{label}: {text}" for label, text in
              (("attitude", setup and setup.attitude), ("drag loads", setup and setup.drag_loads))
              if text]
    reason = ("certkit does not assess whether the gear attitude and the drag (spin-up) loads "
              "represent the landing conditions; " +
              ("the spec states " + "; ".join(stated) if stated else
               "the spec states neither (setup.attitude, setup.drag_loads)") +
              ". To be shown by the applicant and judged by the reviewer.")
    return [ctx.verdict(criterion, None, None, NOT_SHOWN, reason=reason,
                        shortfall="certkit does not assess the gear attitude and the drag "
                                  "(spin-up) loads of the drops",
                        remedy="the applicant shows them and the reviewer judges them "
                               "(setup.attitude, setup.drag_loads)")]


CHECKS = {
    "attitude_and_drag": check_attitude_and_drag,
    "limit_drop_height": check_limit_drop_height,
    "reserve_drop_height": check_reserve_drop_height,
    "dynamic_drop_height": check_dynamic_drop_height,
    "reserve_no_failure": check_reserve_no_failure,
    "effective_weight": check_effective_weight,
    "reserve_effective_weight": check_reserve_effective_weight,
    "inertia_load_factor": check_inertia_load_factor,
    "energy_method_load_factor": check_energy_method_load_factor,
    "design_load_factor_minimum": check_design_load_factor_minimum,
}




def evaluate(assessment: Assessment, basis: BasisResult) -> list[Verdict]:
    """The verdicts of every criterion of ``basis`` that applies to the campaign."""
    ctx = _Context(assessment, basis)
    verdicts = []
    for criterion in basis.rules.criteria:
        if criterion.applies_if and not getattr(basis.entry, criterion.applies_if):
            continue
        verdicts.extend(CHECKS[criterion.check](ctx, criterion))
    return verdicts
