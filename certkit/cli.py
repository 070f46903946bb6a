"""The certkit command line: a thin shell over the library.

Exit codes: 0 success; 1 campaign not compliant (only with ``--strict``); 2 bad input;
3 internal error (a certkit bug; no traceback unless CERTKIT_DEBUG is set).
"""

from __future__ import annotations

import json
import os
import signal
import sys
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.text import Text

from certkit import __version__
from certkit.spec import requirement_sets
from certkit.display import display, with_unit
from certkit.display import parameter as parameter_text
from certkit.errors import CertkitInputError

app = typer.Typer(add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False,
                  help="Turn a landing-gear drop-test campaign into airworthiness evidence.")
err = Console(stderr=True, highlight=False, soft_wrap=True, markup=False)
out = Console(highlight=False, soft_wrap=True, markup=False)

SpecArgument = Annotated[Path, typer.Argument(help="campaign spec (YAML)", show_default=False)]


def _print_problems(error: CertkitInputError) -> None:
    for problem in error.problems:
        err.print(Text.assemble(("error: ", "bold red"), str(problem)))


def _fail_input(error: CertkitInputError) -> None:
    _print_problems(error)
    raise typer.Exit(2)


def _fail(spec: Path, message: str) -> None:
    """A bad-input outcome that is not a spec problem (a failed simulation, no data)."""
    err.print(Text.assemble(("error: ", "bold red"), f"{spec}: {message}"))
    raise typer.Exit(2)


def _bad_option(option: str, expected: str, found) -> None:
    """A command-line option with a value it cannot take: say which, and exit 2."""
    err.print(Text.assemble(("error: ", "bold red"),
                            f"--{option}: expected {expected}, found {found}"))
    raise typer.Exit(2)


def _version(value: bool) -> None:
    if value:
        out.print(f"certkit {__version__}")
        raise typer.Exit()


_STOP_SIGNALS = (signal.SIGTERM, signal.SIGHUP, signal.SIGINT)


def _exit_on_signal(number, _frame):
    # The first stop signal becomes an exception, so staged outputs are removed; further
    # signals are ignored so they cannot interrupt that clean-up.
    for other in _STOP_SIGNALS:
        signal.signal(other, signal.SIG_IGN)
    raise SystemExit(128 + number)


@app.callback()
def main(version: Annotated[bool, typer.Option("--version", callback=_version, is_eager=True,
                                               help="print the version and exit")] = False):
    """certkit: drop-test campaign -> compliance report, audit tables and evidence."""
    for number in _STOP_SIGNALS:
        signal.signal(number, _exit_on_signal)


def run() -> None:
    """Console entry point: input errors exit 2; an unexpected error is reported as a bug (3)."""
    try:
        app()
    except CertkitInputError as error:  # raised outside a command's own handling
        _print_problems(error)
        sys.exit(2)
    except Exception as error:  # noqa: BLE001 - last resort: no traceback for users
        if os.environ.get("CERTKIT_DEBUG"):
            raise
        err.print(Text.assemble(("internal error: ", "bold red"),
                                f"{type(error).__name__}: {error}. This is a certkit bug; "
                                f"please report it with the campaign (set CERTKIT_DEBUG=1 to "
                                f"see the traceback)."))
        sys.exit(3)


@app.command()
def validate(spec: SpecArgument) -> None:
    """Check a campaign spec and its data files; print what was found wrong."""
    from certkit.spec.campaign import load_campaign
    try:
        campaign = load_campaign(spec)
    except CertkitInputError as error:
        _fail_input(error)
    runs = len(campaign.spec.runs)
    with_data = sum(series is not None for series in campaign.series.values())
    out.print(f"{spec}: valid — {runs} run(s), {with_data} with time series, "
              f"{len(campaign.inputs)} input file(s)")


@app.command()
def report(spec: SpecArgument,
           output: Annotated[Path, typer.Option("-o", "--output", help="output folder")] = Path("out"),
           strict: Annotated[bool, typer.Option(
               "--strict", help="exit 1 when a criterion fails or the data-quality audit "
                                "finds an error")] = False,
           model: Annotated[bool, typer.Option(
               "--model/--no-model", help="calibrate the drop model against the runs and add "
                                          "the governing-equation section")] = True) -> None:
    """Write report.html, report.pdf (PDF/A-3b), results.json and tables/*.csv."""
    from rich.status import Status

    from certkit.spec.campaign import load_campaign
    from certkit.compliance.engine import assess
    from certkit.evidence.report import render_report

    status = Status("loading campaign", console=err) if err.is_terminal else None
    if status:
        status.start()
    try:
        def progress(message: str) -> None:
            if status:
                status.update(message)

        try:
            campaign = load_campaign(spec)
        except CertkitInputError as error:
            if status:
                status.stop()
            _fail_input(error)
        progress("assessing")
        assessment = assess(campaign)
        evidence = None
        if model:  # the model's compiled kernel loads only when it is asked for
            from certkit.evidence.model_evidence import model_evidence
            from certkit.physics.fitting import FitError
            from certkit.physics.simulation import SimulationError

            progress("calibrating the drop model")
            try:
                evidence = model_evidence(campaign)
            except (CertkitInputError, SimulationError, FitError) as error:
                if status:
                    status.stop()
                if isinstance(error, CertkitInputError):
                    _fail_input(error)
                _fail(spec, str(error))
        try:
            render_report(assessment, output, progress, evidence)
        except CertkitInputError as error:
            if status:
                status.stop()
            _fail_input(error)
    finally:
        if status:
            status.stop()
    counts, findings = assessment.counts(), assessment.finding_counts()
    out.print(f"{assessment.outcome}: {counts['PASS']} pass, {counts['FAIL']} fail, "
              f"{counts['NOT SHOWN']} not shown; data-quality findings: {findings['error']} "
              f"error, {findings['warning']} warning")
    out.print(f"wrote {output}/report.pdf, report.html, results.json, tables/")
    if strict and (counts["FAIL"] or findings["error"] or assessment.planning):
        raise typer.Exit(1)


def _numbers(text: str, key: str, kind=float) -> tuple:
    try:
        values = tuple(kind(v) for v in text.split(",") if v.strip())
    except ValueError:
        values = ()
    if not values:
        _bad_option(key, "comma-separated numbers", repr(text))
    return values


def _blind_check(spec: Path, gear: str | None, output: Path, workers, scheduler, seeds: str,
                 ratios: str) -> None:
    from rich.table import Table

    from certkit.gap.blind_check import BlindCheckError, Settings, blind_check, write_blind_check
    from certkit.physics.fitting import FitError
    from certkit.outputs import check_target, staged_folder
    from certkit.physics.simulation import SimulationError

    settings = Settings(ratios=_numbers(ratios, "ratios"), seeds=_numbers(seeds, "seeds", int))
    if workers is not None and workers < 1:
        _bad_option("workers", "a whole number ≥ 1", workers)
    own = {"blind-check.json", "blind-check-cases.csv"}
    try:   # the output folder is checked before the battery, not after it
        check_target(output, [spec], own)
    except CertkitInputError as error:
        _fail_input(error)
    try:
        def progress(outcome):
            named = ", ".join(outcome["named"]) or "(none)"
            err.print(f"{outcome['id']}: named {named}")

        document = blind_check(spec, gear, settings, workers=workers, scheduler=scheduler,
                               progress=progress)
    except CertkitInputError as error:
        _fail_input(error)
    except (SimulationError, FitError, BlindCheckError) as error:
        _fail(spec, str(error))
    try:
        with staged_folder(output, [spec], own) as folder:
            write_blind_check(document, folder)
    except CertkitInputError as error:
        _fail_input(error)
    table = Table(title=f"blind check of the gap diagnosis ({len(document['cases'])} cases)")
    for column in ("metric", "measured", "cases", "target", "met"):
        table.add_column(column, justify="left" if column == "metric" else "right")
    for name, metric in document["metrics"].items():
        value = "n/a" if metric["value"] is None else f"{100 * metric['value']:.0f} %"
        target = "" if metric["target"] is None else \
            f"{metric['direction']} {100 * metric['target']:.0f} %"
        met = {True: "yes", False: "NO", None: ""}[metric["met"]]
        table.add_row(name.replace("_", " "), value, str(metric["cases"]), target, met)
    out.print(table)
    out.print(f"written: {output}")


@app.command()
def simulate(spec: SpecArgument,
             output: Annotated[Path, typer.Option("-o", "--output", help="output folder")],
             seed: Annotated[int, typer.Option(help="seed of the sensor noise")] = 0,
             noise: Annotated[bool, typer.Option(
                 "--noise/--no-noise", help="add sensor noise, quantisation and offsets")] = True,
             ) -> None:
    """Simulate every run with the gear's drop model; write data files and a campaign file."""
    from certkit.spec.campaign import load_campaign
    from certkit.physics.simulation import SimulationError
    from certkit.physics.synthetic import NO_SENSOR_EFFECTS, SensorModel, simulate_campaign

    try:
        campaign = load_campaign(spec)
        written = simulate_campaign(campaign, output, seed=seed,
                                    sensors=SensorModel() if noise else NO_SENSOR_EFFECTS)
    except CertkitInputError as error:
        _fail_input(error)
    except SimulationError as error:
        _fail(spec, f"{error} (check the gear parameters; nothing was written)")
    out.print(f"wrote {written} and {len(campaign.spec.runs)} data file(s) (synthetic)")


@app.command()
def calibrate(spec: SpecArgument,
              parameter: Annotated[list[str] | None, typer.Option(
                  "-p", "--parameter", help="parameter to fit (repeat); default: the spec's "
                                            "model.calibration, else C_d, pre-charge, n, tyre "
                                            "stiffness and friction")] = None,
              gear: Annotated[list[str] | None, typer.Option(
                  "-g", "--gear", help="gear unit to calibrate (repeat); default: all "
                                       "recorded")] = None,
              json_file: Annotated[Path | None, typer.Option(
                  "--json", help="also write the results (SI) to this JSON file")] = None,
              ) -> None:
    """Fit the drop model's parameters to the measured runs, all drop heights jointly."""
    from rich.table import Table

    from certkit.physics.calibration import calibrate as run_calibration
    from certkit.physics.calibration import calibration_document
    from certkit.spec.rundata import CHANNEL_LABELS
    from certkit.spec.campaign import load_campaign
    from certkit.physics.fitting import FitError
    from certkit.physics.simulation import SimulationError

    try:
        campaign = load_campaign(spec)
        result = run_calibration(campaign, knobs=parameter or None, gears=gear or None)
    except CertkitInputError as error:
        _fail_input(error)
    except (SimulationError, FitError) as error:
        _fail(spec, str(error))
    if not result.gears:
        _fail(spec, "no run records a gear unit with time histories; nothing to fit")
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
        for warning in fit_.warnings:
            err.print(Text.assemble(("warning: ", "bold yellow"), warning))
        if not fit_.success:
            err.print(Text.assemble(("warning: ", "bold yellow"),
                                    f"the fit did not converge: {fit_.message}"))
    if json_file is not None:
        text = json.dumps(calibration_document(result), indent=2, ensure_ascii=False)
        json_file.write_text(text + "\n", encoding="utf-8")
        out.print(f"wrote {json_file}")


@app.command()
def identify(spec: SpecArgument,
             json_file: Annotated[Path | None, typer.Option(
                 "--json", help="also write the results to this JSON file")] = None) -> None:
    """Identify Hammerstein, Wiener and NARX models of each gear and validate them."""
    from rich.table import Table

    from certkit.spec.campaign import load_campaign
    from certkit.ident.protocol import OUTPUT_LABELS, PROTOCOL_NAMES, identification_document
    from certkit.ident.protocol import identify as run_identification
    from certkit.physics.fitting import FitError
    from certkit.physics.simulation import SimulationError

    try:
        campaign = load_campaign(spec)
        result = run_identification(campaign)
    except CertkitInputError as error:
        _fail_input(error)
    except (SimulationError, FitError) as error:
        _fail(spec, str(error))
    if not result.gears:
        _fail(spec, "no gear unit has two usable drops with time histories; nothing to "
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
            err.print(Text.assemble(("note: ", "bold"), note))
    if json_file is not None:
        text = json.dumps(identification_document(result), indent=2, ensure_ascii=False)
        json_file.write_text(text + "\n", encoding="utf-8")
        out.print(f"wrote {json_file}")


@app.command()
def gap(spec: SpecArgument,
        gear: Annotated[list[str] | None, typer.Option(
            "-g", "--gear", help="gear unit (repeat); default: every recorded one")] = None,
        blind: Annotated[bool, typer.Option(
            "--blind-check", help="check the diagnosis blind on synthetic campaigns simulated "
                                  "from SPEC with withheld effects, and score it")] = False,
        output: Annotated[Path, typer.Option(
            "-o", "--output", help="blind check: the folder for blind-check.json and "
                                   "blind-check-cases.csv")] = Path("blind-check"),
        workers: Annotated[int | None, typer.Option(
            help="blind check: local worker processes (default: one per core)")] = None,
        scheduler: Annotated[str | None, typer.Option(
            help="blind check: a dask.distributed scheduler address to run the cases on "
                 "(needs certkit\\[cluster])")] = None,
        seeds: Annotated[str, typer.Option(
            help="blind check: seeds of the single-effect cases, comma-separated")] = "21,22,23",
        ratios: Annotated[str, typer.Option(
            help="blind check: effect sizes, multiples of the load noise RMS")] = "1,2,5",
        ) -> None:
    """Where the nominal model disagrees with the runs, and which effect explains it."""
    from rich.table import Table

    if blind:
        _blind_check(spec, gear[0] if gear else None, output, workers, scheduler, seeds, ratios)
        return

    from certkit.spec.campaign import load_campaign
    from certkit.physics.fitting import FitError
    from certkit.gap.diagnosis import gap_diagnosis
    from certkit.evidence.report import largest_disagreement
    from certkit.physics.simulation import SimulationError

    try:
        campaign = load_campaign(spec)
        recorded = [g.id for g in campaign.spec.gear_units
                    if any(s is not None and g.id in s.gears for s in campaign.series.values())]
        unknown = [g for g in gear or [] if g not in recorded]
        if unknown:
            _fail(spec, f"--gear {', '.join(unknown)}: no drop records it; recorded: "
                        f"{', '.join(recorded) or 'none'}")
        if not recorded:
            _fail(spec, "no run has time histories; the gap diagnosis compares the model "
                        "with recorded drops")
        for gear_id in [g for g in recorded if not gear or g in gear]:
            result = gap_diagnosis(campaign, gear_id)
            which = result.diagnosis
            out.print(f"{gear_id}: trained on {', '.join(result.training)}, held out "
                      f"{', '.join(result.held_out)}"
                      f" ({'declared in model.gap.held_out' if result.declared else 'default'})")
            units = campaign.spec.report.units
            out.print(largest_disagreement(result.before.largest, units))
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
    except CertkitInputError as error:
        _fail_input(error)
    except (SimulationError, FitError) as error:
        _fail(spec, str(error))


@app.command()
def audit(spec: SpecArgument,
          format: Annotated[str, typer.Option(
              "--format", help="the table on standard output (or -o): md, csv or json")] = "md",
          output: Annotated[Path | None, typer.Option(
              "-o", "--output", help="write the table to this file instead")] = None,
          junit: Annotated[Path | None, typer.Option(
              "--junit", help="also write JUnit XML here (a test case per row)")] = None,
          baseline: Annotated[Path | None, typer.Option(
              "--baseline", help="an earlier results.json: report every number that "
                                 "drifted, criterion added or removed, verdict changed")] = None,
          tolerance: Annotated[float, typer.Option(
              help="with --baseline: relative drift allowed before a number counts as "
                   "changed")] = 1e-9,
          ) -> None:
    """One row per criterion per run and per data-quality finding (and per change since a
    baseline); exit 0 when every criterion passes, no finding is an error and nothing
    changed, 1 otherwise, 2 on bad input."""
    from certkit.evidence.audit import (audit_rows, baseline_rows, passed, to_csv, to_json, to_junit,
                        to_markdown)
    from certkit.spec.campaign import load_campaign
    from certkit.compliance.engine import assess
    from certkit.outputs import write_text_atomically

    writers = {"md": None, "csv": to_csv, "json": to_json}
    if format not in writers:
        _bad_option("format", "md, csv or json", repr(format))
    try:
        campaign = load_campaign(spec)
    except CertkitInputError as error:
        _fail_input(error)
    assessment = assess(campaign)
    rows = audit_rows(assessment)
    if baseline is not None:
        from certkit.evidence.baseline import compare, read_baseline
        from certkit.evidence.report import results_document

        if not tolerance >= 0:
            _bad_option("tolerance", "a share ≥ 0", tolerance)
        try:
            earlier = read_baseline(baseline)
        except CertkitInputError as error:
            _fail_input(error)
        rows += baseline_rows(compare(results_document(assessment, {}), earlier, tolerance))
    title = f"{campaign.spec.campaign.id} ({spec.name})"
    units = campaign.spec.report.units
    text = to_markdown(rows, title, units) if format == "md" else writers[format](rows)
    # both files or neither: the table first, then the JUnit; a failed second write puts
    # back what the first replaced (or removes it, if there was nothing)
    written: list[tuple[Path, bytes | None]] = []
    try:
        for path, content in ((output, text), (junit, None)):
            if path is None:
                continue
            before = path.read_bytes() if path.is_file() else None
            write_text_atomically(path, content if content is not None
                                  else to_junit(rows, title, units))
            written.append((path, before))
    except OSError as error:
        for path, before in written:
            if before is None:
                path.unlink(missing_ok=True)
            else:
                path.write_bytes(before)
        _fail(spec, f"cannot write the audit: {error}")
    if output is None:
        sys.stdout.write(text)
    raise typer.Exit(0 if passed(rows) else 1)


@app.command()
def archive(spec: SpecArgument,
            output: Annotated[Path, typer.Option(
                "-o", "--output", help="the bag to write: a new folder, or a .zip",
                show_default=False)],
            model: Annotated[bool, typer.Option(
                "--model/--no-model", help="include the drop-model sections (calibration, "
                                           "identification, gap) in the archived report")] = True,
            ) -> None:
    """Archive the campaign as a BagIt bag: spec, raw data, results, tables, report and the
    software environment, with SHA-256 manifests; the same inputs give the same bytes."""
    from certkit.archive.campaign_bag import archive_campaign
    from certkit.physics.fitting import FitError
    from certkit.physics.simulation import SimulationError

    try:
        archived = archive_campaign(spec, output, model=model,
                                    progress=lambda m: err.print(m) if err.is_terminal else None)
    except CertkitInputError as error:
        _fail_input(error)
    except (SimulationError, FitError) as error:
        _fail(spec, str(error))
    out.print(f"archived {archived.files} file(s), {archived.octets} bytes, as {output}")
    out.print(f"bag hash (SHA-256 of tagmanifest-sha256.txt): {archived.bag_hash}")
    out.print(f"campaign outcome: {archived.outcome}")


@app.command()
def verify(bag: Annotated[Path, typer.Argument(help="a bag folder or a .zip of one",
                                               show_default=False)],
           recompute: Annotated[bool, typer.Option(
               "--recompute", help="also re-run the assessment from the archived inputs and "
                                   "check the archived results.json reproduces")] = False,
           tolerance: Annotated[float, typer.Option(
               help="with --recompute: relative difference allowed between numbers")] = 1e-9,
           expect_hash: Annotated[str | None, typer.Option(
               "--expect-hash", help="the bag hash recorded when it was archived (or in the "
                                     "catalog): a bag re-hashed after tampering differs")] = None,
           ) -> None:
    """Check an archive against its manifests: every added, removed or modified file is
    named (exit 1); exit 0 when it is intact (and, with --recompute, reproduces)."""
    from certkit.archive.campaign_bag import verify_archive
    from certkit.archive.bag import BagError
    from certkit.physics.fitting import FitError
    from certkit.physics.simulation import SimulationError

    if not tolerance >= 0:
        _bad_option("tolerance", "a share ≥ 0", tolerance)
    try:
        result = verify_archive(bag, recompute_results=recompute, tolerance=tolerance,
                                expected_hash=expect_hash)
    except BagError as error:
        err.print(Text.assemble(("error: ", "bold red"), str(error)))
        raise typer.Exit(2)
    except CertkitInputError as error:
        _fail_input(error)
    except (SimulationError, FitError) as error:
        _fail(bag, f"the recomputation failed: {error}")
    for change in result.changes:
        out.print(f"{change.kind}: {change.path} ({change.detail})")
    files = (result.info.get("Payload-Oxum") or ["?.?"])[0].split(".")[-1]
    if result.intact:
        out.print(f"{bag}: intact — {files} payload file(s) match manifest-sha256.txt")
    else:
        out.print(f"{bag}: NOT INTACT — {len(result.changes)} change(s) since it was archived")
    out.print(f"bag hash (SHA-256 of tagmanifest-sha256.txt): {result.bag_hash}")
    if not result.hash_as_expected:
        out.print(f"NOT THE BAG EXPECTED: its hash is not {result.expected_hash}; it was "
                  f"changed and re-hashed, or it is another bag")
    for note in result.notes:
        out.print(note)
    recomputed = result.recomputed
    if recomputed is not None:
        for line in recomputed.differences:
            out.print(f"not reproduced: {line}")
        for line in recomputed.software:
            out.print(f"software differs: {line}")
        if recomputed.identical:
            out.print("recomputed: results.json reproduced byte for byte")
        elif recomputed.reproduced:
            out.print(f"recomputed: every number of results.json reproduced within "
                      f"{tolerance:g} (relative); the bytes differ")
        else:
            out.print(f"recomputed: {len(recomputed.differences)} value(s) of results.json "
                      f"did not reproduce")
    raise typer.Exit(0 if result.passed else 1)


catalog_app = typer.Typer(no_args_is_help=True, help="An SQLite index of archived campaigns: "
                                                     "add bags, list and search them.")
app.add_typer(catalog_app, name="catalog")
DEFAULT_CATALOG = Path.home() / ".local" / "share" / "certkit" / "catalog.sqlite"
CatalogOption = Annotated[Path, typer.Option(
    "--catalog", envvar="CERTKIT_CATALOG",
    help="the catalog file (a lab shares one by setting CERTKIT_CATALOG)")]


def _show_entries(entries, as_json: bool, catalog: Path) -> None:
    if as_json:
        sys.stdout.write(json.dumps([e.as_dict() for e in entries], indent=2,
                                    ensure_ascii=False) + "\n")
        return
    if not entries:
        out.print(f"no catalogued campaign matches (catalog {catalog})")
        return
    out.print(f"{len(entries)} archived campaign(s) in {catalog}:")
    for e in entries:
        tested = e.first_test_date if e.first_test_date == e.last_test_date else \
            f"{e.first_test_date} to {e.last_test_date}"
        out.print(Text.assemble("\n", (e.campaign_id, "bold"), f" — {e.aircraft}"))
        out.print(f"  {e.title}")
        out.print(f"  report {e.report_number} rev. {e.revision}, issued {e.issue_date}, "
                  f"tested {tested}")
        out.print(f"  {e.outcome}: {e.passed} pass, {e.failed} fail, {e.not_shown} not shown; "
                  f"{e.dq_errors} data-quality error(s), {e.dq_warnings} warning(s)")
        out.print(f"  bag {e.bag_hash} at {e.location} ({e.software})")


@catalog_app.command("add")
def catalog_add(bag: Annotated[list[Path], typer.Argument(help="bag folder(s) or .zip file(s)",
                                                          show_default=False)],
                catalog: CatalogOption = DEFAULT_CATALOG) -> None:
    """Verify each bag and add it to the catalog (a bag already there is left as it is);
    exit 1 when a bag is not intact, 2 when one is not a certkit bag (neither is added)."""
    from certkit.archive.bag import BagError
    from certkit.archive.catalog import CatalogRefusal, add

    status = 0
    for item in bag:
        try:
            entry, added = add(catalog, item)
        except BagError as error:   # not a bag: say so, go on with the others
            err.print(Text.assemble(("error: ", "bold red"), str(error)))
            status = 2
            continue
        except CertkitInputError as error:
            _fail_input(error)
        except CatalogRefusal as refusal:
            err.print(Text.assemble(("error: ", "bold red"), str(refusal)))
            for change in refusal.changes:
                err.print(f"  {change.kind}: {change.path} ({change.detail})")
            status = max(status, 1)
            continue
        what = "added" if added else "already catalogued"
        out.print(f"{what}: {entry.campaign_id} ({entry.aircraft}), bag {entry.bag_hash[:12]} "
                  f"at {entry.location}")
    raise typer.Exit(status)


@catalog_app.command("list")
def catalog_list(catalog: CatalogOption = DEFAULT_CATALOG,
                 as_json: Annotated[bool, typer.Option("--json", help="print JSON")] = False,
                 ) -> None:
    """Every catalogued campaign, by aircraft."""
    from certkit.archive.catalog import search as run_search

    try:
        _show_entries(run_search(catalog), as_json, catalog)
    except CertkitInputError as error:
        _fail_input(error)


def _date_option(value: str | None, key: str) -> str | None:
    import datetime as dt

    if value is None:
        return None
    try:
        return dt.date.fromisoformat(value).isoformat()
    except ValueError:
        _bad_option(key, "a date as YYYY-MM-DD", repr(value))


@catalog_app.command("search")
def catalog_search(text: Annotated[str | None, typer.Argument(
                       help="words in the campaign id, title, aircraft or report number",
                       show_default=False)] = None,
                   aircraft: Annotated[str | None, typer.Option(help="aircraft model contains")] = None,
                   campaign: Annotated[str | None, typer.Option(help="campaign id contains")] = None,
                   outcome: Annotated[str | None, typer.Option(
                       help="campaign outcome, e.g. 'COMPLIANCE SHOWN'")] = None,
                   since: Annotated[str | None, typer.Option(
                       "--from", help="tested on or after (YYYY-MM-DD)")] = None,
                   until: Annotated[str | None, typer.Option(
                       "--to", help="tested on or before (YYYY-MM-DD)")] = None,
                   verdict: Annotated[str | None, typer.Option(
                       help="has a criterion with this verdict: PASS, FAIL or 'NOT SHOWN'")] = None,
                   clause: Annotated[str | None, typer.Option(
                       help="has a criterion whose clause or id contains this")] = None,
                   catalog: CatalogOption = DEFAULT_CATALOG,
                   as_json: Annotated[bool, typer.Option("--json", help="print JSON")] = False,
                   ) -> None:
    """Catalogued campaigns matching every filter given."""
    from certkit.archive.catalog import search as run_search

    if verdict is not None and verdict.upper() not in ("PASS", "FAIL", "NOT SHOWN"):
        _bad_option("verdict", "PASS, FAIL or NOT SHOWN", repr(verdict))
    try:
        entries = run_search(catalog, text, aircraft=aircraft, campaign=campaign,
                             outcome=outcome, since=_date_option(since, "from"),
                             until=_date_option(until, "to"), verdict=verdict, clause=clause)
    except CertkitInputError as error:
        _fail_input(error)
    _show_entries(entries, as_json, catalog)


@app.command()
def schema() -> None:
    """Print the JSON Schema of the campaign spec (for editors and CI)."""
    from certkit.spec.schema import json_schema
    sys.stdout.write(json.dumps(json_schema(), indent=2, ensure_ascii=False) + "\n")


@app.command()
def sets() -> None:
    """List the shipped requirement sets."""
    for set_id in requirement_sets.available():
        rules = requirement_sets.load(set_id)
        marker = " (values to be confirmed against the licensed standard)" if rules.to_confirm else ""
        out.print(f"{set_id}: {rules.title}{marker}")


if __name__ == "__main__":  # pragma: no cover
    run()
