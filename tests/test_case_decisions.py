"""Reading a battery case again (benchmarks/case_decisions.py and the case helpers of
benchmarks/blind_independent.py): the case a name gives is the battery's own, and the
campaign written for it is the one the battery ran."""

import json
import re
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))

from certkit import load_campaign  # noqa: E402

EXAMPLE = "campaigns/seed-amphibian/campaign.yaml"
RECORD = "campaigns/seed-amphibian/blind-check/blind-check.json"


def test_a_case_is_named_by_its_plan_seed_ratio_and_forms_as_the_battery_makes_it(
        monkeypatch, capsys):
    import blind_independent as independent
    from blindcheck.sizing import BEYOND_GAIN

    whole = independent.battery(independent.plans_of("development"))
    by_id = {c.id: c for c in whole}
    for text, forms, ratio, seed, measure, part in (
            ("S5:14402:2.0:gain-skew", ("gain-skew",), 2.0, 14402, "load", "S5"),
            ("S1:7507:none:none", (), None, 7507, "load", "S1"),
            ("D:31:5.0:crosstalk:beyond-gain", ("crosstalk",), 5.0, 31, BEYOND_GAIN, "D")):
        case = independent.case_named(text)
        assert (case.forms, case.ratio, case.seed, case.measure, case.plan.name) == \
            (forms, ratio, seed, measure, part)
        assert by_id[case.id].plan is case.plan      # the battery's own case
    pair = next(c for c in whole if len(c.forms) == 2 and c.plan.name == "S2")
    assert independent.case_named(f"S2:{pair.seed}:{pair.ratio}:{'+'.join(pair.forms)}") == pair
    # a seed of another plan, a ratio the plan does not run, an unknown plan: refused
    for text, words in (("D:7507:none:none", "plan D has no such case (its effect seeds 31, 32; "
                                             "its no-effect seeds 500-519"),
                        ("S1:7101:3.0:blow-off", "plan S1 has no such case"),
                        ("S9:1:2.0:blow-off", "no plan 'S9'"),
                        ("S1:x:2.0:blow-off", "SEED a whole number"),
                        ("S1:7101:2.0", "expected PLAN:SEED:RATIO:FORMS[:beyond-gain]")):
        with pytest.raises(ValueError, match=re.escape(words)):
            independent.case_named(text)
    # the reading script refuses a sealed case without the record of its run
    import case_decisions

    sealed = next(c for c in independent.battery(independent.plans_of("sealed"))
                  if c.forms == ("blow-off",))
    monkeypatch.setattr(sys, "argv", ["case_decisions.py", EXAMPLE, "-g", "left-main",
                                      f"{sealed.plan.name}:{sealed.seed}:{sealed.ratio}:blow-off"])
    with pytest.raises(SystemExit) as refused:
        case_decisions.main()
    assert refused.value.code == 2
    assert "a sealed case is read only after its one run" in capsys.readouterr().err


@pytest.mark.slow
def test_a_case_read_again_is_the_case_the_battery_ran(monkeypatch, capsys):
    """benchmarks/case_decisions.py (through :func:`blind_independent.noisy_case`) writes a
    case as the battery wrote it: on the development record's S1 blow-off valve at 5 ×
    (seed 7101: drawn shapes, nuisances and scatter), run by the battery with this
    diagnosis code and template, the nominal model's held-out load error is the record's to
    1e-9, and the answer printed is the record's (one diagnosis, the script's own)."""
    import blind_independent as independent
    import case_decisions

    from certkit.gap.code import code_fingerprint
    from certkit.gap.selection import diagnose, pooled
    from certkit.spec.blind_record import template_fingerprint

    record = json.loads((BENCHMARKS.parent / RECORD).read_text(encoding="utf-8"))
    assert record["run_by"]["code"] == code_fingerprint()
    assert record["template"]["sha256"] == template_fingerprint(load_campaign(EXAMPLE))
    kept = next(o for o in record["cases"] if o["id"] == "case-45d8eb4355")
    assert (kept["part"], kept["forms"], kept["ratio"], kept["seed"]) == \
        ("S1", ["blow-off"], 5.0, 7101)
    case = independent.case_named("S1:7101:5.0:blow-off")
    assert case.id == kept["id"] and case.plan.drawn

    found = []

    def kept_diagnosis(campaign, gear_id):
        found.append(diagnose(campaign, gear_id))
        return found[-1]

    monkeypatch.setattr(case_decisions, "diagnose", kept_diagnosis)
    monkeypatch.setattr(sys, "argv", ["case_decisions.py", EXAMPLE, "-g", "left-main",
                                      "S1:7101:5.0:blow-off"])
    assert case_decisions.main() == 0
    before = {(r, c): v for (label, r, c), v in found[0].held_out_rmse.items()
              if label == "nominal"}
    assert pooled(before)["load"] == pytest.approx(kept["before"], rel=1e-9)
    assert list(found[0].answer) == kept["named"]
    out = capsys.readouterr().out
    assert f"S1:7101:5.0:blow-off (case-45d8eb4355): named {' + '.join(kept['named'])};" in out
    assert "step 1: rebound orifice" in out and ": named (cut " in out
