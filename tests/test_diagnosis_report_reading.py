"""The reports of ``impedax diagnose`` and ``impedax refine`` read by a researcher who does not
know impedax's internals (docs/diagnosis.md): counts in their number, each fact said once, the
verdict's count of bands agreeing with the bands listed, and a plain word when nothing is
missing. Each test states the words a reading of the REAL example files or of a SYNTHETIC
spectrum found wanting."""

from __future__ import annotations

import io
import re
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import impedax as ix
from impedax.fitting.diagnosis.diagnosis import _verdict

REAL = Path(__file__).parent / "fixtures" / "real"


def _band(data_problem: bool) -> SimpleNamespace:
    return SimpleNamespace(data_problem=data_problem)


def _suggestion(delta_aic: float) -> SimpleNamespace:
    return SimpleNamespace(significant=True, effect="series_inductance", added="L_lead", delta_aic=delta_aic, beyond_band=())


def test_the_verdict_counts_its_bands_in_their_number():
    """REAL ZPlot from R0 + R1 || C1: "structured in 1 band(s)" for the one band listed."""
    verdict, reason = _verdict([_suggestion(-83.1)], [_band(False)], 8.71)
    assert verdict == "missing_effect"
    assert reason == "the residuals are 8.71× the noise and structured in 1 band; adding series_inductance (L_lead) lowers AIC by 83.1."
    _, reason = _verdict([_suggestion(-20.0)], [_band(False), _band(False)], 3.0)
    assert "structured in 2 bands;" in reason and "(s)" not in reason


def test_the_verdict_names_the_bands_of_the_data_s_problem_it_does_not_count():
    """REAL BioLogic from R0 + R1 || C1 lists two bands under "where the model fails", one tagged
    "[data problem: …]", beside "structured in 1 band(s)": the verdict says what the other is."""
    _, reason = _verdict([_suggestion(-54.1)], [_band(False), _band(True)], 1.72)
    assert reason.startswith("the residuals are 1.72× the noise and structured in 1 band (and 1 where the KK test flags the data); adding"), reason
    # adequate beyond the catalog says the same
    cand = SimpleNamespace(significant=False, effect="diffusion", added="W_d", delta_aic=-3.0, beyond_band=())
    verdict, reason = _verdict([cand], [_band(False), _band(False), _band(True)], 4.0)
    assert verdict == "adequate" and "structured in 2 bands (and 1 where the KK test flags the data), but no effect" in reason, reason


@pytest.fixture(scope="module")
def biologic():
    """REAL BioLogic (impedance.py's example file, MIT) diagnosed from R0 + R1 || C1: 4 lone
    points inside the band flagged by the KK test and kept in every fit."""
    return ix.diagnose(ix.load(REAL / "exampleDataBioLogic.mpt"), "R0 + R1 || C1", progress=False)


@pytest.mark.slow
def test_the_report_counts_in_the_number_of_its_counts(biologic):
    """"the KK test flags 4 point(s) inside the band", "structured in 1 band(s)" on REAL BioLogic."""
    report = biologic.report()
    assert "(s)" not in report, [line for line in report.splitlines() if "(s)" in line]
    assert "the KK test flags 4 points inside the band (5.34 Hz, 56.2 Hz, 123 Hz, 270 Hz): kept in every fit" in report
    (verdict,) = [line for line in report.splitlines() if line.startswith("verdict:")]
    assert "structured in 1 band (and 1 where the KK test flags the data);" in verdict, verdict
    assert sum(line.startswith("  ") and "[data problem" in line for line in report.splitlines()) == 1


@pytest.mark.slow
def test_the_data_line_names_the_flagged_points_once(biologic):
    """The data line said "NOT Kramers–Kronig consistent in 5.34 Hz, 56.2 Hz, 123 Hz, 270 Hz (…);
    the KK test flags 4 points inside the band (5.34 Hz, 56.2 Hz, 123 Hz, 270 Hz): …"."""
    (data_line,) = [line for line in biologic.report().splitlines() if line.startswith("data:")]
    listed = "5.34 Hz, 56.2 Hz, 123 Hz, 270 Hz"
    assert data_line.count(listed) == 1, data_line
    assert data_line.startswith("data: the data are NOT Kramers–Kronig consistent (KK rms_rel 2.81 %); "
                                f"the KK test flags 4 points inside the band ({listed}): kept in every fit"), data_line


@pytest.fixture(scope="module")
def nothing_missing():
    """SYNTHETIC R0 + R1 ∥ C1 (10 Ω, 100 Ω, 1 µF; numpy, 31 points 100 kHz–1 Hz, 0.5 % noise on
    each component, seed 7), diagnosed and refined from the model that made it."""
    f = np.logspace(5, 0, 31)
    z = 10 + 100 / (1 + 2j * np.pi * f * 100 * 1e-6)
    rng = np.random.default_rng(7)
    z = z * (1 + 0.005 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)))
    data = ix.make_spectrum(f, z)
    return ix.diagnose(data, "R0 + R1 || C1", progress=False), ix.refine(data, "R0 + R1 || C1", progress=False)


@pytest.mark.slow
def test_nothing_missing_is_said_plainly(nothing_missing):
    """The verdict said "ADEQUATE — the residuals are 0.854× the noise with no structured band,
    and no effect lowers AIC by more than 10 while explaining at least 25% of the noise variance",
    and refine printed a one-row table under it: no line said that nothing is missing."""
    d, r = nothing_missing
    assert d.verdict == r.verdict == "adequate" and len(r.steps) == 1
    lines = d.report(fit_command="impedax fit syn.csv").splitlines()
    (plain,) = [line for line in lines if line.startswith("nothing is missing:")]
    ratio = f"{d.noise_ratio:.3g}"
    assert plain == (f"nothing is missing: R0 + R1 || C1 follows the data to their noise (the residuals are {ratio}× the noise), "
                     "and no effect of the catalog improves it significantly; its parameters with their errors: impedax fit syn.csv --model 'R0 + R1 || C1'"), plain
    assert lines.index(plain) > next(i for i, line in enumerate(lines) if line.startswith("verdict:"))
    lines = r.report().splitlines()
    (plain,) = [line for line in lines if line.startswith("nothing is missing:")]
    assert plain == f"nothing is missing: R0 + R1 || C1 follows the data to their noise as given (the residuals are {ratio}× the noise); refine added no effect.", plain


def test_the_verdict_writes_a_percentage_as_the_report_writes_every_other():
    """"at least 25% of the noise variance" beside "rms_rel 0.583 %" on the lines above it."""
    cand = SimpleNamespace(significant=False, effect="series_inductance", added="L_lead", delta_aic=0.6, beyond_band=())
    verdict, reason = _verdict([cand], [], 0.854)
    assert verdict == "adequate" and "at least 25 % of the noise variance" in reason, reason
    assert not re.search(r"\d%", reason), reason


@pytest.mark.slow
def test_every_percentage_of_the_report_has_its_space(biologic):
    """REAL BioLogic: "rms_rel 2.8 %" and "(relative error > 100%, …, or > 0.99 with a relative
    error above 10%)" in one report."""
    report = biologic.report()
    assert "relative error > 100 %" in report and "a relative error above 10 %" in report
    assert not re.findall(r".{30}\d%.{10}", report), re.findall(r".{30}\d%.{10}", report)


@pytest.mark.slow
def test_the_rule_of_an_undetermined_parameter_is_said_once(biologic):
    """REAL BioLogic: three "not proposed" lines each ended "(relative error > 100 %, |correlation|
    > 0.999, or > 0.99 with a relative error above 10 %)"; the JSON's warnings keep it."""
    report = biologic.report()
    rule = "relative error > 100 %, |correlation| > 0.999, or > 0.99 with a relative error above 10 %"
    lines = [line for line in report.splitlines() if line.startswith("  not proposed:")]
    assert len(lines) == 3 and all("the data do not determine" in line for line in lines), lines
    assert report.count(rule) == 1 and rule in lines[0], lines
    assert lines[1].endswith("the data do not determine R1, Ws_d.R"), lines[1]
    assert all(rule in c["warning"] for c in biologic.summary()["candidates"] if (c["warning"] or "").startswith("the data do not determine"))


@pytest.mark.slow
def test_refine_says_once_that_it_does_not_start_again_on_the_kk_band():
    """REAL Gamry from R0 + R1 || C1: the verdict ends "(refine does not: the trim leaves out 72 %
    of the points, more than the 25 % it leaves out on its own)", and a note under it said the
    same again ("refine does not start again there: it would leave out 72 % of the points, …").
    The JSON's notes keep it."""
    r = ix.refine(ix.load(REAL / "exampleDataGamry.DTA"), "R0 + R1 || C1", progress=False)
    lines = r.report().splitlines()
    (verdict,) = [line for line in lines if line.startswith("verdict:")]
    assert "(refine does not: the trim leaves out 72 % of the points, more than the 25 % it leaves out on its own)" in verdict, verdict
    assert not any("refine does not start again there" in line for line in lines), lines
    assert sum("refine does not start again there" in n for n in r.summary()["notes"]) == 1


def test_an_implausible_value_is_written_in_its_unit_s_prefix():
    """AutoEIS's REAL battery cycle 0 from R0 + R1 || C1: "not proposed: (R0 + R1 || C1) ||
    C_stray (rms_rel 26 %): C_stray = 4.97e-05 F is not fixture capacitance (pF–nF, at most 1e-09 F)",
    where every other value of the report reads "49.7 µF"."""
    from impedax.fitting.diagnosis.effects import _diffusion_plausible, _lead_plausible, _stray_plausible

    stray = _stray_plausible({"C_stray": 4.97e-05}, SimpleNamespace(added="C_stray"))
    assert stray.startswith("C_stray = 49.7 µF is not fixture capacitance (pF–nF, at most 1 nF): "), stray
    lead = _lead_plausible({"L_lead": 2.5e-3}, SimpleNamespace(added="L_lead"))
    assert lead.startswith("L_lead = 2.5 mH is not the inductance of leads (about a µH per metre, at most 100 µH): "), lead
    seen = _diffusion_plausible({"Ws_d.tau": 1.1e-6}, SimpleNamespace(added="Ws_d", band=(1.0, 1e5)))
    assert seen.startswith("Ws_d.tau = 1.1 µs: its diffusion region"), seen


REPORT = (
    "verdict: MISSING_EFFECT — the residuals are 8.71× the noise and structured in 1 band; adding series_inductance (L_lead) lowers AIC by 83.1.\n"
    "  1. [series_inductance] series inductance: adding L_lead in series with the whole circuit (leads) (L_lead = 2.99 µH) lowers rms_rel from 1.35 % to 0.511 %.\n"
    "     model R0 + R1 || C1 + L_lead   rms_rel 0.511 %   ΔAIC -83.1   ΔBIC -81.3\n"
    "  to apply 1. from its fitted values (a fit from scratch may stop in another minimum): impedax fit tests/fixtures/real/exampleDataZPlot.z "
    "--model 'R0 + R1 || C1 + L_lead' --init R0=149.231 --init R1=501.568 --init C1=3.0868e-08 --init L_lead=2.98983e-06"
)  # (REAL ZPlot from R0 + R1 || C1, the report's lines of 139, 156 and 253 characters)


def test_a_terminal_gets_the_report_within_its_width_and_the_commands_whole():
    """On a terminal of 100 columns the report's lines (up to 700 characters on the REAL example
    files) broke mid-word; the prose is wrapped at words under its own indentation, and a command
    goes on lines of its own that a shell reads as one (each but the last ending in " \\")."""
    import shlex

    from impedax.cli.diagnose import terminal_text

    text = terminal_text(REPORT, 100)
    lines = text.splitlines()
    assert all(len(line) <= 100 for line in lines), [len(line) for line in lines]
    assert " ".join(text.split()).replace(" \\ ", " ") == " ".join(REPORT.split()), text  # (every word kept, in order)
    assert lines[0].startswith("verdict: MISSING_EFFECT") and lines[1].startswith("    ")  # (a wrapped line hangs under its own)
    assert "     model R0 + R1 || C1 + L_lead   rms_rel 0.511 %   ΔAIC -83.1   ΔBIC -81.3" in lines  # (short lines as they were)
    at = lines.index("  to apply 1. from its fitted values (a fit from scratch may stop in another minimum):")
    command = lines[at + 1:]
    assert all(line.endswith(" \\") for line in command[:-1]) and not command[-1].endswith("\\"), command
    words = shlex.split(" ".join(line.removesuffix(" \\") for line in command))
    assert words == shlex.split(REPORT.splitlines()[-1].partition(": ")[2]), words
    assert terminal_text(REPORT, 1000) == REPORT


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_only_a_terminal_gets_the_report_wrapped(monkeypatch):
    """What `impedax diagnose` and `impedax refine` print goes through `to_terminal`: wrapped on a
    terminal (COLUMNS=100), as it is into a pipe or a file, and never with --json."""
    from impedax.cli.diagnose import to_terminal

    monkeypatch.setenv("COLUMNS", "100")
    for tty, text, wrapped in ((True, True, True), (True, False, False), (False, True, False)):
        out = _Terminal() if tty else io.StringIO()
        monkeypatch.setattr(sys, "stdout", out)
        with to_terminal(text):
            print(REPORT)
        assert (max(map(len, out.getvalue().splitlines())) <= 100) is wrapped, out.getvalue()


def test_a_wrapped_line_keeps_each_number_with_its_unit():
    """REAL BioLogic on a 100-column terminal: "… up to 1.5 % below near 390" and "mHz" on the
    next line."""
    from impedax.cli.diagnose import terminal_text

    for n in range(80, 100):
        line = "x" * n + " near 390 mHz, 2.8 %, 41.9 Ω, 1.72× and 22° below"
        wrapped = terminal_text(line, 100).splitlines()
        assert not any(re.search(r"\d$", each) for each in wrapped), wrapped
        assert " ".join(" ".join(wrapped).split()) == line


@pytest.mark.slow
def test_refine_says_nothing_more_is_missing_after_its_steps():
    """REAL BioLogic from R0 + R1 || C1: refine adds CPE1 and ends ADEQUATE at 1.24× the noise."""
    r = ix.refine(ix.load(REAL / "exampleDataBioLogic.mpt"), "R0 + R1 || C1", progress=False)
    lines = r.report().splitlines()
    assert r.verdict == "adequate" and len(r.steps) == 2, lines
    at = lines.index(f"nothing more is missing: the final model follows the data to their noise (the residuals are {r.steps[-1].noise_ratio:.3g}× the noise).")
    assert lines[at + 1].startswith(f"final fit {r.final_model}: ")


@pytest.mark.slow
def test_the_json_says_when_nothing_is_missing(nothing_missing, biologic):
    """The JSON held the verdict ("adequate"), beyond_catalog and the noise ratio, but not the
    report's "nothing is missing" as a fact of its own."""
    d, r = nothing_missing
    assert d.summary()["nothing_missing"] is True and r.summary()["nothing_missing"] is True
    assert biologic.summary()["nothing_missing"] is False


def test_adequate_within_the_catalog_says_what_to_do_next():
    """REAL Autolab's refine from R0 + R1 || C1 ended "ADEQUATE WITHIN THE CATALOG — the residuals
    are 2.4× the noise and structured in 1 band, but no effect of the catalog explains them with
    determined, plausible parameters: what is left is beyond the catalog (or the model discrepancy
    floor)." and nothing after it said where to go from there."""
    cand = SimpleNamespace(significant=False, effect="diffusion", added="W_d", delta_aic=-3.0, beyond_band=())
    verdict, reason = _verdict([cand], [_band(False)], 2.4)
    assert verdict == "adequate", reason
    assert reason.endswith(": what is left is beyond the catalog (or the model discrepancy floor); to go further, impedax drt FILE reads a circuit off "
                           "the data's DRT, and an effect of your own joins the catalog (docs/diagnosis.md, \"An effect of your own\")."), reason
    _, reason = _verdict([cand], [_band(False)], 2.4, left_out=("constant_phase",))
    assert reason.endswith("diagnose again with them."), reason  # (there the next step is the effects left out)


@pytest.mark.slow
def test_nothing_more_is_missing_names_the_points_it_was_judged_on():
    """REAL Parstat from R0 + R1 || C1: refine starts again on the 25 of 31 points the KK test
    passes and ends ADEQUATE there; "nothing more is missing: … follows the data to their noise"
    read as all 31 points, under a note that diagnose says DATA_INVALID on them."""
    r = ix.refine(ix.load(REAL / "exampleDataParstat.txt"), "R0 + R1 || C1", progress=False)
    assert r.verdict == "adequate" and len(r.masked_points) == 6, r.report()
    (plain,) = [line for line in r.report().splitlines() if line.startswith("nothing more is missing:")]
    assert plain == (f"nothing more is missing: the final model follows the data to their noise on the 25 points kept "
                     f"(the residuals are {r.steps[-1].noise_ratio:.3g}× the noise)."), plain


@pytest.mark.slow
def test_a_best_candidate_that_raises_aic_is_not_called_best(nothing_missing):
    """The adequate line read "no effect improves the fit significantly (best: series_inductance,
    ΔAIC +0.6, …)": an effect that makes AIC worse called best. Its sign decides the words."""
    import dataclasses

    d, _ = nothing_missing
    top = d.candidates[0]
    for delta, words in ((0.6, f"(none lowers AIC; the closest, {top.effect}, raises it by 0.6, rms_rel "),
                         (-4.2, f"(best: {top.effect}, ΔAIC -4.2, rms_rel ")):
        changed = dataclasses.replace(d, candidates=(dataclasses.replace(top, delta_aic=delta),) + tuple(d.candidates[1:]))
        (line,) = [line for line in changed.report().splitlines() if line.startswith("no effect improves the fit significantly")]
        assert line.startswith("no effect improves the fit significantly " + words), line
