"""What a reviewer checks besides the numbers (issue 15): the test article, the set-up and
procedure, every transducer's calibration at the test dates, and 14 CFR 23.725(c), which
certkit cannot assess and says so."""

import re

from certkit import assess, load_campaign
from certkit.evidence.provenance import provenance
from certkit.evidence.render import render_html
from certkit.evidence.view import build_view
from certkit.results import NOT_SHOWN

from .test_verdicts import edit

# the analytic campaign's single drop R1 has no date of its own: the document's test date
# 2025-02-27 stands for it
INSTRUMENTATION = "instrumentation:\n  sampling_rate: 1000 Hz\n"
CHANNELS = """instrumentation:
  sampling_rate: 1000 Hz
  channels:
    - {name: Fz, measures: load, calibration_date: 2025-01-10, calibration_due: 2026-01-10,
       calibration_reference: CAL-1}
    - {name: stroke, measures: stroke, calibration_date: 2025-03-01}
    - {name: tyre, measures: tyre, calibration_date: 2024-01-10, calibration_due: 2025-01-10}
    - {name: acc, measures: acceleration}
"""


def _findings(spec):
    return [f for f in assess(load_campaign(spec)).findings
            if f.check == "instrument-calibration"]


def test_a_channel_without_valid_calibration_at_the_test_date_is_a_finding(timeseries_campaign):
    edit(timeseries_campaign, INSTRUMENTATION, CHANNELS)
    found = {(f.severity, f.message.split(":")[0]): f.message
             for f in _findings(timeseries_campaign)}
    # Fz: calibrated 2025-01-10, due 2026-01-10, the test 2025-02-27: valid, no finding
    assert not any("'Fz'" in key[1] for key in found)
    assert "calibrated on 2025-03-01, after the test date 2025-02-27" in \
        found[("error", "channel 'stroke'")]
    assert "calibration due 2025-01-10, before the test date 2025-02-27" in \
        found[("error", "channel 'tyre'")]
    assert "no calibration date stated" in found[("warning", "channel 'acc'")]
    # stroke has no due date: its validity rests on its date alone (an info beside its error)
    assert ("info", "channel 'stroke'") in found
    # an expired or later calibration stops a compliance statement
    reasons = assess(load_campaign(timeseries_campaign)).outcome_reasons()
    assert any("2 data-quality error(s)" in reason for reason in reasons), reasons


def test_a_run_date_decides_over_the_document_dates(timeseries_campaign):
    edit(timeseries_campaign, INSTRUMENTATION, CHANNELS)
    edit(timeseries_campaign, "    lift: {method: reduced_mass",
         "    date: 2025-03-02\n    lift: {method: reduced_mass")
    messages = [f.message for f in _findings(timeseries_campaign) if f.severity == "error"]
    # stroke calibrated 2025-03-01 is now valid for the drop R1 on 2025-03-02; tyre is not
    assert messages == ["channel 'tyre': calibration due 2025-01-10, before drop R1 on "
                        "2025-03-02: its calibration had expired"]


def test_no_channels_listed_cannot_show_calibration(timeseries_campaign):
    (warning,) = _findings(timeseries_campaign)
    assert warning.severity == "warning" and "lists no transducer" in warning.message


def test_synthetic_histories_need_no_calibration(seed_copy):
    # the example's channels state no calibration, but its histories are synthetic
    assert _findings(seed_copy) == []


def test_23_725c_is_not_shown_and_quotes_what_the_setup_states(timeseries_campaign):
    def verdict():
        (found,) = [v for v in assess(load_campaign(timeseries_campaign)).verdicts
                    if v.criterion == "CFR23.725c-attitude-and-drag"]
        return found

    assert verdict().verdict == NOT_SHOWN
    assert "states neither (setup.attitude, setup.drag_loads)" in verdict().reason
    edit(timeseries_campaign, "\nruns:\n", "\nsetup:\n  attitude: level, 0 deg pitch\n"
                                         "  drag_loads: wheel spun up to 60 kt\nruns:\n")
    assert verdict().verdict == NOT_SHOWN
    assert "attitude: level, 0 deg pitch; drag loads: wheel spun up to 60 kt" in verdict().reason


def _html(spec) -> str:
    assessment = assess(load_campaign(spec))
    return render_html(build_view(assessment, provenance(assessment.campaign.inputs)))


def _row(html: str, label: str) -> str:
    found = re.search(rf"<th scope=\"row\">{re.escape(label)}</th><td>(.*?)</td>", html)
    assert found, label
    return found.group(1)


def test_report_shows_article_setup_and_conduct_and_says_what_is_not_stated(timeseries_campaign):
    html = _html(timeseries_campaign)
    for label in ("Test article serial number", "Conformity record", "Tyre ply rating",
                  "Gas charged at (temperature)", "Drop rig (drawing or photograph)",
                  "Drop-height tolerance", "Test plan", "Witness"):
        assert _row(html, label) == "not stated"
    edit(timeseries_campaign, "    design_stroke: 120 mm\n",
         "    design_stroke: 120 mm\n    article: {serial_number: SN-0042, "
         "conformity_record: 8100-1 no. 17, oil_volume: 0.41 L, gas_temperature: 18 degC}\n")
    edit(timeseries_campaign, "\nruns:\n", "\nsetup: {height_tolerance: 2 mm, "
                                         "witness: J. Doe (DER)}\nruns:\n")
    edit(timeseries_campaign, "    lift: {method: reduced_mass",
         "    date: 2025-02-27\n    time: '14:05'\n    ambient_temperature: 21 degC\n"
         "    lift: {method: reduced_mass")
    edit(timeseries_campaign, "inspection: {failure: false}",
         "inspection: {before: no damage, failure: false}")
    html = _html(timeseries_campaign)
    assert _row(html, "Test article serial number") == "SN-0042"
    assert _row(html, "Conformity record") == "8100-1 no. 17"
    assert _row(html, "Oil volume as serviced") == "0.41 L"
    assert _row(html, "Gas charged at (temperature)") == "18 degC"
    assert _row(html, "Drop-height tolerance") == "2 mm"
    assert _row(html, "Witness") == "J. Doe (DER)"
    assert _row(html, "Tyre part number") == "not stated"
    assert "<td>2025-02-27 14:05</td><td>21 degC</td>" in html
    assert "<strong>Inspection before the drop:</strong> no damage." in html


def test_every_sign_off_block_is_there_and_no_signature_is_filled(timeseries_campaign):
    html = _html(timeseries_campaign)
    table = html[html.index("<h2>Signatories</h2>"):html.index("</table>",
                                                              html.index("<h2>Signatories</h2>"))]
    roles = re.findall(r"<tr><td>(\w+)</td><td>([^<]*)</td>", table)
    # the analytic campaign names only who prepared it
    assert [role for role, _ in roles] == ["prepared", "checked", "approved", "witnessed"]
    assert [name for _, name in roles][1:] == ["not stated"] * 3
    assert table.count('<td class="signature"></td>') == 4


def test_contents_conclusions_and_references(timeseries_campaign):
    html = _html(timeseries_campaign)
    contents = re.findall(r'<li><a href="#([a-z-]+)">(\d+)\. ', html)
    # every numbered section of the body in order, each anchor present, each heading where
    # it points; this report was made without the drop model: no appendix, one line
    assert [int(n) for _, n in contents] == list(range(1, 14))
    for anchor, n in contents:
        assert re.search(rf'<(section|nav) id="{anchor}"[^>]*>\s*<h2>{n}\. ', html), anchor
    assert "Appendix" not in html
    assert html.count("--no-model") == 1
    conclusions = html[html.index('<section id="conclusions">'):
                       html.index('<section id="references">')]
    # the analytic drop passes 23.725(a) and the 23.725(c) row is never shown
    assert "14 CFR 23.725(a), Limit drop made from at least the required free drop height: " \
           "PASS (R1)" in conclusions
    assert "14 CFR 23.725(c), Gear attitude and drag loads in the drops represent the " \
           "landing conditions (campaign): NOT SHOWN" in conclusions
    assert "Test plan; Witness" in conclusions and "checked sign-off" in conclusions
    edit(timeseries_campaign, INSTRUMENTATION, CHANNELS)
    html = _html(timeseries_campaign)
    conclusions = html[html.index('<section id="conclusions">'):
                       html.index('<section id="references">')]
    assert "calibration of channel acc; checked sign-off" in conclusions
    references = html[html.index('<section id="references">'):]
    assert "Amdt 23-62" in references and "edition stated by the applicant" in references


def test_a_drop_time_is_hh_mm_and_an_unquoted_one_is_refused_with_the_fix(timeseries_campaign):
    from typer.testing import CliRunner

    from certkit.cli import app

    for typed, expected in (('"25:70"', 'expected a time of day as HH:MM (00:00 to 23:59), '
                                        'got "25:70"'),
                            # YAML 1.1 reads 14:05 unquoted as 14·60 + 5 = 845
                            ("14:05", 'YAML read an unquoted time as the number 845: write it '
                                      'as "14:05"')):
        text = timeseries_campaign.read_text(encoding="utf-8")
        lift = "    lift: {method: reduced_mass"
        timeseries_campaign.write_text(text.replace(lift, f"    time: {typed}\n{lift}", 1),
                                       encoding="utf-8")
        result = CliRunner().invoke(app, ["validate", str(timeseries_campaign)])
        assert result.exit_code == 2 and expected in result.output, result.output
        assert "runs[0].time" in result.output and "Traceback" not in result.output
        timeseries_campaign.write_text(text, encoding="utf-8")
