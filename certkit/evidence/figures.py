"""Figures a reviewer would rather look at, as inline SVG with byte-stable output."""

from __future__ import annotations

import contextlib
import io
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from certkit.display import number, pretty, to_display, unit_of, with_unit  # noqa: E402
from certkit.gap.phases import PHASES
from certkit.spec.rundata import CHANNEL_LABELS  # noqa: E402
from certkit.units import convert  # noqa: E402

_STYLE = {
    "svg.hashsalt": "certkit",      # stable element ids across processes
    "svg.fonttype": "none",         # text stays text (searchable, small)
    "font.family": "DejaVu Sans",
    "font.size": 8.0,
    "axes.grid": True,
    "grid.linewidth": 0.4,
    "grid.alpha": 0.5,
    "lines.linewidth": 1.1,
    "figure.dpi": 100,
}
_WIDTH, _HEIGHT = 6.6, 2.6  # inches: fits A4 portrait with 15 mm margins
_LEAD = 0.05                 # seconds shown before touchdown
#: The columns a plotted line is thinned to: a figure's axes are about 5.5 in wide, 500
#: columns of 0.011 in (about two dots of a 150 dpi print each).
COLUMNS = 500


def kept(*curves: np.ndarray) -> np.ndarray:
    """The sample indices a line keeps (min–max decimation): every sample when there are
    at most 2·:data:`COLUMNS`; otherwise the samples are cut into :data:`COLUMNS` runs of
    consecutive samples (columns of the page, for uniformly sampled time) and each run keeps
    its first sample and the lowest and highest sample of every curve (both coordinates of
    a load–travel loop), so no peak, trough or extreme of a loop is lost, whatever the
    logger's rate."""
    size = len(curves[0])
    if size <= 2 * COLUMNS:
        return np.arange(size)
    edges = np.linspace(0, size, COLUMNS + 1).astype(int)
    chosen = [edges[:-1], [size - 1]]
    for curve in curves:
        values = np.asarray(curve, dtype=float)
        for start, stop in zip(edges[:-1], edges[1:]):
            part = values[start:stop]
            if np.isnan(part).all():
                continue
            chosen.append([start + int(np.nanargmin(part)), start + int(np.nanargmax(part))])
    return np.unique(np.concatenate([np.asarray(c, dtype=int) for c in chosen]))


def _time_axis(units) -> tuple[float, str]:
    """(seconds -> the campaign's display time unit, the axis label)."""
    return convert(1.0, "s", units.time), f"time from touchdown [{units.time}]"


def record_label(origin: str) -> str:
    """What a run's recorded channels are called in a legend: by their declared origin."""
    return "measured" if origin == "measured" else "synthetic record"


@contextlib.contextmanager
def _style(extra: dict | None = None):
    """certkit's figure style on top of matplotlib's own defaults, whatever a user's
    matplotlibrc says, so the same inputs draw the same figures on every machine."""
    with plt.rc_context():
        matplotlib.rcdefaults()
        matplotlib.rcParams.update({**_STYLE, **(extra or {})})
        yield


def _to_svg(figure) -> str:
    buffer = io.StringIO()
    figure.savefig(buffer, format="svg", metadata={"Date": None, "Creator": None},
                   bbox_inches="tight")
    plt.close(figure)
    text = buffer.getvalue()
    text = text[text.index("<svg"):]  # drop the XML prolog and DOCTYPE for inline use
    return re.sub(r'\s(width|height)="[\d.]+pt"', lambda m: f' {m.group(1)}="100%"'
                  if m.group(1) == "width" else "", text, count=2)


def run_figures(run_id: str, time: np.ndarray, gears: dict, touchdown: float | None,
                units) -> list[dict]:
    """Load, travel and load-travel figures of one run.

    Parameters
    ----------
    gears : dict
        gear id -> (GearSeries, GearMeasures).
    units : DisplayUnits
        Display units for length and force.

    Returns
    -------
    list of dict
        ``{"title": ..., "caption": ..., "svg": ...}``.
    """
    length_unit, force_unit = units.length, units.force
    start = (touchdown - _LEAD) if touchdown is not None else float(time[0])
    window = time >= start
    to_time, time_label = _time_axis(units)
    t_ms = (time[window] - (touchdown if touchdown is not None else time[0])) * to_time
    figures = []
    with _style():
        figure, axes = plt.subplots(figsize=(_WIDTH, _HEIGHT))
        for gear_id, (series, _) in gears.items():
            load = series.load[window]
            shown = kept(load)
            axes.plot(t_ms[shown], convert(1.0, "N", force_unit) * load[shown], label=gear_id)
        axes.set_xlabel(time_label)
        axes.set_ylabel(f"vertical load [{force_unit}]")
        axes.legend(loc="upper right", frameon=False)
        figures.append({"title": f"Run {run_id}: platform vertical load",
                        "caption": "Vertical load per gear unit against time from touchdown "
                                   "(certkit M3).", "svg": _to_svg(figure)})

        travels = [(g, s) for g, (s, _) in gears.items() if s.stroke is not None or s.tyre is not None]
        if travels:
            figure, axes = plt.subplots(figsize=(_WIDTH, _HEIGHT))
            scale = convert(1.0, "m", length_unit)
            for gear_id, series in travels:
                if series.stroke is not None:
                    stroke = series.stroke[window]
                    shown = kept(stroke)
                    axes.plot(t_ms[shown], scale * stroke[shown], label=f"{gear_id} strut stroke")
                if series.tyre is not None:
                    tyre = series.tyre[window]
                    shown = kept(tyre)
                    axes.plot(t_ms[shown], scale * tyre[shown], linestyle="--",
                              label=f"{gear_id} tyre deflection")
            axes.set_xlabel(time_label)
            axes.set_ylabel(f"travel [{length_unit}]")
            axes.legend(loc="upper right", frameon=False, ncol=2)
            figures.append({"title": f"Run {run_id}: strut stroke and tyre deflection",
                            "caption": "Travel of each element against time from touchdown.",
                            "svg": _to_svg(figure)})

        for gear_id, (series, measures) in gears.items():
            pairs = [(series.stroke, "strut stroke", measures.strut_energy),
                     (series.tyre, "tyre deflection", measures.tyre_energy)]
            pairs = [p for p in pairs if p[0] is not None]
            if not pairs:
                continue
            figure, all_axes = plt.subplots(1, len(pairs), figsize=(_WIDTH, _HEIGHT))
            all_axes = np.atleast_1d(all_axes)
            for axes, (travel, name, energy) in zip(all_axes, pairs):
                x = convert(1.0, "m", length_unit) * travel[window]
                y = convert(1.0, "N", force_unit) * series.load[window]
                end = int(np.argmax(travel[window]))
                loading = kept(x[: end + 1], y[: end + 1])
                axes.fill_between(x[loading], y[loading], alpha=0.25, linewidth=0)
                shown = kept(x, y)
                axes.plot(x[shown], y[shown])
                axes.set_xlabel(f"{name} [{length_unit}]")
                axes.set_ylabel(f"vertical load [{force_unit}]")
                # above the axes, not over the loop (a legend inside covered the curve)
                axes.set_title(f"shaded: absorbed {with_unit(energy, 'energy', units)} (E1)",
                               fontsize=7, loc="left")
            figure.tight_layout()
            figures.append({"title": f"Run {run_id}, {gear_id}: load against travel",
                            "caption": "Shaded: loading stroke from touchdown to maximum travel, "
                                       "whose area is the absorbed energy (certkit E1).",
                            "svg": _to_svg(figure)})
    return figures




def model_figure(gear_id: str, run_id: str, traces: list, units, window: float = 1.0,
                 origin: str = "measured", held_out: bool = False,
                 tabulated: dict | None = None) -> dict:
    """The run's record against nominal and calibrated model, one panel per channel (0 to
    ``window`` s after touchdown); ``origin`` is the run's declared data origin,
    ``held_out`` whether the calibration left the run out.  ``tabulated``: channel -> the
    value (SI) the results table gives for this run when that does not come from this
    record (the source's reported values), drawn as a dotted level so the two are seen side
    by side."""
    recorded = record_label(origin)
    tabulated = tabulated or {}
    to_time, time_label = _time_axis(units)
    with _style():
        figure, all_axes = plt.subplots(len(traces), 1, figsize=(_WIDTH, 0.85 * len(traces) + 0.6),
                                        sharex=True)
        all_axes = np.atleast_1d(all_axes)
        for axes, trace in zip(all_axes, traces):
            kind, si = ("force", "N") if trace.channel == "load" else ("length", "m")
            unit = getattr(units, kind)
            scale = convert(1.0, si, unit)
            within = np.flatnonzero(trace.time <= window)
            shown = within[kept(trace.measured[within], trace.nominal[within],
                                trace.calibrated[within])]
            t_ms = trace.time[shown] * to_time
            axes.plot(t_ms, scale * trace.measured[shown], color="0.55", linewidth=1.6,
                      label=recorded)
            axes.plot(t_ms, scale * trace.nominal[shown], linestyle="--", label="nominal model")
            axes.plot(t_ms, scale * trace.calibrated[shown], label="calibrated model")
            if trace.channel in tabulated:
                axes.axhline(scale * tabulated[trace.channel], color="black", linestyle=":",
                             linewidth=1.0, label="results table (reported)")
            axes.set_ylabel(f"{CHANNEL_LABELS[trace.channel]}\n[{unit}]")
        handles, labels = [], []
        for axes in all_axes:
            for handle, label in zip(*axes.get_legend_handles_labels()):
                if label not in labels:
                    handles.append(handle)
                    labels.append(label)
        # above the panels, never over a curve
        all_axes[0].legend(handles, labels, loc="lower left", bbox_to_anchor=(0.0, 1.02),
                           ncol=len(labels), frameon=False, borderaxespad=0.0)
        all_axes[-1].set_xlabel(time_label)
        figure.tight_layout()
        role = "held out: not fitted" if held_out else "a training run"
        caption = (f"Grey: the run's channels; dashed: the drop model with the spec's "
                   f"nominal parameters; solid: after calibration on the training runs "
                   f"(this run is {role}).")
        if tabulated:
            caption += (" Dotted: the peak values the results table (section 5) gives for "
                        "this run, which are the source's reported values, not this "
                        f"{recorded}'s: the {recorded} was simulated from one gear "
                        "configuration and does not reproduce them, and no verdict rests "
                        "on it.")
        return {"title": f"Run {run_id}, {gear_id}: {recorded} and governing-equation model",
                "caption": caption, "svg": _to_svg(figure)}




def identification_figures(gear, units, origin: str = "measured") -> list[dict]:
    """Static nonlinearities, the held-out drop against every model and the models' errors
    of one gear unit (identification works in kN and mm; drawn in the display units).
    ``origin``: the held-out run's declared data origin."""
    figures = []
    outputs = ("stroke", "tyre")
    held = gear.measured[gear.held_out[0]]
    recorded = record_label(origin)
    force = convert(1e3, "N", units.force)     # one kN in the display force unit
    length = convert(1e-3, "m", units.length)  # one mm in the display length unit
    # a Wiener block whose static gain is not determined is scaled to unit ‖b‖: its output
    # z is then no force, and drawn on the load axis it would dwarf the others
    unscaled = [(model, name) for (model, name), block in gear.linear_blocks.items()
                if not block.gain_determined]
    with _style():
        figure, all_axes = plt.subplots(1, 2, figsize=(_WIDTH, _HEIGHT))
        for axes, output in zip(all_axes, outputs):
            for (model, name), (grid, curve) in gear.nonlinearities.items():
                if name == output and (model, name) not in unscaled:
                    axes.plot(force * np.asarray(grid), length * np.asarray(curve), label=model)
            axes.set_xlabel(f"vertical load [{units.force}]")
            axes.set_ylabel(f"{CHANNEL_LABELS[output]} [{units.length}]")
            if axes.get_legend_handles_labels()[0]:   # the models drawn differ per output
                # above the panel, never over a curve
                axes.legend(loc="lower left", bbox_to_anchor=(0.0, 1.02), frameon=False,
                            fontsize=6.0, ncol=2, borderaxespad=0.0)
        figure.tight_layout()
        left_out = "".join(
            f" Not drawn: {model} for the {CHANNEL_LABELS[name]}, whose linear block's static "
            f"gain is not determined (scaled to unit ‖b‖, so its z is no force)."
            for model, name in unscaled)
        figures.append({"title": f"{gear.gear_id}: static nonlinearities",
                        "caption": "Wiener: f(z) against the linear block's output z "
                                   f"({units.force}), the block scaled to unit static gain; "
                                   "Hammerstein: f(u) with the linear block scaled to unit "
                                   "static gain, up to its offset. Fitted on the training runs "
                                   f"({', '.join(gear.training)})." + left_out,
                        "svg": _to_svg(figure)})
        to_time, time_label = _time_axis(units)
        t_ms = held.time * to_time
        figure, all_axes = plt.subplots(2, 1, figsize=(_WIDTH, 4.2), sharex=True)
        for axes, output in zip(all_axes, outputs):
            measured = held.outputs[output]
            shown = kept(measured)
            axes.plot(t_ms[shown], length * measured[shown], color="0.55", linewidth=1.6,
                      label=recorded)
            for score in gear.scores:
                if (score.protocol == "held-out" and score.output == output
                        and score.run == gear.held_out[0]):
                    shown = kept(score.simulated)
                    axes.plot(t_ms[shown], length * score.simulated[shown], linewidth=0.9,
                              label=score.model)
            axes.set_ylabel(f"{CHANNEL_LABELS[output]}\n[{units.length}]")
        # above the panels, never over a curve
        all_axes[0].legend(loc="lower left", bbox_to_anchor=(0.0, 1.02), frameon=False,
                           fontsize=6.5, ncol=4, borderaxespad=0.0)
        all_axes[-1].set_xlabel(time_label)
        figure.tight_layout()
        figures.append({
            "title": (f"{gear.gear_id}, held-out run {gear.held_out[0]}: {recorded} and "
                      f"free-run simulated"),
            "caption": "Every model simulated in free run from the load alone (the "
                       "Hammerstein and NARX models take their first samples from the "
                       "record); none was fitted or tuned on this run. Each model's error "
                       "over the run is in the table above.",
            "svg": _to_svg(figure)})
    return figures


def gap_heatmap(gap, title: str, caption: str, vmax: float | None = None) -> dict:
    """Residual RMS over the channel's RMS (%) per channel × phase (rows) and run (columns)
    of a :class:`certkit.gap.diagnosis.GapMap`; one colour scale up to ``vmax`` (a fraction; default:
    the largest cell) so that two maps drawn with the same ``vmax`` compare."""

    runs = list(gap.training) + list(gap.held_out)
    by_key = {(c.run, c.channel, c.phase): c.normalised for c in gap.cells}
    channels = [ch for ch in ("load", "stroke", "tyre") if any(k[1] == ch for k in by_key)]
    rows = [(ch, ph) for ch in channels for ph in PHASES
            if any((run, ch, ph) in by_key for run in runs)]
    values = np.array([[by_key.get((run, ch, ph), np.nan) for run in runs] for ch, ph in rows],
                      dtype=float)
    finite = values[np.isfinite(values)]
    top = vmax if vmax is not None else (float(finite.max()) if finite.size else 1.0)
    top = top if top > 0 else 1.0
    with _style({"axes.grid": False}):
        figure, axes = plt.subplots(figsize=(_WIDTH, 0.15 * len(rows) + 1.0))
        mesh = axes.pcolormesh(np.ma.masked_invalid(100.0 * values), cmap="Blues", vmin=0.0,
                               vmax=100.0 * top, edgecolors="white", linewidth=0.5)
        for i in range(len(rows)):
            for j in range(len(runs)):
                value = values[i, j]
                text = "—" if not np.isfinite(value) else number(100.0 * value)
                axes.text(j + 0.5, i + 0.5, text, ha="center", va="center", fontsize=6.0,
                          color="white" if np.isfinite(value) and value > 0.6 * top else "black")
        axes.set_xticks(np.arange(len(runs)) + 0.5,
                        [f"{run}\n(held out)" if run in gap.held_out else f"{run}\n(training)"
                         for run in runs])
        axes.set_yticks(np.arange(len(rows)) + 0.5,
                        [f"{CHANNEL_LABELS[ch]} · {ph}" for ch, ph in rows], fontsize=6.5)
        axes.invert_yaxis()
        axes.xaxis.tick_top()
        bar = figure.colorbar(mesh, ax=axes, fraction=0.05, pad=0.02)
        bar.set_label("residual RMS / channel RMS [%]")
        figure.tight_layout()
        return {"title": title, "caption": caption, "svg": _to_svg(figure)}


def gap_overlay(gear_id: str, run_id: str, before, after, phases, label_after: str | None,
                units, window: float, origin: str = "measured") -> dict:
    """A held-out run's channels against the calibrated bare model and (``after``) the
    model with the named effects, with the recorded run's phase boundaries drawn and
    numbered: on the left the impact (touchdown to a few times the end of the compression,
    where the first phases lie a few milliseconds apart), on the right the whole window to
    ``window`` s after touchdown.

    ``before``, ``after``: :class:`certkit.physics.calibration.AlignedRecord`; ``phases``: the
    measured run's :class:`certkit.gap.phases.Phase` list."""
    touchdown = float(before.time[before.after][0])
    t = before.time - touchdown
    to_time, time_label = _time_axis(units)
    boundaries = [(p.name, float(t[p.start])) for p in phases[1:]
                  if -_LEAD <= t[p.start] <= window]
    rebound = next((at for name, at in boundaries if name == "rebound"), None)
    impact = max(0.06, min(window / 3.0, 2.0 * (rebound or 0.03)))
    spans = ((-0.005, impact), (-_LEAD, window))
    channels = list(before.measured)
    records = (before.measured, before.simulated) + ((after.simulated,) if after else ())
    with _style():
        figure, all_axes = plt.subplots(len(channels), 2,
                                        figsize=(_WIDTH, 0.95 * len(channels) + 0.9),
                                        sharex="col", gridspec_kw={"width_ratios": (1, 2)})
        all_axes = np.atleast_2d(all_axes)
        for column, (start, stop) in enumerate(spans):
            within = np.flatnonzero((t >= start) & (t <= stop))
            shown = within[kept(*(record[channel][within] for channel in channels
                                  for record in records))]
            t_ms = t[shown] * to_time
            for axes, channel in zip(all_axes[:, column], channels):
                kind, si = ("force", "N") if channel == "load" else ("length", "m")
                unit = getattr(units, kind)
                scale = convert(1.0, si, unit)
                axes.plot(t_ms, scale * before.measured[channel][shown], color="0.55",
                          linewidth=1.6, label=record_label(origin))
                axes.plot(t_ms, scale * before.simulated[channel][shown], linestyle="--",
                          label="calibrated bare model")
                if after is not None:
                    axes.plot(t_ms, scale * after.simulated[channel][shown],
                              label=f"with {label_after}")
                for _, at in boundaries:
                    if start <= at <= stop:
                        axes.axvline(at * to_time, color="0.3", linestyle=":", linewidth=0.7)
                if column == 0:
                    axes.set_ylabel(f"{CHANNEL_LABELS[channel]}\n[{unit}]")
            # each boundary numbered once, above the column where it stands apart
            for number_, (_, at) in enumerate(boundaries, start=1):
                inside = start <= at <= stop if column == 0 else at > impact
                if inside:
                    all_axes[0, column].text(at * to_time, 1.02, str(number_), ha="center",
                                             va="bottom", fontsize=6.0,
                                             transform=all_axes[0, column].get_xaxis_transform())
            all_axes[-1, column].set_xlabel(time_label)
        all_axes[0, 1].legend(loc="lower right", bbox_to_anchor=(1.0, 1.12), frameon=False,
                              fontsize=6.5, ncol=3, borderaxespad=0.0)
        figure.tight_layout()
        phases_words = ("Dotted lines: the recorded run's phase boundaries, numbered above the "
                        "plot with the phase each starts: "
                        + "; ".join(f"{n} {name} at {with_unit(at, 'time', units)}"
                                    for n, (name, at) in enumerate(boundaries, start=1)) + "."
                        if boundaries else "No phase boundary of the recorded run falls within "
                                           "the plotted window.")
        return {"title": f"{gear_id}, held-out run {run_id}: {record_label(origin)} and model, "
                         f"with the drop's phases",
                "caption": f"Left: the impact, to {with_unit(impact, 'time', units)} after "
                           f"touchdown; right: the whole record to "
                           f"{with_unit(window, 'time', units)}. Grey: the "
                           "run's channels; dashed: the bare model calibrated on the training "
                           "runs; solid: refitted with the named effect(s), when one was named. "
                           + phases_words + " Neither model was fitted or tuned on this run.",
                "svg": _to_svg(figure)}


def missing_force_figure(gear_id: str, forces, units, origins: dict) -> dict:
    """The force the calibrated bare model misses on each run's first compression and
    rebound (:mod:`certkit.gap.missing_force`): the strut's against stroke rate, the tyre's
    against tyre deflection.  A sign(ṡ) step shows as a jump at ṡ = 0, rebound damping as a
    curve on the extension side only, a tyre loop as two branches in δ."""
    force_unit, speed_unit, length_unit = units.force, units.velocity, units.length
    to_force, to_speed, to_length = (convert(1.0, si, unit) for si, unit in
                                     (("N", force_unit), ("m/s", speed_unit),
                                      ("m", length_unit)))
    with _style():
        figure, (strut, tyre) = plt.subplots(1, 2, figsize=(_WIDTH, _HEIGHT + 0.3))
        for force in forces:
            label = f"{force.run} ({record_label(origins.get(force.run, 'measured'))})"
            shown = kept(force.stroke_rate, force.strut_missing)
            strut.plot(to_speed * force.stroke_rate[shown], to_force * force.strut_missing[shown],
                       linewidth=0.9, label=label)
            shown = kept(force.tyre, force.tyre_missing)
            tyre.plot(to_length * force.tyre[shown], to_force * force.tyre_missing[shown],
                      linewidth=0.9, label=label)
        for axes in (strut, tyre):
            axes.axhline(0.0, color="0.3", linewidth=0.6)
        strut.axvline(0.0, color="0.3", linewidth=0.6)
        strut.set_xlabel(f"stroke rate ṡ [{speed_unit}] (> 0: compressing)")
        strut.set_ylabel(f"missing strut force [{force_unit}]")
        tyre.set_xlabel(f"tyre deflection δ [{length_unit}]")
        tyre.set_ylabel(f"missing tyre force [{force_unit}]")
        tyre.legend(loc="lower right", bbox_to_anchor=(1.0, 1.02), frameon=False,
                    fontsize=6.0, ncol=3, borderaxespad=0.0)
        figure.tight_layout()
        return {"title": f"{gear_id}: the force the calibrated bare model misses, from the "
                         f"records alone",
                "caption": "First compression and rebound of each run. Left: the strut force "
                           "the records imply (from the measured load and the axle's "
                           "acceleration) less the calibrated bare model's strut law at the "
                           "measured stroke and stroke rate. Right: the measured load less its tyre "
                           "law at the measured deflection and rate. No candidate effect "
                           "enters these curves.",
                "svg": _to_svg(figure)}


def blind_curve(points, target_top1: float | None, target_shrink: float | None,
                scored_from: float | None = None) -> dict:
    """The blind check's detectability curve: top-1 accuracy and median held-out shrink of
    the single-effect cases against effect size / noise, with the targets drawn."""
    ratios = [p.ratio for p in points]
    with _style():
        figure, axes = plt.subplots(figsize=(_WIDTH * 0.7, _HEIGHT))
        for key, label, marker in (("top1", "top-1 accuracy", "o"),
                                   ("median_shrink", "median held-out load shrink", "s")):
            values = [getattr(p, key) for p in points]
            axes.plot(ratios, [100.0 * v if v is not None else np.nan for v in values],
                      marker=marker, label=label)
        drawn = []
        for target, style, words in ((target_top1, "--", "the top-1 target"),
                                     (target_shrink, ":", "the shrink target")):
            if target is not None:
                axes.axhline(100.0 * target, color="grey", linestyle=style, linewidth=0.8)
                drawn.append(f"{'dashed' if style == '--' else 'dotted'}: {words}")
        axes.set_xscale("log")
        axes.set_xticks(ratios, [f"{r:g}" for r in ratios])
        axes.minorticks_off()
        axes.set_ylim(0, 105)
        axes.set_xlabel("effect size / load noise RMS")
        axes.set_ylabel("top-1 accuracy, median shrink [%]")
        axes.legend(loc="lower right", fontsize=7)
        figure.tight_layout()
        judged = (f", judged at sizes of {scored_from:g} and more" if scored_from is not None
                  else "")
        lines = ("; ".join(drawn) + f" (the record's targets{judged})." if drawn
                 else "The record sets no target for these two measures.")
        return {"title": "Blind check: what the diagnosis gets right against effect size",
                "caption": "Single-effect cases at each size. " + lines[:1].upper() + lines[1:],
                "svg": _to_svg(figure)}


def conformance_figure(items: list, units, rule: str) -> dict:
    """The verdicts nearest their limits: each margin's Monte Carlo distribution against the
    limit (a zero margin) and the acceptance zone (margin ≥ the guard band w).

    ``items``: (verdict id, sorted margin draws [SI], acceptance limit w [SI], kind)."""
    with _style():
        figure, axes_row = plt.subplots(1, len(items), figsize=(_WIDTH, _HEIGHT * 0.8),
                                        squeeze=False)
        for axes, (verdict_id, draws, acceptance, kind) in zip(axes_row[0], items):
            unit = pretty(unit_of(kind, units) or "")
            scale = to_display(1.0, kind, units) if unit_of(kind, units) else 1.0
            shown = np.asarray(draws) * scale
            low = min(float(shown.min()), 0.0)
            high = max(float(shown.max()), acceptance * scale)
            pad = 0.05 * (high - low or 1.0)
            axes.axvspan(acceptance * scale, high + pad, color="#d9ead3", zorder=0)
            axes.hist(shown, bins=40, color="#4a6fa5", zorder=1)
            axes.axvline(0.0, color="black", linewidth=1.0)
            if acceptance:
                axes.axvline(acceptance * scale, color="black", linestyle="--", linewidth=0.8)
            axes.set_xlim(low - pad, high + pad)
            axes.set_yticks([])
            axes.set_xlabel(f"margin [{unit}]" if unit else "margin")
            criterion, _, scope = verdict_id.partition("/")
            axes.set_title(f"{criterion}\n{scope}" if scope else criterion, fontsize=6.5)
        figure.tight_layout()
        return {"title": "The verdicts nearest their limits: the distribution of each margin",
                "caption": (f"Monte Carlo draws of each margin (value against limit, positive "
                            f"when the criterion holds) for the verdicts with the smallest "
                            f"margin in units of U. Solid line: the limit (margin 0); shaded: "
                            f"the acceptance zone under {rule}"
                            + (", from the guard band (dashed)" if any(i[2] for i in items)
                               else "") + "."),
                "svg": _to_svg(figure)}
