"""Regenerate the planning campaign's SYNTHETIC logger files (data/D06.csv ...).

Run:  .venv/bin/python campaigns/lsa-main-gear-rig/synthesise.py [--check]

The rig does not exist yet: this campaign plans its drops.  Its logger files are simulated
here, as the rig's 2 kHz logger would write them, in the rig's own imperial units.  The
script takes the campaign's spec, applies the "truth" below (how the simulated strut differs
from the spec's nominal drop model, as a serviced strut differs from its drawing), simulates
every run with certkit's library call (:func:`certkit.physics.synthetic.simulate_campaign`, which
writes SI columns t_s / N / mm with sensor noise but without offsets or quantisation), then
rewrites each file as the logger would: time in ms from the start of the record, load in lbf
(0.1 lbf steps), stroke, tyre deflection and drop-carriage displacement in inches (0.001 in
steps), the carriage accelerometer in g (0.001 g steps, specific force: it reads 0 g in free
fall), with a zero offset on the load cell and the two travel transducers.  The offsets are
printed as the runs' data blocks, which campaign.yaml carries as written here.  With
``--check`` the script writes nothing and fails when the committed files differ from a fresh
simulation (tests/test_second_example.py runs it).

The truth (the nominal drop model is the spec's: rebound orifice and seal friction):
- discharge coefficient 0.62 (spec 0.6);
- pre-charge 168 psi gauge (spec 160 psi: the strut serviced 5 % high);
- seal friction 15 lbf + 3 % of the gas force (spec 12 lbf + 3 %);
- tyre hysteresis 6 %, an effect the spec's model leaves out (for the gap diagnosis).
"""

from __future__ import annotations

import csv
import sys
import tempfile
from pathlib import Path

import numpy as np
import yaml

HERE = Path(__file__).resolve().parent
SEED = 2026
EFFECTS = ["rebound-orifice", "seal-friction", "tyre-hysteresis"]
TRUTH = {"strut": {"discharge_coefficient": 0.62, "gas_precharge_pressure": "168 psi",
                   "seal_friction": {"constant": "15 lbf", "pressure_factor": "3 %"}},
         "tyre": {"hysteresis": "6 %"}}
LEAD = 0.1                         # s of free fall recorded before contact
DURATION = 1.4                     # s recorded from contact: 1.5 s records at 2 kHz
GEAR = "main-right"

# unit conversions, exact by definition (NIST SP 811, appendix B)
LBF = 4.4482216152605              # N
INCH = 0.0254                      # m
G0 = 9.80665                       # m/s^2

# the logger's resolution and the sensor noise (one standard deviation), in column units
STEP = {"Fz_lbf": 0.1, "stroke_in": 0.001, "tyre_in": 0.001, "acc_g": 0.001, "disp_in": 0.001}
NOISE_SI = {"load": 1.5 * LBF, "travel": 0.001 * INCH, "acceleration": 0.005 * G0,
            "displacement": 0.001 * INCH}
OFFSET_RANGE = {"Fz_lbf": 4.0, "stroke_in": 0.008, "tyre_in": 0.008}   # zero offsets: ±this


def truth_spec(folder: Path) -> Path:
    """The campaign spec with the truth applied and no data blocks, written into ``folder``."""
    from certkit.physics.synthetic import truth_spec as write_truth

    return write_truth(HERE / "campaign.yaml", folder, {GEAR: TRUTH}, EFFECTS)


def _counts(values: np.ndarray, step: float) -> np.ndarray:
    return np.rint(values / step).astype(np.int64)


def _text(counts: np.ndarray, step: float) -> list[str]:
    decimals = len(f"{step:g}".split(".")[1]) if "." in f"{step:g}" else 0
    return [f"{c * step:.{decimals}f}" for c in counts]


def _imperial(si_file: Path, out_file: Path, rng: np.random.Generator) -> dict:
    """Rewrite one SI record as the rig's logger writes it; returns the run's data block."""
    with si_file.open(encoding="utf-8") as handle:
        rows = list(csv.reader(handle))
    header, body = rows[0], np.array(rows[1:], dtype=float)
    si = {name: body[:, i] for i, name in enumerate(header)}
    offsets = {name: _counts(np.array(rng.uniform(-span, span)), STEP[name]) * STEP[name]
               for name, span in OFFSET_RANGE.items()}
    physical = {
        "Fz_lbf": si[f"{GEAR}_load_N"] / LBF,
        "stroke_in": si[f"{GEAR}_stroke_mm"] * 1e-3 / INCH,
        "tyre_in": si[f"{GEAR}_tyre_mm"] * 1e-3 / INCH,
        "acc_g": si["acc_ms2"] / G0 + 1.0,     # an accelerometer reads dv/dt + g
        "disp_in": si["x_mm"] * 1e-3 / INCH,
    }
    columns = {"time_ms": _text(_counts((si["t_s"] + LEAD) * 1e3, 0.5), 0.5)}
    for name, values in physical.items():
        columns[name] = _text(_counts(values + offsets.get(name, 0.0), STEP[name]), STEP[name])
    with out_file.open("w", encoding="utf-8", newline="\n") as handle:
        handle.write(",".join(columns) + "\n")
        for row in zip(*columns.values()):
            handle.write(",".join(row) + "\n")

    def offset(name: str) -> float:
        return round(float(offsets[name]), 6)

    return {
        "file": f"data/{out_file.name}", "origin": "synthetic",
        "time": {"column": "time_ms", "unit": "ms"},
        "gears": {GEAR: {
            "vertical_load": {"column": "Fz_lbf", "unit": "lbf", "offset": offset("Fz_lbf")},
            "strut_stroke": {"column": "stroke_in", "unit": "in", "offset": offset("stroke_in")},
            "tyre_deflection": {"column": "tyre_in", "unit": "in", "offset": offset("tyre_in")}}},
        "drop_mass_acceleration": {"column": "acc_g", "unit": "g0", "reference": "specific_force"},
        "drop_mass_displacement": {"column": "disp_in", "unit": "in"},
    }


def generate(out: Path) -> dict[str, dict]:
    """Write the logger files into ``out`` (a new folder); returns run id -> data block."""
    from certkit import load_campaign
    from certkit.physics.synthetic import SensorModel, simulate_campaign

    sensors = SensorModel(load_noise=NOISE_SI["load"], load_step=0.0, load_offset=0.0,
                          travel_noise=NOISE_SI["travel"], travel_step=0.0, travel_offset=0.0,
                          acceleration_noise=NOISE_SI["acceleration"], acceleration_step=0.0,
                          displacement_noise=NOISE_SI["displacement"], displacement_step=0.0)
    out.mkdir(parents=True)
    blocks = {}
    with tempfile.TemporaryDirectory() as scratch:
        spec = truth_spec(Path(scratch))
        written = simulate_campaign(load_campaign(spec), Path(scratch) / "si", seed=SEED,
                                    sensors=sensors, duration=DURATION, lead=LEAD)
        runs = yaml.safe_load(written.read_text(encoding="utf-8"))["runs"]
        for index, run in enumerate(runs):
            rng = np.random.default_rng([SEED, index, 1])
            blocks[run["id"]] = _imperial(written.parent / run["data"]["file"],
                                          out / f"{run['id']}.csv", rng)
    return blocks


def main() -> int:
    from certkit.physics.synthetic import check_requested, write_or_check

    check = check_requested(__doc__)
    with tempfile.TemporaryDirectory() as scratch:
        fresh_dir = Path(scratch) / "data"
        blocks = generate(fresh_dir)
        status = write_or_check(sorted(fresh_dir.glob("*.csv")), HERE / "data", check)
        if not check:
            print("the runs' data blocks are:")
            for run_id, block in blocks.items():
                print(yaml.safe_dump({run_id: block}, sort_keys=False, width=100))
    return status


if __name__ == "__main__":
    sys.exit(main())
