"""The command line: exit codes, help on every command, schema output."""

import json
import subprocess
import sys

import pytest
from typer.testing import CliRunner

from certkit.cli import app

from .conftest import SEED

runner = CliRunner()


@pytest.mark.parametrize("command", [[], ["validate"], ["report"], ["schema"], ["sets"]])
def test_every_command_has_help(command):
    result = runner.invoke(app, command + ["--help"])
    assert result.exit_code == 0
    assert "Usage" in result.output


def test_validate_accepts_the_example():
    result = runner.invoke(app, ["validate", str(SEED)])
    assert result.exit_code == 0, result.output
    assert "valid" in result.output


def test_schema_is_json_schema_of_the_spec():
    result = runner.invoke(app, ["schema"])
    schema = json.loads(result.output)
    assert schema["title"] == "certkit campaign spec"
    assert schema["additionalProperties"] is False
    assert {"campaign", "document", "aircraft", "gear_units", "runs"} <= set(schema["required"])


def test_strict_exits_1_when_the_audit_finds_errors(tmp_path):
    # the seed campaign has data-quality errors (strut efficiency above 1, ...)
    out = tmp_path / "out"
    completed = subprocess.run([sys.executable, "-m", "certkit.cli", "report", str(SEED), "-o",
                                str(out), "--strict", "--no-model"], capture_output=True,
                               text=True, timeout=300)
    assert completed.returncode == 1, completed.stderr
    assert (out / "report.pdf").exists()
    assert "Traceback" not in completed.stderr


def test_timeseries_campaign_reports_with_exit_0(timeseries_campaign, tmp_path):
    result = runner.invoke(app, ["report", str(timeseries_campaign), "-o", str(tmp_path / "o")])
    assert result.exit_code == 0, result.output
    assert "wrote" in result.output
    # its gear has no strut servicing: the model section says why it is empty, by key
    html = (tmp_path / "o" / "report.html").read_text(encoding="utf-8")
    assert "The drop model cannot be built from the spec" in html
    assert "gear_units[0].strut.pneumatic_area" in html


def test_validate_exits_2_with_located_messages_in_a_real_process(timeseries_campaign):
    text = timeseries_campaign.read_text(encoding="utf-8")
    text = text.replace("drop_height: 300 mm", "drop_heigth: 300 mm")
    text = text.replace("date: 2025-03-01", "date: 2025-02-30")  # 2025 is not a leap year
    timeseries_campaign.write_text(text, encoding="utf-8")
    lines = text.splitlines()
    typo = next(n for n, line in enumerate(lines, 1) if "drop_heigth" in line)
    date = next(n for n, line in enumerate(lines, 1) if "2025-02-30" in line)
    completed = subprocess.run([sys.executable, "-m", "certkit.cli", "validate",
                                str(timeseries_campaign)], capture_output=True, text=True,
                               timeout=120)
    assert completed.returncode == 2, completed.stderr
    assert "Traceback" not in completed.stderr
    assert f"campaign.yaml:{date} document.date: \"2025-02-30\" is not a date: February 2025 " \
           f"has 28 days" in completed.stderr
    assert f"campaign.yaml:{typo} runs[0].drop_heigth: unknown key 'drop_heigth': did you " \
           f"mean 'drop_height'?" in completed.stderr
    assert "drop_height: required key is missing" not in completed.stderr


def _every_command():
    """(path, click command) of the application and every command under it."""
    import typer

    stack = [((), typer.main.get_command(app))]
    while stack:
        path, command = stack.pop()
        yield path, command
        for name, sub in getattr(command, "commands", {}).items():
            stack.append(((*path, name), sub))


COMMANDS = dict(_every_command())


@pytest.mark.parametrize("path", sorted(COMMANDS), ids=" ".join)
def test_help_names_each_value_in_words_and_cuts_no_sentence(path):
    result = runner.invoke(app, [*path, "--help"], terminal_width=80)
    assert result.exit_code == 0
    text = result.output
    # no type column of typer's (<path>, <bool>, <list[Path]>), no braces around arguments
    assert "<" not in text and "{" not in text, text
    # every option or argument that takes a value names it in words, in capitals (FILE,
    # FOLDER, SHARE, DATE, ...); a flag takes none
    for param in COMMANDS[path].params:
        if getattr(param, "is_flag", False) or param.name == "help":
            continue
        assert param.metavar and param.metavar.rstrip(".").isupper(), (path, param.name)
    # the list of commands shows each one's first clause whole, not cut with "..."
    if "Commands:" in text:
        listing = text.split("Commands:")[1].split("\n\n")[0]
        assert "..." not in listing, listing
