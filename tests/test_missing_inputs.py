"""An optional input the spec leaves out is never a silent zero: a value that needs it is
NOT SHOWN with the key to declare, or computed with the assumption printed beside it, and no
data-quality error rests on an assumed input."""

from __future__ import annotations

import shutil

import pytest

from certkit import assess, load_campaign

from .conftest import REPO

SECOND = REPO / "campaigns" / "lsa-main-gear-rig"


@pytest.fixture
def second_without(tmp_path):
    """The second example (imperial, 2 kHz, one gear) with lines of its spec removed."""
    def make(*keys: str):
        folder = tmp_path / "lsa"
        shutil.copytree(SECOND, folder)
        spec = folder / "campaign.yaml"
        lines = spec.read_text(encoding="utf-8").splitlines(keepends=True)
        kept = [line for line in lines if not any(line.strip().startswith(f"{k}:") for k in keys)]
        assert len(kept) == len(lines) - len(keys)
        spec.write_text("".join(kept), encoding="utf-8")
        return load_campaign(spec)
    return make


def test_without_the_unsprung_mass_the_energy_at_maximum_travel_is_not_shown(second_without):
    # with m2 = 0 the force that decelerates the wheel would count as absorbed work: E_d
    # would exceed W_drop·(h + d) by about (m2/m_drop)·h/(h + d) = 2.0-2.8 % on this rig
    # (7.98 kg of 215.5 kg), which the energy balance reads as bad data
    assessment = assess(second_without("unsprung_mass"))
    for run in assessment.runs:
        gear = run.gears[0]
        assert gear.get("E_d") is None and gear.get("W_implied") is None
        assert "gear_units[main-right].strut.unsprung_mass" in gear.values["E_d"].note
        assert "needs E_d" in gear.values["W_implied"].note
        # E_s is still computed, and says with what
        for key in ("E_s", "eta_s"):
            assert "m2 = 0 assumed" in gear.values[key].note, key
    checks = {(f.check, f.severity) for f in assessment.findings}
    assert ("energy-balance-not-checked", "warning") in checks
    assert not any(f.severity == "error" for f in assessment.findings)


def test_the_unmodified_second_example_checks_its_energy_balance(second_without):
    assessment = assess(second_without())
    assert all(run.gears[0].get("E_d") is not None for run in assessment.runs)
    assert not any(f.check == "energy-balance-not-checked" for f in assessment.findings)
    assert not any(f.severity == "error" for f in assessment.findings)


def test_an_assumed_inclination_is_printed_beside_every_value_it_enters(second_without):
    # the second example declares no strut inclination: θ = 0 is assumed (a vertical
    # strut), and every value computed with cos θ, directly or through d, says so
    assessment = assess(second_without())
    gear = assessment.runs[2].gears[0]
    for key in ("d", "E_s", "eta_s", "E_d", "E_avail", "W_implied", "W_e"):
        assert "θ = 0 assumed" in (gear.values[key].note or ""), key
        assert "θ" in gear.values[key].inputs, key
    # and no value that does not use θ
    for key in ("F_peak", "d_t", "E_t", "eta_t", "W_drop"):
        assert "θ = 0 assumed" not in (gear.values[key].note or ""), key


def test_the_tyre_plausibility_range_says_where_its_upper_end_comes_from(tmp_path):
    from certkit.errors import CertkitInputError

    folder = tmp_path / "lsa"
    shutil.copytree(SECOND, folder)
    data = folder / "data" / "D06.csv"
    text = data.read_text(encoding="utf-8").splitlines()
    header = text[0].split(",")
    column = header.index("tyre_in")
    rows = [line.split(",") for line in text[1:]]
    rows[400][column] = "7.2"   # beyond half the 14.2 in wheel diameter
    data.write_text("\n".join([text[0]] + [",".join(r) for r in rows]) + "\n", encoding="utf-8")
    with pytest.raises(CertkitInputError) as raised:
        load_campaign(folder / "campaign.yaml")
    message = str(raised.value)
    # 7.2 in less the column's 0.006 in offset, against [-0.1969, 7.100] in: 14.2 in / 2,
    # as the spec declares no tyre.diameter
    assert "value 7.194 in" in message
    assert "[-0.1969, 7.100] in (upper end: half the wheel diameter)" in message
