"""`impedax gap --ep Q` (and ``gap_analysis(ep="Q")``): Q is the circuit language's alias of CPE
(``R0 + Q1`` parses as a CPE), yet gap refused it ("invalid choice: 'Q'"). Now it names the CPE
branch, and an unknown branch's refusal names the alias. SYNTHETIC pad of
tests/test_gap_single_contact.py; the remainder model's choice is stood in for, so that nothing is
fitted (the fits and the sampling take seconds)."""

import sys
from pathlib import Path

import pytest

import impedax as ix
from cli_run import run

sys.path.insert(0, str(Path(__file__).parent))
from test_gap_single_contact import _pad_trials  # noqa: E402

CPE_REMAINDER = "R_EP || CPE_EP || C_gap"  # Sirin's EDL model with a CPE, as docs/models.md writes it


@pytest.fixture
def reached(monkeypatch):
    """What `gap_analysis` asks of `sirin.remainder_circuit`: the branch and the model it gets."""
    import impedax.models.gap as gap
    from impedax.models.sirin import remainder_circuit

    seen = {}

    def stand_in(ep):
        seen.update(ep=ep, circuit=str(remainder_circuit(ep)))
        raise ix.DataError("stand-in: the remainder model was chosen")

    monkeypatch.setattr(gap, "remainder_circuit", stand_in)
    return seen


def test_cli_ep_q_is_the_cpe_branch(tmp_path, capsys, reached):
    pad = str(tmp_path / "pad.nc")
    ix.save(_pad_trials(7), pad)
    code, _, err = run(["gap", pad, "--area", "4e-4", "--no-area-check", "--v0", "200", "--pooled", "--quiet", "--ep", "Q"], capsys)
    assert code == 2 and "stand-in: the remainder model was chosen" in err, err
    assert reached == {"ep": "CPE", "circuit": CPE_REMAINDER}


def test_python_ep_q_is_the_cpe_branch(reached):
    from impedax.models.gap import gap_analysis

    with pytest.raises(ix.DataError, match="stand-in"):
        gap_analysis(_pad_trials(7), area=4e-4, v0=200.0, method="pooled", ep="q", progress=False, check_area=False)
    assert reached == {"ep": "CPE", "circuit": CPE_REMAINDER}


def test_an_unknown_branch_is_refused_with_the_alias_named(tmp_path, capsys):
    from impedax.models.gap import gap_analysis

    pad = str(tmp_path / "pad.nc")
    ix.save(_pad_trials(7), pad)
    code, _, err = run(["gap", pad, "--area", "4e-4", "--ep", "RC"], capsys)
    assert code == 2 and "invalid choice: 'RC'" in err and "Q for CPE" in err and "Traceback" not in err, err
    with pytest.raises(ix.ParameterError, match="unknown ep 'RC'") as refused:
        gap_analysis(_pad_trials(7), area=4e-4, ep="RC")
    assert "Q for CPE" in str(refused.value)
