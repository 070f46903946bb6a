"""Regenerate the example campaign's SYNTHETIC time histories (data/D200.csv ...).

Run:  .venv/bin/python campaigns/seed-amphibian/synthesise.py [--check]

The seed paper does not publish its raw drop-test data, so the example campaign carries
simulated logger files instead.  This script is their provenance: it takes the example's
own spec, applies the "truth" below (how the simulated gear differs from the spec's
nominal drop model, as a real gear differs from its drawing), simulates every run with
`certkit simulate`'s library call at a fixed seed, and writes data/<run>.csv.  With
``--check`` it writes nothing and fails when the committed files differ from a fresh
simulation (tests/test_example_data.py runs this).

The truth, per gear unit (the nominal model is the spec's: rebound orifice and seal friction):
- both: tyre hysteresis 6 % (an effect the spec's model leaves out, for the gap diagnosis);
- left-main: discharge coefficient 0.59, seal friction 100 N + 3 %;
- right-main: pre-charge 0.88 MPa, tyre 4 % stiffer, discharge coefficient 0.61
  (the paper's right gear strokes and deflects less than its left).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import yaml

HERE = Path(__file__).resolve().parent
SEED = 2024
EFFECTS = ["rebound-orifice", "seal-friction", "tyre-hysteresis"]
TRUTH = {
    "left-main": {"strut": {"discharge_coefficient": 0.59,
                            "seal_friction": {"constant": "100 N", "pressure_factor": "3 %"}},
                  "tyre": {"hysteresis": "6 %"}},
    "right-main": {"strut": {"discharge_coefficient": 0.61, "gas_precharge_pressure": "0.88 MPa"},
                   "tyre": {"hysteresis": "6 %",
                            "load_deflection": {"reference_load": "12970.64 N",  # 1.04 x 12471.77
                                                "reference_deflection": "40 mm",
                                                "exponent": 1.26}}},
}
RECORD = {"duration": 1.9, "lead": 0.1}   # 2 s per drop at 1 kHz, as the paper's logger


def truth_spec(folder: Path) -> Path:
    """The example spec with the truth applied and no data blocks, written into ``folder``."""
    from certkit.physics.synthetic import truth_spec as write_truth

    return write_truth(HERE / "campaign.yaml", folder, TRUTH, EFFECTS)


def generate(out: Path) -> Path:
    from certkit import load_campaign
    from certkit.physics.synthetic import simulate_campaign

    with tempfile.TemporaryDirectory() as scratch:
        spec = truth_spec(Path(scratch))
        return simulate_campaign(load_campaign(spec), out, seed=SEED, **RECORD)


def main() -> int:
    from certkit.physics.synthetic import check_requested, write_or_check

    check = check_requested(__doc__)
    with tempfile.TemporaryDirectory() as scratch:
        written = generate(Path(scratch) / "synthetic")
        status = write_or_check(sorted((written.parent / "data").glob("*.csv")), HERE / "data",
                                check)
        if not check:
            mapping = yaml.safe_load(written.read_text(encoding="utf-8"))
            print("the runs' data blocks are:")
            for run in mapping["runs"]:
                print(yaml.safe_dump({run["id"]: run["data"]}, sort_keys=False, width=100))
    return status


if __name__ == "__main__":
    sys.exit(main())
