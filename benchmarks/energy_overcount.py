"""How far reported energies, each taken to its own peak, exceed the energy available on a
consistent drop: the evidence behind the audit's ``energy_sum_tolerance``,
``reported_energy_spread`` and ``static_stroke_tolerance``.

Run:  .venv/bin/python benchmarks/energy_overcount.py        (about a minute on one core)

Each example campaign's first gear unit in its last run (campaigns/seed-amphibian,
campaigns/lsa-main-gear-rig) is simulated with certkit's two-mass drop model (the scipy
reference integrator) over a grid: tyre stiffness ×0.4/1/2.5, orifice diameter ×0.7/1/1.4,
upper mass ×0.7/1/1.3, unsprung mass ×0.5/1/3, drop heights 0.05/0.1/0.2/0.3/0.5 m.  For each
drop the work done on strut and tyre up to each one's own maximum travel (what a table of
reported E_s and E_t holds), against W·(h + d_s + d_t) (the audit's energy available from
reported maxima).  Printed: the distribution of the excess, the largest change of the
implied-weight ratio across heights for one gear, and the smallest ratio of maximum
stroke to the gas-law static stroke.
"""

from __future__ import annotations

import blas_threads  # noqa: F401  (first: pins the BLAS threads before numpy is loaded)

# isort: split
import itertools
import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from certkit import load_campaign
from certkit.physics.gear_model import drop_model_for
from certkit.physics.simulation import simulate_reference
from certkit.units import STANDARD_GRAVITY

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ("campaigns/seed-amphibian/campaign.yaml", "campaigns/lsa-main-gear-rig/campaign.yaml")
GRID = dict(tyre=(0.4, 1.0, 2.5), orifice=(0.7, 1.0, 1.4), mass=(0.7, 1.0, 1.3),
            unsprung=(0.5, 1.0, 3.0))
HEIGHTS = (0.05, 0.1, 0.2, 0.3, 0.5)


def _spread(ratios: list[float]) -> float:
    return (max(ratios) - min(ratios)) / (0.5 * (max(ratios) + min(ratios)))


def main() -> None:
    excess, spreads, middle, narrow, static = [], [], [], [], []
    for spec in EXAMPLES:
        campaign = load_campaign(ROOT / spec)
        run = campaign.spec.runs[-1]
        base = drop_model_for(campaign.spec, run, run.gear_units[0])
        for tyre, orifice, mass, unsprung in itertools.product(*GRID.values()):
            model = replace(base, upper_mass=base.upper_mass * mass,
                            lower_mass=base.lower_mass * unsprung,
                            tyre=replace(base.tyre,
                                         reference_load=base.tyre.reference_load * tyre),
                            orifice=replace(base.orifice,
                                            orifice_area=base.orifice.orifice_area * orifice ** 2))
            ratios = {}
            for height in HEIGHTS:
                drop = simulate_reference(model, math.sqrt(2 * STANDARD_GRAVITY * height),
                                          duration=1.0, rtol=1e-7, atol=1e-10)
                strut, tyre_energy = drop.absorbed_on_loading()
                weight = model.total_mass * STANDARD_GRAVITY
                available = weight * (height + drop.stroke.max() + drop.tyre.max())
                ratios[height] = (strut + tyre_energy) / available
                excess.append(ratios[height] - 1)
                if model.static_stroke() > 0:   # else the pre-charge holds the gear topped out
                    static.append(drop.stroke.max() / model.static_stroke())
            spreads.append(_spread(list(ratios.values())))
            middle.append(_spread([ratios[0.1], ratios[0.2], ratios[0.3]]))
            narrow.append(_spread([ratios[0.2], ratios[0.3]]))
    excess = np.array(excess)
    print(f"{excess.size} consistent drops (two example gears, grid above)")
    print(f"(E_s + E_t)/(W·(h + d_s + d_t)) - 1: median {np.median(excess):.1%}, "
          f"95th percentile {np.percentile(excess, 95):.1%}, largest {excess.max():.1%}")
    print(f"implied-weight ratio spread across 0.05-0.5 m, largest: {max(spreads):.1%}; "
          f"across 0.1-0.3 m: {max(middle):.1%}; across 0.2-0.3 m: {max(narrow):.1%}")
    print(f"maximum stroke / gas-law static stroke, smallest: {min(static):.3f}")


if __name__ == "__main__":
    main()
