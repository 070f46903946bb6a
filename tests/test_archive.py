"""`certkit archive` and `certkit verify`: a BagIt bag of the campaign that is the same
from the same inputs, names every file added, removed or modified, reads zips safely,
and whose results reproduce from its inputs."""

import datetime as dt
import hashlib
import json
import os
import shutil
import subprocess
import sys
import zipfile
from importlib import metadata
from pathlib import Path

import bagit
import pytest
from typer.testing import CliRunner

from certkit.archive.campaign_bag import archive_campaign, compare_results, verify_archive
from certkit.archive.bag import BagError, check_bag, extract_zip, read_info, write_bag, write_zip
from certkit.cli import app

from .conftest import SEED

runner = CliRunner()
INPUTS = ["campaign.yaml", "data/D200.csv", "data/D250.csv", "data/D300.csv",
          "blind-check/blind-check.json"]


def _tree(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def bag(tmp_path_factory) -> Path:
    """The example campaign archived (without the drop model, for speed)."""
    target = tmp_path_factory.mktemp("archive") / "SEED-2024"
    archive_campaign(SEED, target, model=False)
    return target


@pytest.fixture
def copy(bag, tmp_path) -> Path:
    target = tmp_path / "copy"
    shutil.copytree(bag, target)
    return target


def test_the_bag_holds_the_campaign_results_report_and_environment(bag):
    files = _tree(bag)
    for name in INPUTS:   # every input, byte for byte, at its place relative to the spec
        assert files[f"data/campaign/{name}"] == (SEED.parent / name).read_bytes(), name
    for name in ("report.html", "report.pdf", "results.json", "tables/verdicts.csv",
                 "tables/findings.csv"):
        assert files[f"data/results/{name}"], name
    environment = json.loads(files["data/environment.json"])
    assert environment["packages"]["numpy"] == metadata.version("numpy")
    assert environment["packages"]["weasyprint"] == metadata.version("weasyprint")
    assert environment["certkit_version"] == metadata.version("certkit")
    # the manifest: a SHA-256 per payload file, recomputed here with hashlib
    manifest = dict(reversed(line.split("  ", 1)) for line in
                    files["manifest-sha256.txt"].decode().splitlines())
    payload = {name for name in files if name.startswith("data/")}
    assert set(manifest) == payload
    for name in payload:
        assert manifest[name] == hashlib.sha256(files[name]).hexdigest(), name
    tags = dict(reversed(line.split("  ", 1)) for line in
                files["tagmanifest-sha256.txt"].decode().splitlines())
    assert set(tags) == {"bagit.txt", "bag-info.txt", "manifest-sha256.txt"}
    assert files["bagit.txt"] == b"BagIt-Version: 1.0\nTag-File-Character-Encoding: UTF-8\n"


def test_bag_info_dates_come_from_the_campaign_not_the_clock(bag):
    info = read_info(bag)
    # campaign.yaml: document.date 2024-01-15, test_dates [2024-01-10]
    assert info["Bagging-Date"] == ["2024-01-15"] and info["Issue-Date"] == ["2024-01-15"]
    assert info["Test-Date"] == ["2024-01-10"]
    assert str(dt.date.today()) not in (bag / "bag-info.txt").read_text()
    assert info["External-Identifier"] == ["SEED-AMPHIBIAN-DT"]
    assert info["Campaign-Spec"] == ["data/campaign/campaign.yaml"]
    payload = [p for p in (bag / "data").rglob("*") if p.is_file()]
    assert info["Payload-Oxum"] == [f"{sum(p.stat().st_size for p in payload)}.{len(payload)}"]
    # README: 4 of the 12 criteria pass, 8 not shown, 2 data-quality errors (the D200 strut
    # efficiencies above 1)
    assert (info["Criteria-Passed"], info["Criteria-Not-Shown"], info["Data-Quality-Errors"]) \
        == (["4"], ["9"], ["2"])


def test_the_bagit_library_accepts_the_bag_and_rejects_a_tampered_one(bag, copy):
    # an independent BagIt reader (the Library of Congress's bagit-python)
    assert bagit.Bag(str(bag)).is_valid()
    with open(copy / "data" / "results" / "results.json", "r+b") as handle:
        handle.seek(100)
        byte = handle.read(1)
        handle.seek(100)
        handle.write(bytes([byte[0] ^ 1]))
    assert not bagit.Bag(str(copy)).is_valid()


@pytest.mark.slow   # several reports or archives in real processes: CI runs it
def test_two_archives_of_the_same_inputs_are_identical(bag, seed_copy, tmp_path):
    # the second made by the command line in a fresh process, from a copy of the campaign
    # in another folder, as a zip
    zipped = tmp_path / "again.zip"
    completed = subprocess.run([sys.executable, "-m", "certkit.cli", "archive", str(seed_copy),
                                "-o", str(zipped), "--no-model"], capture_output=True,
                               text=True, timeout=300)
    assert completed.returncode == 0, completed.stderr
    with zipfile.ZipFile(zipped) as handle:
        names = handle.namelist()
        unzipped = {name.split("/", 1)[1]: handle.read(name) for name in names}
    assert {name.split("/", 1)[0] for name in names} == {"again"}
    assert unzipped == _tree(bag)
    # and the zip's bytes are those of the first archive zipped under the same name
    write_zip(bag, tmp_path / "first.zip", "again", dt.date(2024, 1, 15))
    assert (tmp_path / "first.zip").read_bytes() == zipped.read_bytes()


def test_an_intact_bag_verifies(bag):
    result = runner.invoke(app, ["verify", str(bag)])
    assert result.exit_code == 0, result.output
    # 18: the campaign's 6 inputs (spec, 3 data files, 2 blind-check records) and the outputs
    assert "intact — 18 payload file(s)" in result.output
    assert check_bag(bag) == []


def _payload(bag: Path) -> list[str]:
    return sorted(p.relative_to(bag).as_posix() for p in (bag / "data").rglob("*")
                  if p.is_file())


def test_a_tampered_byte_in_any_payload_file_is_detected(bag, tmp_path):
    names = _payload(bag)
    assert len(names) == 18
    assert "data/campaign/blind-check-sealed/blind-check.json" in names
    for index, name in enumerate(names):
        copy = tmp_path / f"copy{index}"
        shutil.copytree(bag, copy)
        path = copy / name
        content = bytearray(path.read_bytes())
        position = len(content) // 2
        content[position] ^= 0x01    # one bit of one byte, the size unchanged
        path.write_bytes(bytes(content))
        changes = check_bag(copy)
        assert [(c.kind, c.path) for c in changes] == [("modified", name)], name


def test_removed_added_and_modified_files_are_each_named_with_exit_1(copy):
    (copy / "data" / "campaign" / "data" / "D250.csv").unlink()
    (copy / "data" / "campaign" / "data" / "D400.csv").write_text("time,load\n")
    (copy / "notes.txt").write_text("a file beside the manifests\n")
    info = copy / "bag-info.txt"
    info.write_text(info.read_text().replace("Criteria-Failed: 0", "Criteria-Failed: 1"))
    result = runner.invoke(app, ["verify", str(copy)])
    assert result.exit_code == 1
    lines = [line for line in result.output.splitlines() if ": data/" in line
             or line.startswith(("added", "removed", "modified"))]
    assert lines == [   # what the manifests list, in path order; then what they do not
        lines[0],
        "removed: data/campaign/data/D250.csv (listed in manifest-sha256.txt, not in the "
        "bag)",
        "added: data/campaign/data/D400.csv (in the bag, not in any manifest)",
        "added: notes.txt (in the bag, not in any manifest)",
    ]
    assert lines[0].startswith("modified: bag-info.txt (SHA-256 ")
    assert "NOT INTACT — 4 change(s)" in result.output


def test_a_missing_manifest_and_a_non_bag_are_told_apart(copy, tmp_path):
    (copy / "manifest-sha256.txt").unlink()
    kinds = {(c.kind, c.path) for c in check_bag(copy)}
    assert ("removed", "manifest-sha256.txt") in kinds
    assert ("added", "data/campaign/campaign.yaml") in kinds   # now listed nowhere
    result = runner.invoke(app, ["verify", str(tmp_path / "nothing")])
    assert result.exit_code == 2 and "not found" in result.output
    result = runner.invoke(app, ["verify", str(SEED.parent)])
    assert result.exit_code == 2 and "not a bag (no bagit.txt, no manifest" in result.output


def test_a_manifest_line_that_escapes_the_bag_is_damage(copy):
    manifest = copy / "manifest-sha256.txt"
    text = manifest.read_text()
    manifest.write_text(text + "0" * 64 + "  ../outside.txt\n")
    changes = check_bag(copy)
    assert [(c.kind, c.path) for c in changes if c.kind == "damaged"] == \
        [("damaged", "manifest-sha256.txt")]
    # the line added after the manifest's own lines (one per payload file)
    assert f"line {len(text.splitlines()) + 1}:" in changes[0].detail


# ------------------------------------------------------------------ zipped bags
def _zip(path: Path, members: dict[str, bytes], links: tuple = ()) -> Path:
    with zipfile.ZipFile(path, "w") as handle:
        for name, content in members.items():
            handle.writestr(name, content)
        for name in links:
            item = zipfile.ZipInfo(name)
            item.create_system = 3
            item.external_attr = (0o120777 << 16)
            handle.writestr(item, "/etc/passwd")
    return path


@pytest.mark.parametrize("name, why", [
    ("../evil.txt", "a path with '..'"),
    ("bag/../../evil.txt", "a path with '..'"),
    ("/tmp/evil.txt", "an absolute path"),
    ("C:/evil.txt", "an absolute path"),
    ("bag\\..\\evil.txt", "a path with '..'"),
])
def test_zip_extraction_refuses_absolute_and_parent_paths(tmp_path, name, why):
    archive = _zip(tmp_path / "bad.zip", {"bag/bagit.txt": b"BagIt-Version: 1.0\n",
                                          name: b"evil"})
    into = tmp_path / "into"
    into.mkdir()
    with pytest.raises(BagError, match=why):
        extract_zip(archive, into)
    assert list(into.iterdir()) == []          # refused before anything was written
    assert not (tmp_path / "evil.txt").exists()
    result = runner.invoke(app, ["verify", str(archive)])
    assert result.exit_code == 2 and "refused to extract" in result.output


def test_zip_extraction_refuses_links_and_repeated_names(tmp_path):
    archive = _zip(tmp_path / "link.zip", {"bag/bagit.txt": b""}, links=("bag/data/x",))
    with pytest.raises(BagError, match="a symbolic link"):
        extract_zip(archive, tmp_path)
    with zipfile.ZipFile(tmp_path / "twice.zip", "w") as handle:
        handle.writestr("bag/bagit.txt", b"a")
        with pytest.warns(UserWarning):
            handle.writestr("bag/bagit.txt", b"b")
    with pytest.raises(BagError, match="a name the zip already holds"):
        extract_zip(tmp_path / "twice.zip", tmp_path / "x")


def test_a_zipped_bag_verifies_and_its_tampering_is_named(bag, tmp_path):
    original = tmp_path / "bag.zip"
    with zipfile.ZipFile(original, "w") as handle:
        for name, content in _tree(bag).items():
            handle.writestr(f"SEED-2024/{name}", content)
    assert runner.invoke(app, ["verify", str(original)]).exit_code == 0
    tampered = tmp_path / "tampered.zip"
    with zipfile.ZipFile(tampered, "w") as handle:
        for name, content in _tree(bag).items():
            if name == "data/results/report.pdf":
                middle = len(content) // 2
                content = content[:middle] + bytes([content[middle] ^ 1]) + content[middle + 1:]
            handle.writestr(f"SEED-2024/{name}", content)
    result = runner.invoke(app, ["verify", str(tampered)])
    assert result.exit_code == 1
    assert "modified: data/results/report.pdf" in result.output


# ------------------------------------------------------------------ safety
def test_an_existing_target_is_never_replaced(bag, tmp_path):
    for target in (tmp_path / "empty", tmp_path / "file.zip"):
        if target.suffix:
            target.write_bytes(b"not mine")
        else:
            target.mkdir()
        result = runner.invoke(app, ["archive", str(SEED), "-o", str(target), "--no-model"])
        assert result.exit_code == 2, result.output
        assert "already exists; certkit never replaces an archive" in result.output
    assert (tmp_path / "file.zip").read_bytes() == b"not mine"
    assert list((tmp_path / "empty").iterdir()) == []
    result = runner.invoke(app, ["archive", str(SEED), "-o", str(bag), "--no-model"])
    assert result.exit_code == 2 and check_bag(bag) == []


def test_a_failed_archive_leaves_nothing_behind(tmp_path, monkeypatch):
    import certkit.evidence.pipeline as pipeline

    def broken(*args, **kwargs):
        raise RuntimeError("renderer failed")

    monkeypatch.setattr(pipeline, "render_report", broken)
    target = tmp_path / "new" / "deeper" / "bag"
    with pytest.raises(RuntimeError):
        archive_campaign(SEED, target, model=False)
    assert list(tmp_path.iterdir()) == []      # no bag, no staging, no parent folders


def test_bad_input_exits_2_and_writes_nothing(tmp_path):
    spec = tmp_path / "campaign.yaml"
    spec.write_text(SEED.read_text().replace("maximum_weight: 1430 lb",
                                             "maximum_weight: 1430 furlong"))
    result = runner.invoke(app, ["archive", str(spec), "-o", str(tmp_path / "bag")])
    assert result.exit_code == 2
    assert "aircraft.maximum_weight" in result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["campaign.yaml"]


# ------------------------------------------------------------------ recompute
def test_recompute_reproduces_the_archived_results(bag):
    result = runner.invoke(app, ["verify", str(bag), "--recompute"])
    assert result.exit_code == 0, result.output
    assert "results.json reproduced byte for byte" in result.output


def test_recompute_names_an_archived_number_that_does_not_reproduce(copy):
    # an archive that is intact (re-bagged) but whose results were not computed from its
    # inputs: the drop height of run D300 made 1 % larger
    results_path = copy / "data" / "results" / "results.json"
    results = json.loads(results_path.read_text())
    verdict = next(v for v in results["verdicts"] if v["id"] == "F2245-drop-height/D300")
    assert verdict["value"] == 0.3
    verdict["value"] = 0.303
    results_path.write_text(json.dumps(results, indent=2))
    for name in ("bagit.txt", "bag-info.txt", "manifest-sha256.txt", "tagmanifest-sha256.txt"):
        (copy / name).unlink()
    write_bag(copy, [("Campaign-Spec", "data/campaign/campaign.yaml")])
    assert check_bag(copy) == []
    verification = verify_archive(copy, recompute_results=True)
    assert not verification.passed and not verification.recomputed.identical
    index = results["verdicts"].index(verdict)
    assert verification.recomputed.differences == [
        f"verdicts/{index}/value: archived 0.303, recomputed 0.3"]
    result = runner.invoke(app, ["verify", str(copy), "--recompute"])
    assert result.exit_code == 1 and "1 value(s) of results.json did not reproduce" \
        in result.output


def test_recompute_is_refused_on_a_bag_that_is_not_intact(copy):
    (copy / "data" / "campaign" / "data" / "D200.csv").write_text("x")
    result = runner.invoke(app, ["verify", str(copy), "--recompute"])
    assert result.exit_code == 1 and "not recomputed: the bag is not intact" in result.output


def test_compare_results_tolerance_and_software_notes():
    archived = {"a": 1.0, "b": [1, "x"], "provenance": {"certkit_version": "0.1.0",
                                                         "inputs": [{"sha256": "ab"}]}}
    same = json.loads(json.dumps(archived))
    assert compare_results(archived, same, 0.0) == ([], [])
    drift = {**same, "a": 1.0 + 5e-10}
    assert compare_results(archived, drift, 1e-9) == ([], [])
    assert compare_results(archived, drift, 1e-10)[0] == \
        [f"a: archived 1.0, recomputed {1.0 + 5e-10!r}"]
    other = json.loads(json.dumps(archived))
    other["provenance"]["certkit_version"] = "0.2.0"
    other["provenance"]["inputs"][0]["sha256"] = "cd"
    other["b"].append(2)
    differences, software = compare_results(archived, other, 1e-9)
    assert differences == ["b/2: archived '(absent)', recomputed 2",
                           "provenance/inputs/0/sha256: archived 'ab', recomputed 'cd'"]
    assert software == ["provenance/certkit_version: archived '0.1.0', recomputed '0.2.0'"]


def test_the_bag_is_readable_as_the_umask_allows_not_private_to_its_writer(bag):
    mask = os.umask(0)
    os.umask(mask)
    assert bag.stat().st_mode & 0o777 == 0o777 & ~mask
    for path in bag.rglob("*"):
        expected = (0o777 if path.is_dir() else 0o666) & ~mask
        assert path.stat().st_mode & 0o777 == expected, path


# ------------------------------------------------------------------ review findings
def test_file_names_are_printed_as_they_are_not_as_markup(copy):
    (copy / "data" / "[bold]y.csv").write_text("x")
    (copy / "data" / "x[").mkdir()
    (copy / "data" / "x[" / "].csv").write_text("x")
    result = runner.invoke(app, ["verify", str(copy)])
    assert result.exit_code == 1, result.output
    assert "added: data/[bold]y.csv (" in result.output
    assert "added: data/x[/].csv (" in result.output


def test_a_tag_manifest_cannot_vouch_for_a_payload_file(copy):
    # the outcome changed, and the new hash appended to the tag manifest, not the manifest
    path = copy / "data" / "results" / "results.json"
    path.write_text(path.read_text().replace("COMPLIANCE NOT SHOWN", "COMPLIANCE SHOWN"))
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    tags = copy / "tagmanifest-sha256.txt"
    tags.write_text(tags.read_text() + f"{digest}  data/results/results.json\n")
    changes = {(c.kind, c.path) for c in check_bag(copy)}
    assert ("modified", "data/results/results.json") in changes
    assert ("damaged", "tagmanifest-sha256.txt") in changes
    assert runner.invoke(app, ["verify", str(copy)]).exit_code == 1


def test_a_path_listed_twice_in_a_manifest_is_damage(copy):
    manifest = copy / "manifest-sha256.txt"
    first = manifest.read_text().splitlines()[0]
    manifest.write_text(manifest.read_text() + "0" * 64 + first[64:] + "\n")
    damaged = [c for c in check_bag(copy) if c.kind == "damaged"]
    assert len(damaged) == 1 and "is listed twice" in damaged[0].detail


def test_a_removed_bagit_txt_is_a_removed_file_not_a_foreign_folder(copy):
    (copy / "bagit.txt").unlink()
    result = runner.invoke(app, ["verify", str(copy)])
    assert result.exit_code == 1 and "removed: bagit.txt" in result.output


def test_a_fifo_in_place_of_a_tag_file_does_not_hang_verify(copy):
    (copy / "bag-info.txt").unlink()
    os.mkfifo(copy / "bag-info.txt")
    completed = subprocess.run([sys.executable, "-m", "certkit.cli", "verify", str(copy)],
                               capture_output=True, text=True, timeout=60)
    assert completed.returncode == 1
    assert "modified: bag-info.txt (is no longer a regular file)" in completed.stdout


@pytest.mark.parametrize("shadow", ["SEED-2024/./data/results/results.json",
                                    "SEED-2024/data/results/RESULTS.json",
                                    "SEED-2024//data/results/results.json"])
def test_a_zip_cannot_hide_a_second_copy_of_a_file(bag, tmp_path, shadow):
    archive = tmp_path / "shadow.zip"
    with zipfile.ZipFile(archive, "w") as handle:
        for name, content in _tree(bag).items():
            handle.writestr(f"SEED-2024/{name}", content)
        handle.writestr(shadow, b"{}")
    result = runner.invoke(app, ["verify", str(archive)])
    assert result.exit_code == 2 and "refused to extract" in result.output


def test_a_damaged_zip_is_bad_input_not_a_crash(bag, tmp_path):
    archive = tmp_path / "bag.zip"
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as handle:
        for name, content in _tree(bag).items():
            handle.writestr(f"SEED-2024/{name}", content)
    data = bytearray(archive.read_bytes())
    start = data.index(b"PK\x03\x04", 1000)          # the deflated body of a later member
    data[start + 200:start + 240] = bytes(40)
    archive.write_bytes(bytes(data))
    result = runner.invoke(app, ["verify", str(archive)])
    assert result.exit_code in (1, 2), result.output
    assert "internal error" not in result.output


def test_a_bag_another_tool_made_verifies_but_is_not_a_certkit_archive(tmp_path):
    folder = tmp_path / "other"
    (folder / "photos").mkdir(parents=True)
    (folder / "photos" / "rig.txt").write_text("the rig\n")
    bagit.make_bag(str(folder), checksums=["sha256"])
    assert runner.invoke(app, ["verify", str(folder)]).exit_code == 0   # intact
    result = runner.invoke(app, ["verify", str(folder), "--recompute"])
    assert result.exit_code == 2 and "not a certkit archive" in result.output
    result = runner.invoke(app, ["catalog", "add", str(folder), "--catalog",
                                 str(tmp_path / "c.sqlite")])
    assert result.exit_code == 2 and "not a certkit archive" in result.output


@pytest.mark.slow   # several reports or archives in real processes: CI runs it
def test_an_input_behind_a_link_is_archived_where_the_spec_names_it(seed_copy, tmp_path):
    data = seed_copy.parent / "data"
    (seed_copy.parent / "raw").mkdir()
    (data / "D200.csv").rename(seed_copy.parent / "raw" / "D200-2024-01-10.csv")
    (data / "D200.csv").symlink_to("../raw/D200-2024-01-10.csv")
    target = tmp_path / "bag"
    archive_campaign(seed_copy, target, model=False)
    assert (target / "data" / "campaign" / "data" / "D200.csv").read_bytes() == \
        (SEED.parent / "data" / "D200.csv").read_bytes()
    assert not (target / "data" / "campaign" / "raw").exists()
    result = runner.invoke(app, ["verify", str(target), "--recompute"])
    assert result.exit_code == 0 and "reproduced byte for byte" in result.output, result.output


@pytest.mark.parametrize("intruder", ["empty folder", "folder", "file"])
def test_a_target_that_appears_while_archiving_is_left_alone(small_campaign, tmp_path,
                                                            monkeypatch, intruder):
    import certkit.archive.campaign_bag as archive_module

    target = tmp_path / "bag"
    original = archive_module.write_bag

    def write_and_intrude(folder, info):
        digest = original(folder, info)
        if intruder == "file":
            target.write_text("someone else's")
        else:
            target.mkdir()
            if intruder == "folder":
                (target / "theirs.txt").write_text("someone else's")
        return digest

    monkeypatch.setattr(archive_module, "write_bag", write_and_intrude)
    result = runner.invoke(app, ["archive", str(small_campaign), "-o", str(target),
                                 "--no-model"])
    assert result.exit_code == 2
    assert "appeared while the archive was being written" in result.output
    if intruder == "file":
        assert target.read_text() == "someone else's"
    else:
        assert [p.name for p in target.iterdir()] == ([] if intruder == "empty folder"
                                                      else ["theirs.txt"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bag", "small"]   # no staging left


def test_a_zip_cannot_carry_a_date_before_1980(seed_copy, tmp_path):
    text = seed_copy.read_text()
    seed_copy.write_text(text.replace("  date: 2024-01-15\n", "  date: 1979-12-31\n", 1)
                         .replace("test_dates: [2024-01-10]", "test_dates: [1979-12-30]")
                         .replace("{revision: A, date: 2024-01-15", "{revision: A, date: "
                                                                    "1979-12-31"))
    result = runner.invoke(app, ["archive", str(seed_copy), "-o", str(tmp_path / "old.zip"),
                                 "--no-model"])
    assert result.exit_code == 2, result.output
    assert "a zip cannot carry a date before 1980 (document.date 1979-12-31)" in result.output
    assert not (tmp_path / "old.zip").exists()


@pytest.mark.slow
def test_a_full_archive_with_the_drop_model_reproduces_from_its_inputs(tmp_path, full_report):
    # the default archive: calibration, identification and gap diagnosis included; its
    # report is the one `certkit report` makes in another process, byte for byte
    target = tmp_path / "full"
    archive_campaign(SEED, target)
    assert _tree(target / "data" / "results") == _tree(full_report)
    results = json.loads((target / "data" / "results" / "results.json").read_text())
    assert results["model"]["calibration"]["gear_units"]
    assert read_info(target)["Drop-Model"] == ["run (report appendices A to C)"]
    verification = verify_archive(target, recompute_results=True)
    assert verification.intact and verification.recomputed.identical, \
        verification.recomputed.differences[:5]


def _rehash(copy: Path) -> None:
    """Rewrite a bag's manifests after its payload was changed (a careful forger)."""
    info = read_info(copy)
    for name in ("bagit.txt", "bag-info.txt", "manifest-sha256.txt", "tagmanifest-sha256.txt"):
        (copy / name).unlink()
    write_bag(copy, [(label, value) for label, values in info.items() if label !=
                     "Payload-Oxum" for value in values])


def test_a_bag_changed_and_re_hashed_is_caught_by_its_recorded_hash(bag, copy):
    recorded = hashlib.sha256((bag / "tagmanifest-sha256.txt").read_bytes()).hexdigest()
    result = runner.invoke(app, ["verify", str(bag), "--expect-hash", recorded.upper()])
    assert result.exit_code == 0 and f"bag hash (SHA-256 of tagmanifest-sha256.txt): " \
        f"{recorded}" in result.output
    path = copy / "data" / "results" / "results.json"
    path.write_text(path.read_text().replace("COMPLIANCE NOT SHOWN", "COMPLIANT"))
    _rehash(copy)
    assert check_bag(copy) == []                      # intact by its own manifests
    result = runner.invoke(app, ["verify", str(copy), "--expect-hash", recorded])
    assert result.exit_code == 1
    assert f"NOT THE BAG EXPECTED: its hash is not {recorded}" in result.output


def test_a_tag_manifest_that_leaves_out_the_manifest_is_damage(copy):
    tags = copy / "tagmanifest-sha256.txt"
    tags.write_text("".join(line + "\n" for line in tags.read_text().splitlines()
                            if not line.endswith("manifest-sha256.txt")))
    assert [(c.kind, c.path) for c in check_bag(copy)] == [("damaged",
                                                            "tagmanifest-sha256.txt")]
