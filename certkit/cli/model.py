"""Commands on a campaign's drop model: simulate, calibrate, identify, gap.

Each command imports the model stage it needs (physics, ident, gap) inside its body, the one
place in certkit where imports are lazy on purpose: importing them at the top would load the
numba kernel and scipy's optimisers on every start-up, also for ``certkit validate`` and
``certkit report --no-model``.  Measured with ``python -X importtime -c "import certkit.cli"``:
0.56 s for certkit itself, 0.58 s more with the model stage imported eagerly.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table

from certkit.cli.app import SpecArgument, bad_option, command, fail, out, warning
from certkit.display import display
from certkit.display import parameter as parameter_text
from certkit.display import with_unit
from certkit.evidence.gap_view import largest_disagreement
from certkit.outputs import check_file_target, write_text_atomically, writing_failure
from certkit.spec.campaign import load_campaign
from certkit.spec.rundata import CHANNEL_LABELS


def _check_json_target(path: Path | None, campaign) -> None:
    """--json may not name a folder or one of the campaign's inputs (checked before the
    fit, which takes minutes)."""
    if path is not None:
        check_file_target(path, [item.path for item in campaign.inputs], "--json")


def _write_json(path: Path, document: dict) -> None:
    try:
        write_text_atomically(path, json.dumps(document, indent=2, ensure_ascii=False) + "\n")
    except OSError as problem:
        raise writing_failure(problem, path, "cannot write the JSON file", key="--json") \
            from None
    out.print(f"wrote {path}")


@command()
def simulate(spec: SpecArgument,
             output: Annotated[Path, typer.Option(
                 "-o", "--output", metavar="FOLDER",
                 help="the folder to write the new campaign and its data files into")],
             seed: Annotated[int, typer.Option(metavar="INTEGER",
                                              help="the seed of the sensor noise")] = 0,
             noise: Annotated[bool, typer.Option(
                 "--noise/--no-noise", help="add sensor noise, quantisation and offsets")] = True,
             ) -> None:
    """Simulate every run with the gear's drop model; write data files and a campaign file."""
    from certkit.physics.synthetic import NO_SENSOR_EFFECTS, SensorModel, simulate_campaign


    campaign = load_campaign(spec)
    written = simulate_campaign(campaign, output, seed=seed,
                                sensors=SensorModel() if noise else NO_SENSOR_EFFECTS)
    out.print(f"wrote {written} and {len(campaign.spec.runs)} data file(s) (synthetic)")


@command()
def calibrate(spec: SpecArgument,
              parameter: Annotated[list[str] | None, typer.Option(
                  "-p", "--parameter", metavar="NAME",
                  help="a parameter to fit, by its name in the spec's model.calibration "
                       "(repeat the option for several); default: the spec's "
                       "model.calibration, else C_d, pre-charge, n, tyre stiffness and "
                       "exponent, top-out compression, and the friction level and load-cell "
                       "gain where those effects are on")] = None,
              gear: Annotated[list[str] | None, typer.Option(
                  "-g", "--gear", metavar="GEAR",
                  help="the id of a gear unit to calibrate (repeat the option for several); "
                       "default: every recorded one")] = None,
              starts: Annotated[int | None, typer.Option(
                  "--starts", metavar="N",
                  help="further starts of the fit spread over the parameters' bounds, 0 to "
                       "20; the best is kept when its training cost is more than 0.1 % below "
                       "the fit from the spec's values; overrides the spec's "
                       "model.calibration.starts for this command (default: that, else 0)"
                  )] = None,
              json_file: Annotated[Path | None, typer.Option(
                  "--json", metavar="FILE",
                  help="also write the results, in SI, to FILE (JSON)")] = None,
              ) -> None:
    """Fit the drop model's parameters to the measured runs; all drop heights jointly."""
    from certkit.evidence.model_view import starts_words
    from certkit.physics.calibration import calibrate as run_calibration
    from certkit.physics.calibration import calibration_document
    from certkit.physics.starts import MOST_STARTS

    if starts is not None and not 0 <= starts <= MOST_STARTS:
        bad_option("starts", f"a whole number from 0 to {MOST_STARTS}", starts)
    campaign = load_campaign(spec)
    _check_json_target(json_file, campaign)
    result = run_calibration(campaign, knobs=parameter or None, gears=gear or None,
                             starts=starts)
    if not result.gears:
        fail(spec, "no run records a gear unit with time histories; nothing to fit")
    for item in result.gears:
        fit_ = item.fit
        table = Table(title=f"{item.gear_id}: runs {', '.join(item.runs)}; effects "
                            f"{', '.join(result.effects) or 'none'}")
        for column in ("parameter", "unit", "nominal", "estimate", "standard error"):
            table.add_column(column, justify="left" if column in ("parameter", "unit") else "right")
        units = campaign.spec.report.units
        for p, e, se in zip(fit_.parameters, fit_.estimate, fit_.standard_error):
            nominal, unit = parameter_text(p.nominal, p.unit, units)
            table.add_row(p.name, unit, nominal, parameter_text(float(e), p.unit, units)[0],
                          "not determined" if se != se
                          else parameter_text(float(se), p.unit, units)[0])
        out.print(table)
        names = [p.name for p in fit_.parameters]
        corr = Table(title="correlation of the estimates")
        corr.add_column("")
        for number in range(1, len(names) + 1):
            corr.add_column(f"({number})", justify="right")
        for number, (name, row) in enumerate(zip(names, fit_.correlation), start=1):
            corr.add_row(f"({number}) {name}", *("—" if c != c else f"{c:+.2f}" for c in row))
        out.print(corr)
        rmse = Table(title="RMSE, nominal → calibrated")
        for column in ("run", "channel", "nominal", "calibrated"):
            rmse.add_column(column, justify="left" if column in ("run", "channel") else "right")
        for e in item.errors:
            kind = "force" if e.unit == "N" else "length"
            rmse.add_row(e.run, CHANNEL_LABELS[e.channel], with_unit(e.nominal, kind, units),
                         with_unit(e.calibrated, kind, units))
        out.print(rmse)
        if item.search is not None:
            out.print(starts_words(item.search))
        for text in fit_.warnings:
            warning(text)
        if not fit_.success:
            warning(f"the fit did not converge: {fit_.message}")
    if json_file is not None:
        _write_json(json_file, calibration_document(result))


@command()
def identify(spec: SpecArgument,
             json_file: Annotated[Path | None, typer.Option(
                 "--json", metavar="FILE",
                 help="also write the results, in SI, to FILE (JSON)")] = None) -> None:
    """Identify Hammerstein, Wiener and NARX models of each gear; validate them on held-out
    drops."""
    from certkit.gear_identification import (OUTPUT_LABELS, PROTOCOL_NAMES,
                                             identification_document)
    from certkit.gear_identification import identify as run_identification



    campaign = load_campaign(spec)
    _check_json_target(json_file, campaign)
    result = run_identification(campaign)
    if not result.gears:
        fail(spec, "no gear unit has two usable drops with time histories; nothing to "
                    "identify" + (": " + "; ".join(result.skipped) if result.skipped else ""))
    out.print(result.plant_note)
    for gear in result.gears:
        units = campaign.spec.report.units
        table = Table(title=f"{gear.gear_id}: free-run RMSE [{units.length}]; trained on "
                            f"{', '.join(gear.training)}, held out {', '.join(gear.held_out)}")
        table.add_column("model")
        columns = [(o, p) for o in ("stroke", "tyre") for p in ("paper", "held-out")]
        for output, protocol in columns:
            table.add_column(f"{OUTPUT_LABELS[output]}, {PROTOCOL_NAMES[protocol]}",
                             justify="right")
        models = list(dict.fromkeys(x.model for x in gear.scores))
        for model in models:
            cells = []
            for output, protocol in columns:
                score = next((x for x in gear.scores if (x.model, x.output, x.protocol, x.run)
                              == (model, output, protocol, gear.held_out[0])), None)
                cells.append("—" if score is None
                             else display(score.rmse * 1e-3, "length", units)[0])
            table.add_row(model, *cells)
        out.print(table)
        for note in gear.notes:
            warning(note, "note")
    if json_file is not None:
        _write_json(json_file, identification_document(result))


@command()
def gap(spec: SpecArgument,
        gear: Annotated[list[str] | None, typer.Option(
            "-g", "--gear", metavar="GEAR",
            help="the id of a gear unit (repeat the option for several); default: every "
                 "recorded one")] = None,
        ) -> None:
    """Where the nominal model disagrees with the runs; which effect explains it, and how
    far the held-out error shrinks with it."""
    from certkit.gap.diagnosis import gap_diagnosis

    campaign = load_campaign(spec)
    recorded = [g.id for g in campaign.spec.gear_units
                if any(s is not None and g.id in s.gears for s in campaign.series.values())]
    unknown = [g for g in gear or [] if g not in recorded]
    if unknown:
        fail(spec, f"--gear {', '.join(unknown)}: no drop records it; recorded: "
                    f"{', '.join(recorded) or 'none'}")
    if not recorded:
        fail(spec, "no run has time histories; the gap diagnosis compares the model "
                    "with recorded drops")
    for gear_id in [g for g in recorded if not gear or g in gear]:
        result = gap_diagnosis(campaign, gear_id)
        which = result.diagnosis
        out.print(f"{gear_id}: trained on {', '.join(result.training)}, held out "
                  f"{', '.join(result.held_out)}"
                  f" ({'declared in model.gap.held_out' if result.declared else 'default'})")
        units = campaign.spec.report.units
        out.print(largest_disagreement(result.before.largest, units, "on the training runs"))
        table = Table(title="candidate effects, first step (score test on the training runs)")
        for column in ("effect", "LM statistic", "explained RMS [noise]"):
            table.add_column(column, justify="left" if column == "effect" else "right")
        for score in which.steps[0][0].scores:
            table.add_row(score.name, f"{score.statistic:.4g}", f"{score.explained:.3g}")
        out.print(table)
        out.print(which.statement)
        table = Table(title="held-out RMSE, nominal model → with the named effects")
        for column in ("run", "channel", "phase", "before", "after", "shrink"):
            table.add_column(column, justify="left" if column in ("run", "channel", "phase")
                             else "right")
        for row in result.held_out_errors:
            kind = "force" if row.channel == "load" else "length"
            after = "" if row.after is None else with_unit(row.after, kind, units)
            shrink = "" if row.shrink is None else f"{100 * row.shrink:.0f} %"
            table.add_row(row.run, row.channel, row.phase,
                          with_unit(row.before, kind, units), after, shrink)
        out.print(table)


