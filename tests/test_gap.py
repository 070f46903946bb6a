"""Where the gap lies: the residual map of a nominal model against runs whose truth has
an effect the model leaves out."""

import pytest

from certkit import load_campaign
from certkit.gap import default_split, residual_map
from certkit.phases import PHASES
from certkit.synthetic import simulate_campaign


@pytest.fixture(scope="module")
def with_hysteresis(tmp_path_factory):
    from .conftest import PHYSICS_SPEC, write_campaign

    # truth: the spec's gear with 8 % tyre hysteresis on; the diagnosed model has none
    text = PHYSICS_SPEC.replace("      damping: 0.05 s/m\n",
                                "      damping: 0.05 s/m\n      hysteresis: 8 %\n").replace(
        "  effects: [rebound-orifice, seal-friction]",
        "  effects: [rebound-orifice, seal-friction, tyre-hysteresis]")
    root = tmp_path_factory.mktemp("gap")
    return simulate_campaign(load_campaign(write_campaign(root / "truth", text)), root / "runs",
                             seed=11)


def test_default_split_holds_out_the_highest_drop(with_hysteresis):
    assert default_split(load_campaign(with_hysteresis), "left-main") == (["D200", "D250"],
                                                                          ["D300"])


def test_residual_map_covers_every_channel_phase_and_run(with_hysteresis):
    gap = residual_map(load_campaign(with_hysteresis), "left-main")
    assert gap.training == ("D200", "D250") and gap.held_out == ("D300",)
    keys = {(c.run, c.channel, c.phase) for c in gap.cells}
    for run in ("D200", "D250", "D300"):
        for channel in ("load", "stroke", "tyre"):
            assert {(run, channel, phase) for phase in PHASES} <= keys
    # before contact both the model and the (zeroed) measurement are at rest: the free-fall
    # residual is sensor noise only (20 N load, 0.05 mm travel)
    free_fall = [c for c in gap.cells if c.phase == "free fall"]
    assert all(c.rms < (60.0 if c.channel == "load" else 1.5e-4) for c in free_fall)
    # the unmodelled tyre loop leaves a residual well above the noise somewhere after contact
    assert gap.largest is not None and gap.largest.phase != "free fall"
    assert gap.largest.run in gap.training and "largest disagreement" in gap.summary
    for shares in gap.bands.values():
        assert sum(shares.values()) == pytest.approx(1.0)
