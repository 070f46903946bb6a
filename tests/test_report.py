"""The evidence files: content, determinism, safety and all-or-nothing writing."""

import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pikepdf
import pytest

from certkit import assess, load_campaign, render_report
from certkit.evidence import report as report_module

from .conftest import SEED, report_html


@pytest.fixture(scope="module")
def seed_outputs(tmp_path_factory):
    out = tmp_path_factory.mktemp("seed") / "out"
    render_report(assess(load_campaign(SEED)), out)
    return out


def test_report_writes_the_three_outputs_and_tables(seed_outputs):
    for name in ("report.html", "report.pdf", "results.json", "tables/verdicts.csv",
                 "tables/findings.csv", "tables/values.csv", "tables/comparisons.csv"):
        assert (seed_outputs / name).stat().st_size > 0, name


def test_results_json_gives_every_value_a_unit_and_a_source(seed_outputs):
    results = json.loads((seed_outputs / "results.json").read_text(encoding="utf-8"))
    values = results["design"] + [v for s in results["requirement_sets"] for v in s["values"]]
    for run in results["runs"]:
        values += run["values"] + [v for g in run["gears"] for v in g["values"]]
    assert len(values) > 100
    for value in values:
        assert value["unit"] and value["source"], value
        assert value["value"] is not None or value["note"], value
    h_req = next(v for v in results["requirement_sets"][1]["values"] if v["key"] == "h_req")
    assert h_req["unit"] == "m" and h_req["value"] == pytest.approx(0.2913572, abs=1e-7)
    assert results["provenance"]["inputs"][0]["sha256"] == hashlib.sha256(
        SEED.read_bytes()).hexdigest()


def test_pdf_is_pdf_a_3b_with_the_spec_and_results_attached(seed_outputs):
    with pikepdf.open(seed_outputs / "report.pdf") as pdf:
        with pdf.open_metadata() as meta:
            assert meta.pdfa_status == "3B"
        attached = {name: spec.get_file().read_bytes()
                    for name, spec in pdf.attachments.items()}
    assert attached["inputs/campaign.yaml"] == SEED.read_bytes()
    assert attached["results.json"] == (seed_outputs / "results.json").read_bytes()


def test_pdf_embeds_only_the_bundled_fonts(seed_outputs):
    with pikepdf.open(seed_outputs / "report.pdf") as pdf:
        fonts = set()
        for page in pdf.pages:
            for font in page.Resources.get("/Font", {}).values():
                fonts.add(str(font.BaseFont).split("+")[-1])
                descendant = font.get("/DescendantFonts")
                descriptor = descendant[0].FontDescriptor if descendant else font.FontDescriptor
                assert "/FontFile2" in descriptor or "/FontFile3" in descriptor
    assert fonts and all(name.startswith("DejaVu") for name in fonts), fonts


def test_html_is_self_contained(seed_outputs):
    html = (seed_outputs / "report.html").read_text(encoding="utf-8")
    # no stylesheet, script, image or font is fetched from anywhere
    assert not re.search(r"<(link|script|img)\b", html)
    assert not re.search(r"""(src|href)\s*=\s*["'](?!#)""", html)
    # url(#id) references an element of the page itself (an SVG clip path); nothing else
    assert not re.search(r"url\((?!#)", html)
    assert "url(#" not in html.split("<svg")[0]     # the CSS has none at all


def test_report_states_the_impact_load_factor_definition(seed_outputs):
    html = (seed_outputs / "report.html").read_text(encoding="utf-8")
    # (831.92 + 813.38)/650 = 2.53123, (1222.05 + 1282.90)/650 = 3.85377, (1568.42 + 1555.09)/650 = 4.80540
    assert "reproduced, to the precision stated, by ΣF_peak(main units)/(m_drop·g)" in html
    assert "2.53 → 2.531, 3.85 → 3.854, 4.8 → 4.805" in html
    assert "Values to be confirmed against the licensed standard" in html


def test_campaign_title_with_markup_is_rendered_as_text(seed_copy, tmp_path):
    text = seed_copy.read_text(encoding="utf-8").replace(
        "title: Full-airplane drop test", "title: <script>alert(1)</script> Full-airplane drop test")
    seed_copy.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    render_report(assess(load_campaign(seed_copy)), out)
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "<script>" not in html
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in html


def test_renderer_refuses_to_fetch_outside_its_folders():
    html = ('<html><body><img src="file:///etc/passwd"></body></html>')
    with pytest.raises(BaseException, match="refused"):
        report_module.render_pdf(html, [], __import__("datetime").date(2024, 1, 1))
    html = '<html><body><img src="http://example.com/x.png"></body></html>'
    with pytest.raises(BaseException, match="refused"):
        report_module.render_pdf(html, [], __import__("datetime").date(2024, 1, 1))


def test_failed_render_leaves_nothing_and_keeps_the_previous_report(tmp_path, monkeypatch):
    assessment = assess(load_campaign(SEED))
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.pdf").write_bytes(b"previous")

    def broken(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(report_module, "render_pdf", broken)
    with pytest.raises(RuntimeError):
        render_report(assessment, out)
    assert (out / "report.pdf").read_bytes() == b"previous"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    with pytest.raises(RuntimeError):
        render_report(assessment, tmp_path / "new")
    assert not (tmp_path / "new").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def _render_in_fresh_process(spec: Path, out: Path, *options: str, cache: Path | None = None
                             ) -> str:
    """The report in a fresh process (``cache``: its evidence cache); returns its stderr."""
    environment = dict(os.environ, CERTKIT_CACHE=str(cache)) if cache else None
    return subprocess.run([sys.executable, "-m", "certkit.cli", "report", str(spec), "-o",
                           str(out), *options], check=True, capture_output=True, timeout=300,
                          env=environment, text=True).stderr


def _digests(folder: Path) -> dict[str, str]:
    return {p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.mark.slow
def test_same_inputs_give_identical_bytes_across_processes(timeseries_campaign, tmp_path):
    # the time-series campaign exercises figures, fonts and attachments
    _render_in_fresh_process(timeseries_campaign, tmp_path / "a")
    _render_in_fresh_process(timeseries_campaign, tmp_path / "b")
    first, second = _digests(tmp_path / "a"), _digests(tmp_path / "b")
    assert set(first) >= {"report.html", "report.pdf", "results.json", "tables/values.csv"}
    assert first == second
    html = (tmp_path / "a" / "report.html").read_text(encoding="utf-8")
    assert html.count("<svg") == 3  # load, travel, load-travel figures


@pytest.mark.slow
def test_model_section_is_reproducible_and_says_the_data_are_synthetic(full_report, tmp_path):
    # the example campaign: calibration, identification and gap diagnosis of both gears
    # (the same bytes made afresh in two processes at other thread counts: the fast
    # test_full_report_seed.py); a report that takes the evidence from the cache gives the
    # same bytes as the one that made it (its cache copied: the report and its cache are
    # shared by the test session's workers, and a report process may write to its cache)
    cache = tmp_path / "cache"
    shutil.copytree(full_report.parent / "cache", cache)
    stderr = _render_in_fresh_process(SEED, tmp_path / "c", cache=cache)
    assert "taken from the cache" in stderr and "calibrating" not in stderr
    assert _digests(full_report) == _digests(tmp_path / "c")
    html = (full_report / "report.html").read_text(encoding="utf-8")
    assert "Appendix A. Drop-model calibration" in html
    assert "are SYNTHETIC" in html and "9.7364" in html and "11.3473" in html
    assert html.count('class="model-gear"') == 2
    assert "Appendix B. Identification" in html
    assert html.count('class="identification-gear"') == 2
    assert "0.48805" in html and "0.38246" in html  # the seed's Wiener RMSEs quoted
    results = json.loads((full_report / "results.json").read_text(encoding="utf-8"))
    gears = results["model"]["calibration"]["gear_units"]
    assert [g["gear_unit"] for g in gears] == ["left-main", "right-main"]
    for gear in gears:  # calibration improves every run's stroke fit
        strokes = [e for e in gear["rmse"] if e["channel"] == "stroke"]
        assert all(e["calibrated"] < e["nominal"] for e in strokes)
    rows = (full_report / "tables" / "model.csv").read_text(encoding="utf-8").splitlines()
    assert len(rows) == 1 + 2 * 3 * 3  # header + 2 gears x 3 runs (D300 held out) x 3 channels
    identification = results["model"]["identification"]["gear_units"]
    assert [g["held_out"] for g in identification] == [["D300"], ["D300"]]
    # the gap appendix: both gears diagnosed on the default split, after the body and the
    # other appendices
    assert "Appendix C. Sim-to-real gap" in html and html.count('class="gap-gear"') == 2
    assert html.index("10. Methods") < html.index("12. Provenance") \
        < html.index("Appendix B. Identification") < html.index("Appendix C. Sim-to-real gap")
    # the example names its blind-check record, made from this very spec
    assert "has not been recorded for this campaign" not in html
    assert "it matches this campaign&#39;s spec" in html   # (escaped apostrophe)
    # whether the record was made by this diagnosis code is said, either way
    from certkit.gap.code import code_fingerprint
    from certkit.spec.blind_record import read_blind_check
    record = read_blind_check(SEED.parent / "blind-check" / "blind-check.json")
    if record.template.code == code_fingerprint():
        assert "with this certkit&#39;s diagnosis code." in html
    else:
        assert "other diagnosis code than this certkit" in html
    assert "Blind check: what the diagnosis gets right against effect size" in html
    gaps = results["model"]["gap"]["gear_units"]
    assert [(g["gear_unit"], g["training"], g["held_out"]) for g in gaps] == [
        ("left-main", ["D200", "D250"], ["D300"]), ("right-main", ["D200", "D250"], ["D300"])]
    # synthesise.py's truth has a rebound orifice, seal friction and tyre hysteresis
    for gap in gaps:
        assert gap["answer"] and set(gap["answer"]) <= {"rebound orifice", "seal friction",
                                                        "tyre hysteresis"}
    cells = (full_report / "tables" / "gap.csv").read_text(encoding="utf-8").splitlines()
    assert len(cells) == 1 + 2 * 3 * 3 * 6  # header + gears x runs x channels x phases
    shrink = (full_report / "tables" / "gap_shrink.csv").read_text(encoding="utf-8")
    # held-out D300 of each gear: 3 channels x (whole record + 6 phases)
    assert len(shrink.splitlines()) == 1 + 2 * 3 * 7


def test_figures_do_not_depend_on_the_users_matplotlib_settings(timeseries_campaign, tmp_path):
    import matplotlib

    assessment = assess(load_campaign(timeseries_campaign))
    plain = report_html(assessment)
    with matplotlib.rc_context({"lines.linewidth": 7.0, "font.size": 20.0,
                                "axes.facecolor": "yellow"}):   # as a matplotlibrc would
        styled = report_html(assessment)
    assert "<svg" in plain and plain == styled
