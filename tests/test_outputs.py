"""The output folder: never replaces the campaign, the current folder or foreign files."""

import os
import signal
import subprocess
import sys
import time

import pytest
from typer.testing import CliRunner

from certkit.cli import app

runner = CliRunner()


def report(spec, out):
    # folder handling, not the model: --no-model keeps these fast
    return runner.invoke(app, ["report", str(spec), "-o", str(out), "--no-model"])


def test_output_into_the_campaign_folder_is_refused_and_nothing_is_deleted(small_campaign):
    before = sorted(p.name for p in small_campaign.parent.iterdir())
    result = report(small_campaign, small_campaign.parent)
    assert result.exit_code == 2
    assert "would contain the input" in result.output
    assert sorted(p.name for p in small_campaign.parent.iterdir()) == before


def test_output_above_the_campaign_folder_is_refused(small_campaign):
    above = small_campaign.parent.parent
    (above / "notes.txt").write_text("keep me", encoding="utf-8")
    result = report(small_campaign, above)
    assert result.exit_code == 2
    assert (above / "notes.txt").read_text(encoding="utf-8") == "keep me"
    assert small_campaign.exists()


def test_a_folder_with_foreign_files_is_not_replaced(small_campaign, tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "thesis.docx").write_bytes(b"precious")
    result = report(small_campaign, out)
    assert result.exit_code == 2 and "files certkit did not write (thesis.docx)" in result.output
    assert (out / "thesis.docx").read_bytes() == b"precious"


def test_an_earlier_report_folder_is_replaced(small_campaign, tmp_path):
    out = tmp_path / "out"
    assert report(small_campaign, out).exit_code == 0
    first = (out / "results.json").read_bytes()
    assert report(small_campaign, out).exit_code == 0
    assert (out / "results.json").read_bytes() == first
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "small"]


@pytest.mark.parametrize("target", [".", ""])
def test_the_current_folder_is_refused(small_campaign, tmp_path, target, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = report(small_campaign, target)
    assert result.exit_code == 2 and "Traceback" not in result.output


def test_output_below_a_file_is_an_input_error(small_campaign, tmp_path):
    (tmp_path / "afile").write_text("x", encoding="utf-8")
    result = report(small_campaign, tmp_path / "afile" / "out")
    assert result.exit_code == 2 and "cannot create the output folder" in result.output


def test_symbolic_link_output_is_refused(small_campaign, tmp_path):
    (tmp_path / "real").mkdir()
    (tmp_path / "link").symlink_to(tmp_path / "real")
    result = report(small_campaign, tmp_path / "link")
    assert result.exit_code == 2 and "symbolic link" in result.output


def test_terminated_report_leaves_nothing_behind(small_campaign, tmp_path):
    process = subprocess.Popen([sys.executable, "-m", "certkit.cli", "report", str(small_campaign),
                                "-o", str(tmp_path / "deep" / "er" / "out"), "--no-model"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    # wait until the staging folder exists, then terminate mid-render
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not list((tmp_path).rglob(".out.tmp-*")):
        time.sleep(0.05)
    process.send_signal(signal.SIGTERM)
    process.wait(timeout=60)
    assert process.returncode == 128 + signal.SIGTERM
    assert sorted(os.listdir(tmp_path)) == ["small"]


def test_user_files_inside_a_report_like_folder_are_not_deleted(small_campaign, tmp_path):
    out = tmp_path / "u"
    (out / "tables").mkdir(parents=True)
    (out / "tables" / "my_analysis.xlsx").write_bytes(b"keep")
    result = report(small_campaign, out)
    assert result.exit_code == 2 and "tables/my_analysis.xlsx" in result.output
    assert (out / "tables" / "my_analysis.xlsx").read_bytes() == b"keep"


def test_dot_dot_target_is_checked_as_the_folder_it_names(small_campaign, tmp_path, monkeypatch):
    monkeypatch.chdir(small_campaign.parent)
    (tmp_path / "v" / "tables").mkdir(parents=True)
    result = report(small_campaign, tmp_path / "v" / "tables" / "..")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "v" / "report.pdf").exists()


def test_new_output_folder_follows_the_umask_and_existing_keeps_its_mode(small_campaign, tmp_path):
    previous = os.umask(0o077)
    try:
        assert report(small_campaign, tmp_path / "private").exit_code == 0
    finally:
        os.umask(previous)
    assert (tmp_path / "private").stat().st_mode & 0o777 == 0o700
    (tmp_path / "shared").mkdir(mode=0o750)
    (tmp_path / "shared").chmod(0o750)
    assert report(small_campaign, tmp_path / "shared").exit_code == 0
    assert (tmp_path / "shared").stat().st_mode & 0o777 == 0o750
