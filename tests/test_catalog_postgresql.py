"""The catalog on PostgreSQL, what only a server has: a URL's password (never printed),
logins and servers that refuse, a connection lost mid-addition, a role without the
privilege, and psycopg missing.  The tests shared with SQLite are in test_catalog.py;
those here that need a server take ``postgresql_database`` (tests/conftest.py), the others
need only psycopg."""

import importlib.util
import socket
import subprocess
import sys
import uuid
from pathlib import Path

import pytest
from typer.testing import CliRunner

from certkit.archive.catalog import add, search
from certkit.archive.catalog_rows import postgresql_url, without_password
from certkit.cli import app
from certkit.errors import CertkitInputError

from .conftest import admin_execute, database_url, skip_or_fail
from .test_catalog import make_bag, rows

runner = CliRunner()
SECRET = "hunter2-s3cret"


@pytest.fixture
def psycopg_installed():
    if importlib.util.find_spec("psycopg") is None:
        skip_or_fail("psycopg is not installed: pip install 'certkit[postgresql]'")


@pytest.fixture
def bag(tmp_path) -> Path:
    return make_bag(tmp_path / "bag", "LSA-1", "Skylark LSA", ["2025-03-02"],
                    {"CFR23.725a/D1": "PASS"})


def _closed_port() -> int:
    with socket.socket() as probe:           # a port nothing listens on, just freed
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _with_password(url: str, password: str) -> str:
    user, _, rest = url.partition("://")[2].partition("@")
    return f"postgresql://{user.partition(':')[0]}:{password}@{rest}"


# ------------------------------------------------------------------ the URL as shown
def test_a_url_is_shown_without_its_password():
    assert without_password("postgresql://lab:pw@db.example:5433/certkit") == \
        "postgresql://lab@db.example:5433/certkit"
    assert without_password("postgres://lab:p%40ss@h1,h2/c?password=x&sslmode=require") == \
        "postgres://lab@h1,h2/c?sslmode=require"
    assert without_password("postgresql://lab:a@b@host/c") == "postgresql://lab@host/c"
    assert without_password("postgresql://host/c") == "postgresql://host/c"
    assert without_password("postgresql://lab:pw@[::1/c") == \
        "postgresql://… (a URL that cannot be read, not shown)"
    assert without_password(Path("/lab/catalog.sqlite")) == "/lab/catalog.sqlite"
    assert postgresql_url("POSTGRES://h/c") == "POSTGRES://h/c"
    assert postgresql_url("/lab/postgresql:/x") is None and postgresql_url(Path("p")) is None
    with pytest.raises(CertkitInputError, match="found a mysql:// URL"):
        postgresql_url("mysql://lab:pw@host/c")


def test_a_url_of_another_database_is_an_input_error(bag):
    result = runner.invoke(app, ["catalog", "add", str(bag), "--catalog",
                                 f"mysql://lab:{SECRET}@host/c"])
    assert result.exit_code == 2 and "expected a file path or a postgresql://" in result.output
    assert SECRET not in result.output


def test_a_url_password_is_never_printed(bag, postgresql_database):
    # the test server trusts local logins: the password is given, and ignored
    for catalog in (_with_password(postgresql_database, SECRET),
                    f"{postgresql_database}?password={SECRET}"):
        outputs = [runner.invoke(app, ["catalog", *command, "--catalog", catalog]).output
                   for command in (["list"], ["add", str(bag)], ["add", str(bag)], ["list"],
                                   ["search", "LSA"], ["search", "--json", "LSA"],
                                   ["search", "nothing"])]
        assert outputs[1].startswith(("added: LSA-1", "already catalogued: LSA-1"))
        assert outputs[2].startswith("already catalogued: LSA-1"), outputs
        assert f"1 archived campaign(s) in {without_password(catalog)}:" in outputs[3]
        assert not any(SECRET in output for output in outputs), outputs
    for refused in (database_url(_with_password(postgresql_database, SECRET), "no_such_db"),
                    f"postgresql://lab:{SECRET}@127.0.0.1:{_closed_port()}/c"):
        result = runner.invoke(app, ["catalog", "list", "--catalog", refused])
        assert result.exit_code in (2, 4) and SECRET not in result.output, result.output
        assert without_password(refused) in result.output


# ------------------------------------------------------------------ connections refused
def test_an_unreachable_server_is_the_machines_refusal_without_a_traceback(psycopg_installed):
    catalog = f"postgresql://lab:{SECRET}@127.0.0.1:{_closed_port()}/certkit"
    completed = subprocess.run([sys.executable, "-m", "certkit.cli", "catalog", "list",
                                "--catalog", catalog], capture_output=True, text=True,
                               timeout=120)
    assert completed.returncode == 4, completed.stderr
    assert completed.stderr.startswith(f"error: {without_password(catalog)}: cannot connect "
                                       f"to the catalog's server: ")
    assert "Connection refused" in completed.stderr and "check that it is running" in \
        completed.stderr
    assert "Traceback" not in completed.stderr and SECRET not in completed.stderr


def test_an_unknown_database_or_unreadable_url_is_bad_input(postgresql_server, bag):
    for catalog, words in ((database_url(postgresql_server, "no_such_db"),
                            'database "no_such_db" does not exist'),
                           ("postgresql://lab@127.0.0.1:port/c", "not a PostgreSQL URL"),
                           ("postgresql://lab@127.0.0.1/c?colour=red", "not a PostgreSQL URL")):
        result = runner.invoke(app, ["catalog", "add", str(bag), "--catalog", catalog])
        assert result.exit_code == 2, (result.output, result.exception)
        assert words in result.output and "--catalog" in result.output, result.output


def test_a_login_the_server_refuses_is_bad_input(postgresql_server, postgresql_database, bag,
                                                 monkeypatch):
    # .ci/postgresql's server asks the members of password_login for their password
    if rows(postgresql_server, "SELECT 1 FROM pg_roles WHERE rolname = 'password_login'") \
            != [(1,)]:
        skip_or_fail("the server trusts every login: the role password_login, whose members "
                     "must give a password, is missing (.ci/postgresql makes it)")
    role = f"lab_{uuid.uuid4().hex[:12]}"
    admin_execute(postgresql_server,
                  f"CREATE ROLE {role} LOGIN PASSWORD 'right' IN ROLE password_login")
    try:
        name = postgresql_database.rpartition("/")[2]
        admin_execute(database_url(postgresql_server, name),
                      f"GRANT ALL ON SCHEMA public TO {role}")
        url = postgresql_database.replace("postgres@", f"{role}@", 1)
        monkeypatch.delenv("PGPASSWORD", raising=False)
        monkeypatch.setenv("PGPASSFILE", str(Path(__file__).parent / "no-such-pgpass"))
        for catalog, words in ((url, "no password supplied"),
                               (_with_password(url, SECRET), "password authentication failed")):
            result = runner.invoke(app, ["catalog", "add", str(bag), "--catalog", catalog])
            assert result.exit_code == 2, (result.output, result.exception)
            assert words in result.output and SECRET not in result.output, result.output
            assert "(~/.pgpass or PGPASSWORD)" in result.output
        monkeypatch.setenv("PGPASSWORD", "right")       # the password kept out of the URL
        result = runner.invoke(app, ["catalog", "add", str(bag), "--catalog", url])
        assert result.exit_code == 0 and result.output.startswith("added: LSA-1")
    finally:
        admin_execute(database_url(postgresql_server, postgresql_database.rpartition("/")[2]),
                      f"DROP OWNED BY {role}")
        admin_execute(postgresql_server, f"DROP ROLE {role}")


def test_a_role_that_may_not_create_the_tables_is_told_what_to_grant(postgresql_server,
                                                                     postgresql_database, bag):
    role = f"reader_{uuid.uuid4().hex[:12]}"
    admin_execute(postgresql_server, f"CREATE ROLE {role} LOGIN")
    try:
        url = postgresql_database.replace("postgres@", f"{role}@", 1)
        result = runner.invoke(app, ["catalog", "add", str(bag), "--catalog", url])
        assert result.exit_code == 4, (result.output, result.exception)
        assert "permission denied for schema public" in result.output
        assert "GRANT CREATE ON SCHEMA" in result.output
        assert runner.invoke(app, ["catalog", "list", "--catalog", url]).exit_code == 0
        # a reader's role: the catalog made by its owner, SELECT granted, nothing more
        add(postgresql_database, bag)
        admin_execute(postgresql_database, f"GRANT SELECT ON campaigns, verdicts, "
                                           f"certkit_catalog TO {role}")
        result = runner.invoke(app, ["catalog", "list", "--catalog", url])
        assert result.exit_code == 0 and result.output.startswith("1 archived campaign(s)")
        other = make_bag(bag.parent / "other", "AMPH-1", "Heron", ["2024-01-10"],
                         {"CFR23.725a/D1": "PASS"})
        result = runner.invoke(app, ["catalog", "add", str(other), "--catalog", url])
        assert result.exit_code == 4 and "permission denied for table" in result.output
    finally:
        admin_execute(postgresql_database, f"DROP OWNED BY {role}")
        admin_execute(postgresql_server, f"DROP ROLE {role}")


# ------------------------------------------------------------------ a failed addition
@pytest.mark.parametrize("before", [[], ["AMPH-1"]], ids=["new catalog", "one campaign"])
def test_a_connection_lost_before_the_commit_leaves_the_catalog_as_it_was(
        postgresql_database, postgresql_server, bag, tmp_path, monkeypatch, before):
    from certkit.archive import catalog_postgresql

    if before:
        add(postgresql_database, make_bag(tmp_path / "other", "AMPH-1", "Heron amphibian",
                                          ["2024-01-10"], {"CFR23.725a/D1": "PASS"}))
    real = catalog_postgresql._add_rows

    def then_lost(connection, *arguments):
        added = real(connection, *arguments)     # schema and rows written, not committed
        rows(postgresql_server,
             f"SELECT pg_terminate_backend({connection.info.backend_pid})")
        return added

    monkeypatch.setattr(catalog_postgresql, "_add_rows", then_lost)
    result = runner.invoke(app, ["catalog", "add", str(bag), "--catalog", postgresql_database])
    assert result.exit_code == 4, (result.output, result.exception)
    assert "the server failed or the connection was lost" in result.output
    assert [e.campaign_id for e in search(postgresql_database)] == before
    tables = rows(postgresql_database, "SELECT tablename FROM pg_tables WHERE schemaname = "
                                       "'public' ORDER BY tablename")
    assert tables == ([("campaigns",), ("certkit_catalog",), ("verdicts",)] if before else [])


# ------------------------------------------------------------------ psycopg missing
def test_a_url_without_psycopg_says_what_to_install(bag, monkeypatch):
    for name in [m for m in sys.modules if m == "psycopg" or m.startswith("psycopg.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "psycopg", None)       # import psycopg -> ImportError
    catalog = f"postgresql://lab:{SECRET}@db.example/certkit"
    for command in (["add", str(bag)], ["list"]):
        result = runner.invoke(app, ["catalog", *command, "--catalog", catalog])
        assert result.exit_code == 2, (result.output, result.exception)
        assert "pip install 'certkit[postgresql]'" in result.output
        assert "postgresql://lab@db.example/certkit" in result.output
        assert SECRET not in result.output


def test_the_command_line_and_an_sqlite_catalog_do_not_import_psycopg(bag, tmp_path):
    script = (f"import sys\n"
              f"from typer.testing import CliRunner\n"
              f"from certkit.cli import app\n"
              f"result = CliRunner().invoke(app, ['catalog', 'add', {str(bag)!r}, "
              f"'--catalog', {str(tmp_path / 'c.sqlite')!r}])\n"
              f"assert result.exit_code == 0, result.output\n"
              f"print(sorted(m for m in sys.modules if m.startswith('psycopg')))\n")
    completed = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                               timeout=120)
    assert completed.returncode == 0, completed.stderr
    assert completed.stdout.strip() == "[]"


def test_a_deadlock_is_retried_and_at_last_reported(postgresql_database, bag, monkeypatch):
    from psycopg import errors

    from certkit.archive import catalog_postgresql

    real, calls = catalog_postgresql._add_rows, []

    def deadlocked(times):
        def add_rows(*arguments):
            calls.append(1)
            if len(calls) <= times:
                raise errors.DeadlockDetected("deadlock detected")
            return real(*arguments)
        return add_rows

    monkeypatch.setattr(catalog_postgresql, "_add_rows", deadlocked(2))
    assert add(postgresql_database, bag)[1] is True and len(calls) == 3
    calls.clear()
    monkeypatch.setattr(catalog_postgresql, "_add_rows", deadlocked(99))
    result = runner.invoke(app, ["catalog", "add", str(bag), "--catalog", postgresql_database])
    assert result.exit_code == 4 and "it collided with other additions 5 times (deadlock " \
        "detected); try again" in result.output, result.output
    assert len(calls) == catalog_postgresql.RETRIES


def test_a_catalog_held_past_the_timeout_is_the_machines_refusal(postgresql_database, bag,
                                                                 tmp_path, monkeypatch):
    import psycopg

    from certkit.archive import catalog_postgresql

    add(postgresql_database, make_bag(tmp_path / "other", "AMPH-1", "Heron amphibian",
                                      ["2024-01-10"], {"CFR23.725a/D1": "PASS"}))
    monkeypatch.setattr(catalog_postgresql, "TIMEOUT_S", 0.5)
    with psycopg.connect(postgresql_database) as holder:       # a transaction left open
        holder.execute("LOCK TABLE campaigns IN SHARE ROW EXCLUSIVE MODE")
        result = runner.invoke(app, ["catalog", "add", str(bag), "--catalog",
                                     postgresql_database])
    assert result.exit_code == 4, (result.output, result.exception)
    assert "cannot add to the catalog: another process held it for 0.5 s; try again" \
        in result.output
    assert [e.campaign_id for e in search(postgresql_database)] == ["AMPH-1"]
