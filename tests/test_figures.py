"""Plotted lines are thinned to what a page shows, and never lose a peak."""

from __future__ import annotations

import re

import numpy as np

from certkit.evidence import figures
from certkit.evidence.figures import COLUMNS, kept


def test_a_short_record_keeps_every_sample():
    assert np.array_equal(kept(np.arange(2 * COLUMNS)), np.arange(2 * COLUMNS))


def test_a_long_record_keeps_its_peaks_and_at_most_two_samples_a_column_and_the_ends():
    rng = np.random.default_rng(7)
    size = 1_000_003
    load = rng.normal(0.0, 1.0, size)
    load[123_457] = 50.0          # a one-sample spike, the record's peak
    load[876_543] = -40.0         # and its trough
    shown = kept(load)
    assert 123_457 in shown and 876_543 in shown
    assert shown[0] == 0 and shown[-1] == size - 1
    assert np.all(np.diff(shown) > 0)                       # in time order, no repeats
    assert len(shown) <= 2 * COLUMNS + COLUMNS + 1          # min, max and start of a column
    # every column's extremes: the thinned line spans what the record spans in each
    edges = np.linspace(0, size, COLUMNS + 1).astype(int)
    for start, stop in zip(edges[:-1:50], edges[1::50]):
        inside = shown[(shown >= start) & (shown < stop)]
        assert load[inside].max() == load[start:stop].max()
        assert load[inside].min() == load[start:stop].min()


def test_a_loop_keeps_the_extremes_of_both_coordinates():
    phase = np.linspace(0.0, 6.0 * np.pi, 200_000)
    stroke, load = np.sin(phase) * np.exp(-phase / 20), np.cos(phase) ** 3
    shown = kept(stroke, load)
    for curve in (stroke, load):
        assert curve[shown].max() == curve.max() and curve[shown].min() == curve.min()


def test_a_long_logger_record_draws_a_figure_of_bounded_size():
    """30 s at 20 kHz (600,000 samples a channel): the figures' SVG stays at the size of a
    record of about 1,500 samples, not of the record.  An SVG path vertex takes about 25
    bytes ("L 123.456 78.901" and a line break), so a thinned line (at most 3·COLUMNS + 1
    = 1,501 vertices) is under 40 kB, the load-travel figure (its loop drawn and filled)
    under 80 kB, plus some 20 kB of axes and text: 250 kB holds with room, while one
    unthinned line alone would take about 600,000 × 25 bytes = 15 MB."""

    class Series:
        rate = 20_000.0
        time = np.arange(0.0, 30.0, 1.0 / rate)
        load = 1e4 * np.exp(-((time - 1.0) / 0.05) ** 2) + np.random.default_rng(1).normal(
            0, 20, time.size)
        stroke = 0.1 * np.clip(time - 1.0, 0, 0.2)
        tyre = None

    class Measures:
        strut_energy = 1234.0
        tyre_energy = None

    class Units:
        length, force, energy, velocity, time = "mm", "kN", "J", "m/s", "ms"

    svgs = [f["svg"] for f in figures.run_figures("D1", Series.time, {"main": (Series,
                                                                               Measures)},
                                                  1.0, Units)]
    assert len(svgs) == 3
    for svg in svgs:
        assert len(svg.encode()) < 250_000, len(svg.encode())


def test_phase_boundaries_a_few_ms_apart_are_numbered_apart_on_the_impact_panel():
    """The example's held-out drop starts four phases within 40 ms of a 1.1 s window: their
    names (and then their numbers) printed at the boundaries ran into each other.  The left
    column shows the impact (to twice the rebound's start, 80 ms here), where 0, 8, 15 and
    40 ms stand 10-31 % of its width apart; the right column the whole second, where only the
    settling boundary is numbered; the caption names each with its time."""
    from types import SimpleNamespace

    time = np.arange(-0.1, 1.0, 0.001)
    after = time >= 0.0
    load = np.where(after, 1e4 * np.exp(-((time - 0.04) / 0.03) ** 2), 0.0)
    record = SimpleNamespace(time=time, after=after, measured={"load": load},
                             simulated={"load": 0.98 * load})
    starts = {"free fall": 0, "tyre-only contact": 100, "strut breakout": 108,
              "compression": 115, "rebound": 140, "settling": 650}
    phases = [SimpleNamespace(name=name, start=start) for name, start in starts.items()]

    class Units:
        force, length, time = "N", "mm", "ms"

    figure = figures.gap_overlay("main", "D3", record, record, phases, "friction", Units,
                                 window=1.0)
    # sample k after touchdown at 1 kHz is k ms, printed to 4 significant digits
    assert ("1 tyre-only contact at 0 ms; 2 strut breakout at 8.000 ms; 3 compression at "
            "15.00 ms; 4 rebound at 40.00 ms; 5 settling at 550.0 ms.") in figure["caption"]
    assert "Left: the impact, to 80.00 ms after touchdown" in figure["caption"]
    svg = figure["svg"]
    for name in starts:
        assert name not in svg        # no name printed in the plot
    numbers = re.findall(r'<text style="font-size: 6px[^"]*"[^>]* x="([\d.]+)" '
                         r'y="([\d.]+)"[^>]*>([1-5])</text>', svg)
    # each boundary numbered once, all on one row
    assert sorted(n for _, _, n in numbers) == ["1", "2", "3", "4", "5"]
    assert len({y for _, y, _ in numbers}) == 1
    x = {n: float(v) for v, _, n in numbers}
    # on the left panel (80 ms wide) 8 ms is a tenth of its width: the numbers stand apart
    assert x["1"] < x["2"] < x["3"] < x["4"] < x["5"]
    assert min(x["2"] - x["1"], x["3"] - x["2"]) > 0.05 * (x["4"] - x["1"]) / 0.4
