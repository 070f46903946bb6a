"""Commands on archives: archive, verify and the catalog of bags (add, list, search)."""

from __future__ import annotations

import datetime as dt
import json
import sys
from pathlib import Path
from typing import Annotated

import typer
from rich.text import Text

from certkit.archive.bag import BagError
from certkit.archive.campaign_bag import archive_campaign, verify_archive
from certkit.archive.catalog import CatalogRefusal, add, shown_catalog
from certkit.archive.catalog import search as run_search
from certkit.cli.app import SpecArgument, bad_option, catalog_app, command, err, error, out


@command()
def archive(spec: SpecArgument,
            output: Annotated[Path, typer.Option(
                "-o", "--output", help="the bag to write: a new folder, or a file ending in .zip",
                metavar="BAG", show_default=False)],
            model: Annotated[bool, typer.Option(
                "--model/--no-model", help="include the drop-model sections (calibration, "
                                           "identification, gap) in the archived report")] = True,
            ) -> None:
    """Archive the campaign as a BagIt bag: spec, raw data, results, tables, report and the
    software environment, with SHA-256 manifests; the same inputs give the same bytes."""

    archived = archive_campaign(spec, output, model=model,
                                progress=lambda m: err.print(f"certkit archive: {m}"))
    out.print(f"archived {archived.files} file(s), {archived.octets} bytes, as {output}")
    out.print(f"bag hash (SHA-256 of tagmanifest-sha256.txt): {archived.bag_hash}")
    out.print(f"campaign outcome: {archived.outcome}")


@command(context="the recomputation failed: ")
def verify(bag: Annotated[Path, typer.Argument(help="a bag: its folder, or a .zip of one",
                                               metavar="BAG", show_default=False)],
           recompute: Annotated[bool, typer.Option(
               "--recompute", help="also re-run the assessment from the archived inputs and "
                                   "check the archived results.json reproduces")] = False,
           tolerance: Annotated[float, typer.Option(
               metavar="SHARE",
               help="with --recompute: the relative difference allowed between two numbers, "
                    "e.g. 1e-6")] = 1e-9,
           expect_hash: Annotated[str | None, typer.Option(
               "--expect-hash", metavar="SHA256",
               help="the bag hash recorded when it was archived (or in the catalog), 64 hex "
                    "digits: a bag re-hashed after tampering differs")] = None,
           ) -> None:
    """Check an archive against its manifests: every added, removed or modified file is
    named (exit 1); exit 0 when it is intact (and, with --recompute, reproduces)."""

    if not tolerance >= 0:
        bad_option("tolerance", "a share ≥ 0", tolerance)
    result = verify_archive(bag, recompute_results=recompute, tolerance=tolerance,
                            expected_hash=expect_hash)
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


DEFAULT_CATALOG = str(Path.home() / ".local" / "share" / "certkit" / "catalog.sqlite")
CatalogOption = Annotated[str, typer.Option(
    "--catalog", envvar="CERTKIT_CATALOG", metavar="CATALOG",
    show_default="~/.local/share/certkit/catalog.sqlite",
    help="the catalog: an SQLite file's path, or a PostgreSQL database's URL, "
         "postgresql://user@host[:port]/database (give the password in ~/.pgpass or "
         "PGPASSWORD, not in the URL); a lab shares one by setting CERTKIT_CATALOG")]


def _show_entries(entries, as_json: bool, catalog: str) -> None:
    catalog = shown_catalog(catalog)
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


@command(catalog_app, "add")
def catalog_add(bag: Annotated[list[Path], typer.Argument(help="bag folders or .zip files", metavar="BAG...",
                                                          show_default=False)],
                catalog: CatalogOption = DEFAULT_CATALOG) -> None:
    """Verify each bag and add it to the catalog (a bag already there is left as it is);
    exit 1 when a bag is not intact, 2 when one is not a certkit bag (neither is added)."""

    status = 0
    for item in bag:
        try:
            entry, added = add(catalog, item)
        except BagError as problem:   # not a bag: say so, go on with the others
            error(str(problem))
            status = 2
            continue
        except CatalogRefusal as refusal:
            error(str(refusal))
            for change in refusal.changes:
                err.print(f"  {change.kind}: {change.path} ({change.detail})")
            status = max(status, 1)
            continue
        what = "added" if added else "already catalogued"
        out.print(f"{what}: {entry.campaign_id} ({entry.aircraft}), bag {entry.bag_hash[:12]} "
                  f"at {entry.location}")
    raise typer.Exit(status)


@command(catalog_app, "list")
def catalog_list(catalog: CatalogOption = DEFAULT_CATALOG,
                 as_json: Annotated[bool, typer.Option("--json", help="print the entries as JSON")] = False,
                 ) -> None:
    """Every catalogued campaign, by aircraft."""

    _show_entries(run_search(catalog), as_json, catalog)


def _date_option(value: str | None, key: str) -> str | None:
    if value is None:
        return None
    try:
        return dt.date.fromisoformat(value).isoformat()
    except ValueError:
        bad_option(key, "a date as YYYY-MM-DD", repr(value))


@command(catalog_app, "search")
def catalog_search(text: Annotated[str | None, typer.Argument(
                       help="words in the campaign id, title, aircraft or report number",
                       metavar="TEXT",
                       show_default=False)] = None,
                   aircraft: Annotated[str | None, typer.Option(metavar="TEXT", help="the aircraft model contains TEXT")] = None,
                   campaign: Annotated[str | None, typer.Option(metavar="TEXT", help="the campaign id contains TEXT")] = None,
                   outcome: Annotated[str | None, typer.Option(
                       metavar="OUTCOME",
                       help="the campaign outcome: COMPLIANT, 'COMPLIANT SUBJECT TO CONFIRMATION', "
                            "'COMPLIANCE NOT SHOWN', 'NOT COMPLIANT' or 'PLANNING ONLY: NOT "
                            "COMPLIANCE EVIDENCE'")] = None,
                   since: Annotated[str | None, typer.Option(
                       "--from", metavar="DATE", help="tested on or after DATE, written YYYY-MM-DD")] = None,
                   until: Annotated[str | None, typer.Option(
                       "--to", metavar="DATE", help="tested on or before DATE, written YYYY-MM-DD")] = None,
                   verdict: Annotated[str | None, typer.Option(
                       metavar="VERDICT",
                       help="has a criterion with this verdict: PASS, FAIL or 'NOT SHOWN'")] = None,
                   clause: Annotated[str | None, typer.Option(
                       metavar="TEXT",
                       help="has a criterion whose clause or id contains TEXT")] = None,
                   catalog: CatalogOption = DEFAULT_CATALOG,
                   as_json: Annotated[bool, typer.Option("--json", help="print the entries as JSON")] = False,
                   ) -> None:
    """Catalogued campaigns matching every filter given."""

    if verdict is not None and verdict.upper() not in ("PASS", "FAIL", "NOT SHOWN"):
        bad_option("verdict", "PASS, FAIL or NOT SHOWN", repr(verdict))
    entries = run_search(catalog, text, aircraft=aircraft, campaign=campaign,
                         outcome=outcome, since=_date_option(since, "from"),
                         until=_date_option(until, "to"), verdict=verdict, clause=clause)
    _show_entries(entries, as_json, catalog)
