"""The logger's sample rate is the campaign's, not an assumed 1 kHz: the same drops logged at
2 kHz and at 1 kHz give the same compliance verdicts, values within the sampling's own
resolution, and comparable identified models."""

import numpy as np
import pytest
import yaml

from certkit import assess, load_campaign
from certkit.gear_identification import MODEL_RATE, WINDOW, at_model_rate, identify_gear
from certkit.compliance.measures import axle_acceleration
from certkit.physics.synthetic import NO_SENSOR_EFFECTS, simulate_campaign

from .conftest import PHYSICS_SPEC, write_campaign

# Hyper-parameters fixed (the seed's orders kept): tuning on a coarse grid picks other values
# for data that differ by far less than any rate effect (at 1 kHz, only another noise seed
# moved the NARX held-out stroke RMSE from 1.96 to 7.29 mm), which is not what is tested here.
# The Hammerstein γ is 1e4, not 1e6: at 1e6 its fit is so weakly regularised that the
# sub-0.1 mm differences the low-pass makes moved its held-out stroke RMSE from 2.77 to
# 2.06 mm on one machine (not on another); a conditioning question for the engines, not
# the rate handling tested here, which is held to the same 5 % as the other models.
IDENTIFICATION = {"hammerstein": {"na": 6, "nb": 4, "gamma": 1e4, "sigma2": 1e3},
                  "wiener": {"na": 6, "nb": 4, "gamma": 1e4, "sigma2": 10},
                  "narx": {"na": 2, "nb": 2, "gamma": 1e4, "sigma2": 1e3}}


@pytest.fixture(scope="module")
def logged(tmp_path_factory):
    """The physics campaign's three drops simulated without sensor noise and logged at
    2 kHz, and the same files with every other row: what a 1 kHz logger records of the
    same signals.  Returns (2 kHz spec, 1 kHz spec)."""
    root = tmp_path_factory.mktemp("rate")
    raw = yaml.safe_load(PHYSICS_SPEC)
    raw["instrumentation"]["sampling_rate"] = "2000 Hz"
    raw["model"]["identification"] = IDENTIFICATION
    truth = write_campaign(root / "truth", yaml.safe_dump(raw, sort_keys=False))
    fast = simulate_campaign(load_campaign(truth), root / "fast", sensors=NO_SENSOR_EFFECTS,
                             duration=1.5)
    raw = yaml.safe_load(fast.read_text(encoding="utf-8"))
    for run in raw["runs"]:
        run["data"]["origin"] = "measured"     # compliance evidence, unlike synthetic files
    fast.write_text(yaml.safe_dump(raw, sort_keys=False), encoding="utf-8")
    slow = root / "slow"
    (slow / "data").mkdir(parents=True)
    for path in (fast.parent / "data").glob("*.csv"):
        lines = path.read_text(encoding="utf-8").splitlines()
        (slow / "data" / path.name).write_text("\n".join(lines[:1] + lines[1::2]) + "\n",
                                               encoding="utf-8")
    raw["instrumentation"]["sampling_rate"] = "1000 Hz"
    for run in raw["runs"]:
        run["data"]["sampling_rate"] = "1000 Hz"
    return fast, write_campaign(slow, yaml.safe_dump(raw, sort_keys=False))


def test_compliance_at_2_khz_matches_the_same_drops_at_1_khz(logged):
    fast, slow = (assess(load_campaign(spec)) for spec in logged)
    assert [(v.id, v.verdict) for v in fast.verdicts] == [(v.id, v.verdict) for v in slow.verdicts]
    assert sorted((f.id, f.severity) for f in fast.findings) == sorted(
        (f.id, f.severity) for f in slow.findings)
    assert fast.outcome == slow.outcome
    # Tolerances from the sampling's resolution (T = 1 ms; a maximum sampled at T/2 or T is
    # off by at most ½·|x''|·(T/2)²): peak load F'' ≈ F_peak·(π/0.1 s)² ≈ 1.5e7 N/s², so
    # ≤ 2 N, 1.3e-4 of 15 kN; travels s'' ≤ F_peak/m1 ≈ 51 m/s², so ≤ 6.4 µm.  Energies
    # are integrated to fourth order; their strut force differs by m2·Δδ̈, the 20 ms
    # Savitzky-Golay estimate over 21 or 41 samples (about 1 % apart on a 30 Hz sinusoid,
    # test below), on 9 kg × a few hundred m/s² against some 10 kN: ≤ 0.3 %.
    for run_fast, run_slow in zip(fast.runs, slow.runs):
        a, b = run_fast.gears[0], run_slow.gears[0]
        assert a.get("F_peak") == pytest.approx(b.get("F_peak"), rel=1e-3)
        for key in ("d_s", "d_t", "d"):
            assert a.get(key) == pytest.approx(b.get(key), abs=2e-5), key
        for key in ("E_s", "E_t", "E_avail", "eta_s", "eta_t", "W_implied"):
            assert a.get(key) == pytest.approx(b.get(key), rel=3e-3), key
        assert a.measures.energy_at_max_travel == pytest.approx(
            b.measures.energy_at_max_travel, rel=3e-3)
        assert a.get("t0") == pytest.approx(b.get("t0"), abs=1e-3)   # one 1 kHz sample


def test_identification_at_2_khz_runs_on_the_1_khz_grid_and_matches(logged):
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):     # as certkit.gear_identification.identify runs them
        fast, slow = (identify_gear(load_campaign(spec), "left-main") for spec in logged)
    # every drop is taken at the model's rate: 1 s from touchdown, 1 ms apart, at either rate
    for run, drop in fast.measured.items():
        other = slow.measured[run]
        assert drop.load.size == other.load.size == WINDOW == 1000
        assert np.allclose(np.diff(drop.time), 1 / MODEL_RATE, rtol=1e-9)
        assert drop.time[0] == pytest.approx(other.time[0], abs=1e-3)
        # the same samples, but for the 2 kHz record's anti-alias low-pass rounding the
        # touchdown kink (the tyre deflects about 2.4 mm per ms there) and ringing for a few
        # of its 2.5 ms periods: under 0.1 mm, and 1 µm from 20 ms after touchdown
        for output in ("stroke", "tyre"):
            difference = np.abs(drop.outputs[output] - other.outputs[output])
            assert difference.max() < 0.1 and difference[20:].max() < 1e-3, (run, output)
    assert {(s.model, s.protocol, s.output) for s in fast.scores} == {
        (s.model, s.protocol, s.output) for s in slow.scores}
    slow_scores = {(s.model, s.protocol, s.output): s.rmse for s in slow.scores}
    for score in fast.scores:
        reference = slow_scores[(score.model, score.protocol, score.output)]
        if score.model.startswith("governing equation"):
            # noise-free: both are the model's own error, ~0.01 mm, and the kink's rounding
            assert score.rmse == pytest.approx(reference, abs=5e-3), score.model
        else:
            # 5 %, or 0.2 mm: twice the largest change the low-pass makes to the recorded
            # outputs (0.1 mm above), which the free-run models copy as initial samples
            assert score.rmse == pytest.approx(reference, rel=0.05, abs=0.2), (
                score.model, score.protocol, score.output)


def test_axle_acceleration_is_a_20_ms_cubic_fit_at_any_rate():
    from scipy.special import spherical_jn

    # δ = A·sin(ωt), f = 30 Hz: a least-squares cubic over a window T returns at its centre
    # δ̈ = −ω²·A·15·j2(a)/a², a = ωT/2 (only P2 of the Legendre expansion has a second
    # derivative at the centre; ∫P2(x)·cos(ax) dx = −2·j2(a)).  T = 20 ms gives 0.770;
    # n samples act as T = n/rate (0.749 for 21 at 1 kHz, 0.760 for 41 at 2 kHz); the
    # 21 samples of 10 ms at 2 kHz that a sample-count window would use give 0.938.
    omega = 2 * np.pi * 30.0
    a = omega * 0.020 / 2
    expected = 15 * spherical_jn(2, a) / a ** 2
    for rate in (1000.0, 2000.0, 4000.0):
        t = np.arange(0.0, 0.5, 1 / rate)
        acceleration = axle_acceleration(t, 1e-3 * np.sin(omega * t))
        middle = slice(t.size // 4, 3 * t.size // 4)
        gain = np.max(np.abs(acceleration[middle])) / (omega ** 2 * 1e-3)
        assert gain == pytest.approx(expected, rel=0.03), rate


def test_records_are_brought_to_the_model_rate():
    # a 1 kHz record is used as logged; 2 kHz and 500 Hz records of y = sin(2π·20 t) + t are
    # resampled onto a 1 kHz grid from their first sample (the anti-alias low-pass passes
    # 20 Hz; the cubic spline interpolates a 500 Hz record to ~(ωT)⁴/384 = 5e-6)
    t = np.arange(0.0, 1.0, 1e-3)
    channels = {"load": np.sin(t), "tyre": None}
    assert at_model_rate(t, channels) == (t, channels)

    def signal(time):
        return np.sin(2 * np.pi * 20 * time) + time

    for rate in (2000.0, 500.0):
        time = 0.0137 + np.arange(int(1.0 * rate)) / rate
        grid, resampled = at_model_rate(time, {"load": signal(time), "tyre": None})
        assert grid[0] == time[0] and np.allclose(np.diff(grid), 1e-3, rtol=1e-9)
        assert resampled["tyre"] is None
        inner = slice(50, -50)    # the filter's and spline's ends aside
        assert np.max(np.abs(resampled["load"] - signal(grid))[inner]) < 1e-4, rate
