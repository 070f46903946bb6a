"""The drop-model evidence cache: found again only when the inputs and the code that made
the evidence are unchanged; never trusted when unreadable or writable by others."""

from __future__ import annotations

import os
import shutil
import sys

import pytest

from certkit import load_campaign
from certkit.evidence import cache, pipeline
from certkit.evidence import model_evidence as model_evidence_module
from certkit.physics.calibration import KNOBS
from certkit.physics.effects import CANDIDATES


def test_the_key_changes_with_any_input_file_and_not_with_the_folder(timeseries_campaign,
                                                                     tmp_path):
    first = cache.key(load_campaign(timeseries_campaign), "model evidence")
    assert first == cache.key(load_campaign(timeseries_campaign), "model evidence")
    assert first != cache.key(load_campaign(timeseries_campaign), "other evidence")
    # the same files elsewhere (the archive's copy): the same entry
    moved = tmp_path / "elsewhere"
    shutil.copytree(timeseries_campaign.parent, moved)
    assert cache.key(load_campaign(moved / timeseries_campaign.name), "model evidence") == first
    # one byte of a data file: another key
    data = next(p for p in timeseries_campaign.parent.rglob("*.csv"))
    text = data.read_text(encoding="utf-8")
    data.write_text(text[:-2] + ("1" if text[-2] != "1" else "2") + text[-1:],
                    encoding="utf-8")
    assert cache.key(load_campaign(timeseries_campaign), "model evidence") != first
    data.write_text(text, encoding="utf-8")
    assert cache.key(load_campaign(timeseries_campaign), "model evidence") == first
    # the spec: even a comment changes its bytes, so another key
    with timeseries_campaign.open("a", encoding="utf-8") as spec:
        spec.write("# reviewed\n")
    assert cache.key(load_campaign(timeseries_campaign), "model evidence") != first


def test_the_key_changes_with_the_code_that_makes_evidence_not_with_its_layout(
        timeseries_campaign, tmp_path, monkeypatch):
    package = tmp_path / "certkit"
    shutil.copytree(cache.PACKAGE, package, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(cache, "PACKAGE", package)
    campaign = load_campaign(timeseries_campaign)
    first = cache.key(campaign, "model evidence")
    for presentation in ("evidence/view.py", "evidence/figures.py", "cli/campaign.py"):
        with (package / presentation).open("a", encoding="utf-8") as module:
            module.write("\n# layout only\n")
        assert cache.key(campaign, "model evidence") == first, presentation
    for physics in ("physics/dynamics.py", "gap/selection.py", "ident/__init__.py",
                    "evidence/model_evidence.py", "version.py"):
        original = (package / physics).read_bytes()
        (package / physics).write_bytes(original + b"\n# changed\n")
        assert cache.key(campaign, "model evidence") != first, physics
        (package / physics).write_bytes(original)
    assert cache.key(campaign, "model evidence") == first


def test_knobs_and_candidates_are_kept_by_name_and_come_back_as_the_registry_s(tmp_path):
    knob, candidate = KNOBS["gas-precharge"], CANDIDATES[3]
    kept = {"knobs": [knob], "chosen": (candidate,), "value": 1.5}
    assert cache.store("k" * 64, kept, tmp_path) is None
    back = cache.load("k" * 64, tmp_path)
    assert back["knobs"][0] is knob and back["chosen"][0] is candidate
    assert back["value"] == 1.5


def test_an_entry_that_cannot_be_read_or_trusted_counts_as_absent(tmp_path):
    assert cache.load("a" * 64, tmp_path) is None              # absent
    (tmp_path / f"{'b' * 64}.pickle").write_bytes(b"not a pickle")
    assert cache.load("b" * 64, tmp_path) is None              # damaged
    assert cache.store("c" * 64, {"x": 1}, tmp_path) is None
    assert cache.load("c" * 64, tmp_path) == {"x": 1}
    if hasattr(os, "getuid"):
        tmp_path.chmod(0o777)                                  # others may write: not trusted
        assert cache.load("c" * 64, tmp_path) is None
        tmp_path.chmod(0o700)
        assert cache.load("c" * 64, tmp_path) == {"x": 1}


def test_what_cannot_be_kept_is_not_stored_and_says_why(tmp_path):
    assert "cannot be pickled" in cache.store("d" * 64, {"f": lambda: 1}, tmp_path)
    assert not list(tmp_path.iterdir())                        # no temporary file left
    blocked = tmp_path / "a-file"
    blocked.write_text("not a folder", encoding="utf-8")       # the cache folder is a file
    assert str(blocked) in cache.store("e" * 64, {"x": 1}, blocked)


def test_an_entry_is_readable_by_its_owner_only(tmp_path):
    assert cache.store("f" * 64, {"x": 1}, tmp_path / "cache") is None
    assert (tmp_path / "cache" / f"{'f' * 64}.pickle").stat().st_mode & 0o777 == 0o600


def test_only_the_newest_entries_are_kept(tmp_path, monkeypatch):
    monkeypatch.setattr(cache, "KEEP", 3)
    for index in range(5):
        assert cache.store(f"{index:064d}", index, tmp_path) is None
        os.utime(tmp_path / f"{index:064d}.pickle", (1000 + index, 1000 + index))
    cache._prune(tmp_path)
    assert sorted(p.name[-8:] for p in tmp_path.glob("*.pickle")) == \
        ["2.pickle", "3.pickle", "4.pickle"]


def test_make_evidence_reuses_the_kept_evidence_unless_told_not_to(timeseries_campaign,
                                                                   tmp_path, monkeypatch):
    monkeypatch.setenv("CERTKIT_CACHE", str(tmp_path / "cache"))
    made = []

    def fake(campaign, progress=None):
        made.append(campaign.spec_path)
        return model_evidence_module.ModelEvidence(None, f"evidence {len(made)}")

    monkeypatch.setattr(model_evidence_module, "model_evidence", fake)
    campaign = load_campaign(timeseries_campaign)
    steps = []
    _, first = pipeline.make_evidence(campaign, progress=steps.append)
    _, second = pipeline.make_evidence(campaign, progress=steps.append)
    assert first.note == second.note == "evidence 1" and len(made) == 1
    assert any("taken from the cache" in step for step in steps)
    # and the run says the report will have no model appendices, each time
    assert steps.count("no drop-model appendices: evidence 1") == 2
    _, third = pipeline.make_evidence(campaign, cache=False)
    assert third.note == "evidence 2" and len(made) == 2
    # the kept entry is the first one still: --no-cache neither reads nor writes
    _, fourth = pipeline.make_evidence(campaign)
    assert fourth.note == "evidence 1"


@pytest.mark.skipif(sys.platform != "linux", reason="XDG_CACHE_HOME is the Linux convention")
@pytest.mark.parametrize("name", ["CERTKIT_CACHE", "XDG_CACHE_HOME"])
def test_the_cache_folder_can_be_moved(name, tmp_path, monkeypatch):
    monkeypatch.delenv("CERTKIT_CACHE", raising=False)
    monkeypatch.setenv(name, str(tmp_path))
    assert cache.cache_folder().is_relative_to(tmp_path)
