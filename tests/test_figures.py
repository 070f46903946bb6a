"""Plotted lines are thinned to what a page shows, and never lose a peak."""

from __future__ import annotations

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
    record of about 1,500 samples, not of the record."""

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
        length, force, energy, velocity = "mm", "kN", "J", "m/s"

    svgs = [f["svg"] for f in figures.run_figures("D1", Series.time, {"main": (Series,
                                                                               Measures)},
                                                  1.0, Units)]
    assert len(svgs) == 3
    for svg in svgs:
        assert len(svg.encode()) < 250_000, len(svg.encode())
