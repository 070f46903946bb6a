"""What the archive catalog holds, whichever database keeps it: a bag's entry and its
verdict rows, read from the bag once it verifies; the schema, as the steps that make and
migrate it; the search, as SQL both SQLite and PostgreSQL run; and the catalog's location
as it may be shown (a URL without its password).

:mod:`certkit.archive.catalog` keeps a catalog in an SQLite file (the embedded default),
:mod:`certkit.archive.catalog_postgresql` on a PostgreSQL server.
"""

from __future__ import annotations

import re
import urllib.parse
from dataclasses import asdict, dataclass
from pathlib import Path

from certkit.archive.bag import BagError, bag_hash, check_bag, read_info
from certkit.archive.campaign_bag import archived_results, opened_bag
from certkit.errors import CertkitInputError, shown

#: The steps that make the schema: step i brings a catalog of version i to version i + 1
#: (version 0: no catalog yet).  Each step is a list of statements, run in the transaction
#: of the addition that finds the catalog older, so a failed addition leaves the catalog
#: as it was.  ``{integer}`` is the type of the counts: INTEGER in SQLite (64-bit), BIGINT
#: in PostgreSQL (its INTEGER has 32 bits).  A step that changes the columns must also
#: change :func:`search_query`, which reads catalogs of every version up to the current one.
MIGRATIONS: list[list[str]] = [
    [   # version 1: the campaigns and their verdicts
        """CREATE TABLE IF NOT EXISTS campaigns (
    bag_hash        TEXT NOT NULL,
    location        TEXT NOT NULL,
    campaign_id     TEXT NOT NULL,
    title           TEXT NOT NULL,
    aircraft        TEXT NOT NULL,
    report_number   TEXT NOT NULL,
    revision        TEXT NOT NULL,
    issue_date      TEXT NOT NULL,
    first_test_date TEXT NOT NULL,
    last_test_date  TEXT NOT NULL,
    outcome         TEXT NOT NULL,
    passed          {integer} NOT NULL,
    failed          {integer} NOT NULL,
    not_shown       {integer} NOT NULL,
    dq_errors       {integer} NOT NULL,
    dq_warnings     {integer} NOT NULL,
    software        TEXT NOT NULL,
    PRIMARY KEY (bag_hash, location)
)""",
        """CREATE TABLE IF NOT EXISTS verdicts (
    bag_hash  TEXT NOT NULL,
    id        TEXT NOT NULL,
    clause    TEXT NOT NULL,
    run       TEXT,
    gear      TEXT,
    verdict   TEXT NOT NULL,
    PRIMARY KEY (bag_hash, id)
)""",
        "CREATE INDEX IF NOT EXISTS campaigns_aircraft ON campaigns (aircraft)",
    ],
]
TABLES = ("campaigns", "verdicts")


def schema_version() -> int:
    """The version of the schema this certkit makes: the number of migration steps."""
    return len(MIGRATIONS)


def migration(found: int, integer: str) -> list[str]:
    """The statements that bring a catalog of version ``found`` to :func:`schema_version`."""
    return [statement.format(integer=integer) for step in MIGRATIONS[found:]
            for statement in step]


def newer_catalog(version: int) -> str:
    return (f"made by a newer certkit (schema version {version}; this certkit knows "
            f"versions up to {schema_version()}): upgrade certkit to use it")


class CatalogRefusal(Exception):
    """The bag was not added: it is not intact (the changes are listed), or the catalog
    holds another bag at its location (it changed since it was catalogued)."""

    def __init__(self, bag: Path, reason: str, changes=()):
        self.changes = list(changes)
        super().__init__(f"{bag}: not added to the catalog: {reason}")


def changed_bag(bag: str | Path, entry: Entry, before: str) -> CatalogRefusal:
    """The refusal of a bag whose location holds another bag (hash ``before``)."""
    return CatalogRefusal(Path(bag), f"the catalog holds another bag at {entry.location} "
                                     f"(hash {before}, now {entry.bag_hash}): the bag was "
                                     f"changed and re-hashed since it was catalogued")


@dataclass(frozen=True)
class Entry:
    bag_hash: str
    location: str
    campaign_id: str
    title: str
    aircraft: str
    report_number: str
    revision: str
    issue_date: str
    first_test_date: str
    last_test_date: str
    outcome: str
    passed: int
    failed: int
    not_shown: int
    dq_errors: int
    dq_warnings: int
    software: str

    def as_dict(self) -> dict:
        return asdict(self)


FIELDS = tuple(Entry.__dataclass_fields__)


def _first(info: dict[str, list[str]], label: str) -> str:
    return (info.get(label) or [""])[0]


def describe(bag: str | Path) -> tuple[Entry, list[tuple]]:
    """The catalog entry and verdict rows of the bag at ``bag`` (a folder or a .zip).

    Raises CatalogRefusal when the bag is not intact, BagError when it is not a bag.
    """
    bag = Path(bag)
    with opened_bag(bag) as folder:
        changes = check_bag(folder)
        if changes:
            raise CatalogRefusal(bag, "the bag is not intact", changes)
        info = read_info(folder)
        _, results = archived_results(folder)
        digest = bag_hash(folder)
    dates = sorted(info.get("Test-Date", [])) or [""]
    try:
        counts, findings = results["counts"], results["finding_counts"]
        entry = Entry(
            bag_hash=digest, location=str(bag.resolve()),
            campaign_id=_first(info, "Campaign-Id"),
            title=_first(info, "External-Description"),
            aircraft=_first(info, "Aircraft-Model"),
            report_number=_first(info, "Report-Number"),
            revision=_first(info, "Report-Revision"), issue_date=_first(info, "Issue-Date"),
            first_test_date=dates[0], last_test_date=dates[-1], outcome=results["outcome"],
            passed=counts["PASS"], failed=counts["FAIL"], not_shown=counts["NOT SHOWN"],
            dq_errors=findings["error"], dq_warnings=findings["warning"],
            software=_first(info, "Bag-Software-Agent"))
        verdicts = [(digest, v["id"], v["clause"], v["run"], v["gear"], v["verdict"])
                    for v in results["verdicts"]]
    except (KeyError, TypeError) as error:
        raise BagError(f"{bag}: its results.json lacks what the catalog indexes "
                       f"({error})") from None
    _check_indexed(bag, entry, verdicts)
    return entry, verdicts


_COUNTS = {"passed", "failed", "not_shown", "dq_errors", "dq_warnings"}
_VERDICT_FIELDS = ("bag_hash", "id", "clause", "run", "gear", "verdict")


def _is_text(value: object) -> bool:
    """Text both databases store as it is: UTF-8 (a lone surrogate, which JSON's \\ud800
    gives, is not) without a NUL character (PostgreSQL's text cannot hold one)."""
    if not isinstance(value, str) or "\0" in value:
        return False
    try:
        value.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def _check_indexed(bag: Path, entry: Entry, verdicts: list[tuple]) -> None:
    """Raise BagError unless every value indexed is what its column holds: a count a
    whole number from 0 to 2^63 - 1 (the 64-bit integers of SQLite and of PostgreSQL's
    BIGINT), anything else text (:func:`_is_text`); a verdict's run and gear may be null.
    A results.json edited and re-hashed can hold anything."""
    def refuse(name: str, value: object, expected: str):
        raise BagError(f"{bag}: its results.json holds {shown(value)} where the catalog "
                       f"indexes {name}: expected {expected}")

    for name, value in entry.as_dict().items():
        if name in _COUNTS:
            if type(value) is not int or not 0 <= value < 2 ** 63:
                refuse(name, value, "a count (a whole number from 0)")
        elif not _is_text(value):
            refuse(name, value, "text")
    for row in verdicts:
        for name, value in zip(_VERDICT_FIELDS, row):
            if name in ("run", "gear") and value is None:
                continue
            if not _is_text(value):
                refuse(f"verdicts[].{name}", value, "text")


def search_query(placeholder: str, like: str, collate: str, text: str | None = None, *,
                 aircraft: str | None = None, campaign: str | None = None,
                 outcome: str | None = None, since: str | None = None,
                 until: str | None = None, verdict: str | None = None,
                 clause: str | None = None) -> tuple[str, list[str]]:
    """The query of :func:`certkit.archive.catalog.search` and its values, in the SQL of a
    database whose parameters are written ``placeholder`` ("?" in SQLite, "%s" in
    psycopg), whose case-insensitive LIKE is ``like`` (SQLite's LIKE is, PostgreSQL's
    ILIKE) and whose byte-order collation is ``collate`` (so that both list in one order).
    """
    where, values = [], []

    def matches(columns: tuple[str, ...], value: str) -> str:
        pattern = "%" + value.replace("\\", "\\\\").replace("%", "\\%").replace("_", "\\_") + "%"
        values.extend([pattern] * len(columns))
        return "(" + " OR ".join(f"{c} {like} {placeholder} ESCAPE '\\'"
                                 for c in columns) + ")"

    if text:
        where.append(matches(("campaign_id", "title", "aircraft", "report_number"), text))
    if aircraft:
        where.append(matches(("aircraft",), aircraft))
    if campaign:
        where.append(matches(("campaign_id",), campaign))
    if outcome:
        where.append(f"upper(outcome) = upper({placeholder})")
        values.append(outcome)
    if since:
        where.append(f"last_test_date >= {placeholder}")
        values.append(since)
    if until:
        where.append(f"first_test_date <= {placeholder}")
        values.append(until)
    if verdict or clause:
        inner = ["v.bag_hash = campaigns.bag_hash"]
        if verdict:
            inner.append(f"upper(v.verdict) = upper({placeholder})")
            values.append(verdict)
        if clause:
            inner.append(matches(("v.clause", "v.id"), clause))
        where.append(f"EXISTS (SELECT 1 FROM verdicts v WHERE {' AND '.join(inner)})")
    order = ", ".join(f"{column}{collate}" for column in
                      ("aircraft", "campaign_id", "issue_date", "location"))
    query = f"SELECT {', '.join(FIELDS)} FROM campaigns" + \
        (" WHERE " + " AND ".join(where) if where else "") + f" ORDER BY {order}"
    return query, values


# ------------------------------------------------------------------ where the catalog is
_URL = re.compile(r"([A-Za-z][A-Za-z0-9+.-]*)://")
POSTGRESQL_SCHEMES = ("postgresql", "postgres")


def postgresql_url(catalog: str | Path) -> str | None:
    """``catalog`` when it is a ``postgresql://`` (or ``postgres://``) URL, else None (a
    file path).  Raises CertkitInputError for a URL of another kind."""
    if not isinstance(catalog, str):
        return None
    found = _URL.match(catalog)
    if found is None:
        return None
    if found.group(1).lower() in POSTGRESQL_SCHEMES:
        return catalog
    raise CertkitInputError.single(
        without_password(catalog), None, "--catalog",
        f"expected a file path or a postgresql://user@host[:port]/database URL, found a "
        f"{found.group(1)}:// URL")


def without_password(catalog: str | Path) -> str:
    """The catalog's location as it may be printed: a path as it is, a URL without the
    password of its user part or of a ``password=`` parameter."""
    text = str(catalog)
    if not isinstance(catalog, str) or not _URL.match(text):
        return text
    try:
        parts = urllib.parse.urlsplit(text)
        netloc = parts.netloc
        if "@" in netloc:
            user, _, hosts = netloc.rpartition("@")
            netloc = f"{user.partition(':')[0]}@{hosts}"
        query = urllib.parse.urlencode(
            [(key, value) for key, value in urllib.parse.parse_qsl(parts.query,
                                                                    keep_blank_values=True)
             if key != "password"], safe="/:,")
        return urllib.parse.urlunsplit((parts.scheme, netloc, parts.path, query,
                                        parts.fragment))
    except ValueError:
        return f"{_URL.match(text).group(0)}… (a URL that cannot be read, not shown)"
