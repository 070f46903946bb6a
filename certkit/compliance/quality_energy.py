"""Data-quality checks of energy: what strut and tyre absorbed against what the drop supplied.

The relations (docs/audit-checklist.md lists them with their sources):

* an element absorbs no more than the rectangle under its peak force, E ≤ F_peak·δ_max
  (η ≤ 1), and a tyre whose force rises at least linearly with deflection no more than
  half of it (η_t ≤ 0.5);
* the work absorbed by the instant of maximum total travel is what the drop supplied,
  E_d ≤ W_drop·(h + d) − L_dev·W_drop·d (certkit E3, E5);
* from reported values, where E_d is not known, each element alone is bounded by the same
  energy, and their sum exceeds it only by what the element that peaks first gives back;
* the two main units of an airplane absorb no more than the whole airplane supplies;
* the drop weight the energy implies is the weight dropped, the same in every run.
"""

from __future__ import annotations

from certkit.compliance.assessment import Assessment, GearResult, RunResult
from certkit.compliance.clauses import available_energy
from certkit.compliance.drop_conditions import lift_force_ratio
from certkit.compliance.findings import add, gear_items, not_checked, shown
from certkit.display import number
from certkit.units import STANDARD_GRAVITY

#: Tyre efficiency ceiling: a tyre whose force rises linearly or faster with deflection
#: absorbs at most half the rectangle F_peak·δ_max (for F = k·δⁿ, ∫F dδ = F_peak·δ_max/(n + 1)
#: with n ≥ 1).
TYRE_EFFICIENCY_CEILING = 0.5


def _assumed(assessment: Assessment, run: RunResult, gear: GearResult) -> str:
    """The assumptions W_drop and d rest on, in words ('' when none): the inclination where
    it is assumed, and the unit's static weight where it was assumed, not weighed, and the
    unit's share of a complete-airplane drop is taken from it (certkit W1)."""
    words = []
    if "θ" in gear.assumptions:
        words.append(gear.assumptions["θ"])
    unit = assessment.campaign.gear_units[gear.gear_id]
    if len(run.run.gear_units) > 1 and unit.static_weight_basis == "assumed":
        words.append(f"the unit's share of the drop weight rests on its assumed static "
                     f"weight {unit.static_weight.text}")
    return "; ".join(words)


def check_energy_bounds(assessment: Assessment) -> None:
    """E ≤ F_peak·δ_max for strut and tyre (η ≤ 1), η > 0, tyre η ≤ 0.5."""
    for run, gear in gear_items(assessment):
        for element, name in (("s", "strut"), ("t", "tyre")):
            eta = gear.get(f"eta_{element}")
            if eta is None:
                continue
            energy = gear.get(f"E_{element}")
            # the rectangle η is taken against (certkit E2); η > 0 wherever it is used
            bound = energy / eta if eta > 0 else None
            rectangle = "F_peak·cos θ·d_s" if element == "s" else "F_peak·d_t"
            where = f"run {run.run.id}, {gear.gear_id}"
            if eta > 1:
                add(assessment, f"energy-exceeds-bound-{name}", "error", run.run.id, gear.gear_id,
                    f"{where}: {name} energy {shown(assessment, energy, 'energy')} exceeds "
                    f"{rectangle} = {shown(assessment, bound, 'energy')} (η = {eta:.4g} > 1): "
                    f"impossible for any {name}; check the energy integral, the load or the "
                    f"travel", eta=eta, energy=energy, bound=bound)
            elif eta <= 0:
                add(assessment, f"efficiency-not-positive-{name}", "error", run.run.id,
                    gear.gear_id, f"{where}: {name} efficiency η = {eta:.4g} is not positive",
                    eta=eta)
            elif element == "t" and eta > TYRE_EFFICIENCY_CEILING:
                add(assessment, "tyre-efficiency-above-half", "warning", run.run.id, gear.gear_id,
                    f"{where}: tyre efficiency η_t = {number(eta)} exceeds "
                    f"{TYRE_EFFICIENCY_CEILING}, the ceiling for a tyre whose force rises at "
                    f"least linearly with deflection; check the tyre energy integral and the "
                    f"deflection channel", eta=eta)


def check_available_energy(assessment: Assessment) -> None:
    """The absorbed energy cannot exceed what the drop supplied (certkit E5 against E3).

    From time histories: E_d = E_s(t_d) + E_t(t_d) ≤ E_avail = W_drop·(h + d) − L_dev·W_drop·d,
    within ``audit.energy_tolerance``.  By the instant t_d of maximum total travel the upper
    mass m1 is at rest, so for the two-mass gear on a rigid platform (unsprung mass m2)
    E_d = W_drop·h + m1·g·d + m2·g·δ(t_d) − ½·m2·δ̇(t_d)² ≤ W_drop·(h + d), less the lift
    device's work.  An error: the data cannot be right (a warning where it rests on an
    assumed input).

    From reported values E_d is not known: E_s and E_t each run to their own maximum.  Each
    alone is bounded by E_avail on any drop (an error past ``energy_tolerance``).  Their sum
    exceeds E_avail by what the element that peaks first gives back before the other peaks:
    a few per cent on a typical gear, more on a heavily damped strut on a stiff tyre, so a
    sum past ``audit.energy_sum_tolerance`` is a warning that asks for the energies at
    maximum travel.
    """
    settings = assessment.campaign.spec.audit
    tolerance, sum_tolerance = settings.energy_tolerance.si, settings.energy_sum_tolerance.si
    for run, gear in gear_items(assessment):
        available = gear.get("E_avail")
        where = f"run {run.run.id}, {gear.gear_id}"
        if available is None:
            if gear.get("E_s") is not None or gear.get("E_t") is not None:
                not_checked(assessment, "energy-exceeds-available", where,
                            f"E_avail needs the total travel d: {gear.values['d'].note}")
            continue
        assumed = _assumed(assessment, run, gear)
        severity = "warning" if assumed else "error"
        suffix = f"; computed with {assumed}" if assumed else ""
        absorbed = gear.get("E_d")
        if absorbed is not None:
            candidates = [("E_d", "the work strut and tyre absorbed up to the instant of "
                                  "maximum total travel", absorbed)]
        elif gear.measures is not None:
            add(assessment, "energy-balance-not-checked", "warning", run.run.id, gear.gear_id,
                f"{where}: the absorbed energy is not checked against the energy available "
                f"(certkit E5 against E3): E_d {gear.values['E_d'].note}; declare it so that "
                f"the check runs", reason=gear.values["E_d"].note)
            continue
        else:
            candidates = [(key, f"the {name} energy alone, as reported", gear.get(key))
                          for key, name in (("E_s", "strut"), ("E_t", "tyre"))
                          if gear.get(key) is not None]
        over = [(symbol, what, energy) for symbol, what, energy in candidates
                if energy > available * (1 + tolerance)]
        for symbol, what, energy in over:
            add(assessment, "energy-exceeds-available", severity, run.run.id, gear.gear_id,
                f"{where}: {symbol} = {shown(assessment, energy, 'energy')} ({what}; "
                f"certkit E5) exceeds the energy available W_drop·(h + d) − L_dev·W_drop·d "
                f"= {shown(assessment, available, 'energy')} by "
                f"{energy / available - 1:.1%} (tolerance {tolerance:.0%}){suffix}; check the "
                f"energy integral, the drop height and the drop weight",
                absorbed=energy, available=available)
        if absorbed is None and not over and gear.get("E_s") is not None \
                and gear.get("E_t") is not None:
            total = gear.get("E_s") + gear.get("E_t")
            if total > available * (1 + sum_tolerance):
                add(assessment, "energy-sum-exceeds-available", "warning", run.run.id,
                    gear.gear_id,
                    f"{where}: E_s + E_t = {shown(assessment, gear.get('E_s'), 'energy')} + "
                    f"{shown(assessment, gear.get('E_t'), 'energy')} = "
                    f"{shown(assessment, total, 'energy')} exceeds the energy available "
                    f"W_drop·(h + d) − L_dev·W_drop·d = {shown(assessment, available, 'energy')}"
                    f" by {total / available - 1:.1%} (tolerance {sum_tolerance:.0%}). Each "
                    f"energy runs to its own peak, so a valid drop over-counts a little (a few "
                    f"per cent on a typical gear); this much needs explaining: report the "
                    f"energies at maximum total travel (E_d) or the time histories, and check "
                    f"the drop height and weight{suffix}",
                    absorbed=total, available=available)


def _airplane_units(assessment: Assessment, run: RunResult) -> list[GearResult]:
    return [gear for gear in run.gears
            if assessment.campaign.gear_units[gear.gear_id].position == "main"]


def check_airplane_energy(assessment: Assessment) -> None:
    """The main units of a complete-airplane drop absorb together no more than the whole
    airplane supplies: ΣE ≤ m_drop·g·(h + d̄) − L_dev·m_drop·g·d̄ (certkit E3 for the airplane),
    d̄ the mean total travel of the main units standing for the travel of the centre of
    gravity (the airplane dropped level, the nose unit's travel not known).  The nose unit
    absorbs energy too, so the mains' share alone being above the whole is the stronger
    finding.  Unlike the per-unit check it does not rest on how the weight is split among
    the units.  E_d where known, else E_s + E_t to their own peaks; tolerance
    ``audit.energy_sum_tolerance`` either way (d̄ is an approximation).  A warning."""
    tolerance = assessment.campaign.spec.audit.energy_sum_tolerance.si
    for run in assessment.runs:
        mains = _airplane_units(assessment, run)
        if len(run.run.gear_units) < 2 or len(mains) < 2:
            continue
        absorbed, travels, basis = [], [], "E_d"
        for gear in mains:
            energy = gear.get("E_d")
            if energy is None and None not in (gear.get("E_s"), gear.get("E_t")):
                energy, basis = gear.get("E_s") + gear.get("E_t"), "E_s + E_t"
            absorbed.append(energy)
            travels.append(gear.get("d"))
        if None in absorbed or None in travels:
            not_checked(assessment, "airplane-energy-exceeds-available", f"run {run.run.id}",
                        "needs the absorbed energy and the total travel of every main unit")
            continue
        weight = run.run.drop_mass.si * STANDARD_GRAVITY
        h, lift = run.run.drop_height.si, lift_force_ratio(run.run)
        mean_travel = sum(travels) / len(travels)
        supplied = available_energy(weight, h, mean_travel, lift)
        total = sum(absorbed)
        if total > supplied * (1 + tolerance):
            listing = " + ".join(shown(assessment, e, "energy") for e in absorbed)
            arithmetic = (f"{shown(assessment, weight, 'force')} × ("
                          f"{shown(assessment, h, 'length')} + "
                          f"{shown(assessment, mean_travel, 'length')})" if lift == 0 else
                          f"{shown(assessment, weight, 'force')} × ({shown(assessment, h, 'length')}"
                          f" + {1 - lift:.4g} × {shown(assessment, mean_travel, 'length')})")
            add(assessment, "airplane-energy-exceeds-available", "warning", run.run.id, None,
                f"run {run.run.id}: the main units together absorb {basis} = {listing} = "
                f"{shown(assessment, total, 'energy')}, {total / supplied - 1:.1%} more than "
                f"the whole airplane supplies, m_drop·g·(h + d̄) − L_dev·m_drop·g·d̄ = "
                f"{arithmetic} = {shown(assessment, supplied, 'energy')} (d̄ the main units' "
                f"mean travel; "
                f"tolerance {tolerance:.0%}), before the nose unit takes its share; check the "
                f"drop height, the drop mass and the energy integrals",
                absorbed=total, supplied=supplied)


def check_implied_drop_weight(assessment: Assessment) -> None:
    """The drop weight implied by the absorbed energy is the declared one and is constant.

    From E_d (time histories with the unsprung mass declared): W_implied = E_d/(h + (1 − L)·d)
    against W_drop within ``audit.drop_mass_spread``, and its ratio to W_drop the same in every
    run.  From reported values only the spread is checked, on the upper bound
    (E_s + E_t)/(h + (1 − L)·d): the overcount of separately peaking energies changes
    little from one drop height to the next, so the ratio stays within
    ``audit.reported_energy_spread`` on a consistent campaign.
    """
    settings = assessment.campaign.spec.audit
    spread = settings.drop_mass_spread.si
    implied = [(run, gear, gear.get("W_implied")) for run, gear in gear_items(assessment)
               if gear.get("W_implied") is not None]
    for run, gear, weight in implied:
        declared = gear.get("W_drop")
        if abs(weight / declared - 1) > spread:
            add(assessment, "implied-drop-weight", "warning", run.run.id, gear.gear_id,
                f"run {run.run.id}, {gear.gear_id}: the absorbed energy implies a drop weight of "
                f"{shown(assessment, weight, 'force')}, {weight / declared - 1:+.1%} from the "
                f"{shown(assessment, declared, 'force')} dropped (tolerance ±{spread:.0%}); "
                f"check the drop weight, the drop height and the load calibration",
                implied=weight, declared=declared)
    upper = []
    for run, gear in gear_items(assessment):
        d, e_s, e_t = gear.get("d"), gear.get("E_s"), gear.get("E_t")
        if gear.get("W_implied") is None and None not in (d, e_s, e_t):
            h, lift = run.run.drop_height.si, lift_force_ratio(run.run)
            upper.append((run, gear, (e_s + e_t) / (h + (1 - lift) * d)))
    for run, gear in gear_items(assessment):
        if gear.get("W_implied") is None and gear.gear_id not in {g.gear_id for _, g, _ in upper}:
            not_checked(assessment, "implied-drop-weight", f"run {run.run.id}, {gear.gear_id}",
                        f"needs E_d ({gear.values['E_d'].note or 'not known'}) or the reported "
                        f"strut and tyre energies with the travel")
    _spread(assessment, implied, spread, "the absorbed energy E_d")
    _spread(assessment, upper, settings.reported_energy_spread.si,
            "the reported energies, (E_s + E_t)/(h + (1 − L_dev)·d) (an upper bound whose overcount "
            "changes little with height)")


def _spread(assessment: Assessment, implied, spread: float, source: str) -> None:
    # each implied weight is compared with the weight that run dropped: a reserve drop made
    # lighter on purpose (23.727(b)) is not a spread
    by_gear: dict[str, list] = {}
    for run, gear, weight in implied:
        by_gear.setdefault(gear.gear_id, []).append((run.run.id, weight, gear.get("W_drop")))
    for gear_id, items in by_gear.items():
        if len(items) < 2:
            continue
        ratios = [w / dropped for _, w, dropped in items]
        low, high = min(ratios), max(ratios)
        if high + low <= 0:
            continue   # no energy in any run: the efficiency check says so
        share = (high - low) / (0.5 * (high + low))
        if share > spread:
            listing = ", ".join(f"{run_id}: {shown(assessment, w, 'force')} of "
                                f"{shown(assessment, dropped, 'force')} dropped"
                                for run_id, w, dropped in items)
            add(assessment, "implied-drop-weight-spread", "warning", None, gear_id,
                f"{gear_id}: the drop weight implied by {source}, as a share of the weight "
                f"dropped, varies across runs by {share:.0%} (tolerance {spread:.0%}; "
                f"{listing}); one measuring chain implies the same share in every run: check "
                f"the energies, heights and weights of the runs that stand out", values=[w for _, w, _ in items])
