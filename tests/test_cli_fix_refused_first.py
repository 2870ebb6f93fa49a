"""A --fix value outside its element's bounds is refused before anything is read or fitted: one
error line on stderr, nothing before it (sample printed "fitting the least-squares start …" and
compare a note on the data's sigma before the refusal; walkthrough 2026-12-05)."""

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main


@pytest.fixture(scope="module")
def spectrum_file(tmp_path_factory):
    # SYNTHETIC R0 + R1 || C1 (numpy formula) with a sigma column, which compare notes when unused
    f = np.geomspace(1e5, 0.1, 30)
    z = 50.0 + 1000.0 / (1.0 + 2j * np.pi * f * 1000.0 * 1e-5)
    path = tmp_path_factory.mktemp("fix") / "s.nc"
    ix.save(ix.make_spectrum(f, z, sigma=0.01 * np.abs(z)), path)
    return str(path)


@pytest.mark.parametrize("args", [
    ["sample", "--model", "R0 + R1 || C1", "--fix", "R0=-5", "--steps", "100"],
    ["compare", "--model", "R0 + R1 || C1", "--model", "R0 + C1", "--fix", "R0=-5"],
    ["fit", "--model", "R0 + R1 || C1", "--fix", "R0=-5"],
])
def test_a_fixed_value_outside_its_bounds_is_the_only_line(spectrum_file, capsys, args):
    command, rest = args[0], args[1:]
    assert main([command, spectrum_file, *rest]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.strip().splitlines() == [err.strip()] and "--fix: R0=-5 is outside its bounds (0, inf)" in err


# A paper model's name (meyer) printed its stderr line, "meyer is C_s + C_i + … fitted from the
# thesis's eq 3.13 values …", before the refusal of a missing file, a NaN row, a value outside
# its element's bounds or a misspelt --prior name (walkthrough 2026-12-07): the refusal is the only
# line, as for a circuit typed out.
MEYER_BAD = [
    (["fit", "{missing}", "--model", "meyer"], "file not found"),
    (["sample", "{missing}", "--model", "meyer", "--steps", "100"], "file not found"),
    (["diagnose", "{missing}", "--model", "meyer"], "file not found"),
    (["refine", "{missing}", "--model", "meyer"], "file not found"),
    (["fit", "{nan}", "--model", "meyer"], "line 3: column 'zreal' is 'nan'"),
    (["fit", "{good}", "--model", "meyer", "--select", "cycle=3"], "--select cycle=3"),
    (["fit", "{good}", "--model", "meyer", "--init", "R_sc=-5"], "--init: R_sc=-5 is outside its bounds (0, inf) [Ω]"),
    (["fit", "{good}", "--model", "meyer", "--fix", "R_sc=-5"], "--fix: R_sc=-5 is outside its bounds (0, inf) [Ω]"),
    (["sample", "{good}", "--model", "meyer", "--init", "R_sc=-5", "--steps", "100"], "--init: R_sc=-5 is outside its bounds (0, inf) [Ω]"),
    (["compare", "{good}", "--model", "meyer", "--model", "meyer-cpe", "--init", "R_sc=-5"], "--init: R_sc=-5 is outside its bounds (0, inf) [Ω]"),
    (["diagnose", "{good}", "--model", "meyer", "--fix", "R_sc=-5"], "--fix: R_sc=-5 is outside its bounds (0, inf) [Ω]"),
    (["refine", "{good}", "--model", "meyer", "--fix", "R_sc=0"], "--fix: R_sc=0 is on its lower bound"),
    (["sample", "{good}", "--model", "meyer", "--prior", "R_scc=lognormal:100k,1", "--steps", "100"], "--prior: unknown parameter 'R_scc' for model 'C_s + C_i + R_sc || C_sc + R_f'; did you mean R_sc?"),
    (["sample", "{good}", "--model", "meyer", "--prior", "R_sc=lognormal:100k,1", "--fix", "R_sc=130k", "--steps", "100"], "--prior R_sc: R_sc is fixed (--fix R_sc=130000)"),
    (["sample", "{good}", "--model", "meyer", "--prior", "R_sc=uniform:-10,1k", "--steps", "100"], "--prior R_sc=uniform:-10,1000 reaches outside the parameter's bounds (0, inf)"),
    (["sample", "{good}", "--model", "meyer-cpe", "--prior", "CPE_sc.alpha=uniform:0.5,2", "--steps", "100"], "--prior CPE_sc.alpha=uniform:0.5,2 reaches outside the parameter's bounds (0, 1]"),
]


@pytest.fixture(scope="module")
def meyer_files(tmp_path_factory):
    # SYNTHETIC Meyer spectrum (numpy formula: C_s + C_i + R_sc || C_sc + R_f at eq 3.13's values), and a copy with a NaN on line 3
    folder = tmp_path_factory.mktemp("meyer")
    f = np.geomspace(1e6, 10.0, 25)
    s = 2j * np.pi * f
    z = 1 / (s * 140e-12) + 1 / (s * 1.7e-9) + 130e3 / (1 + s * 130e3 * 2.2e-9) + 500.0
    good, nan = folder / "meyer.csv", folder / "nan.csv"
    rows = [[repr(float(a)), repr(float(b.real)), repr(float(b.imag))] for a, b in zip(f, z)]
    good.write_text("freq,zreal,zimag\n" + "".join(",".join(r) + "\n" for r in rows))
    rows[1][1] = "nan"
    nan.write_text("freq,zreal,zimag\n" + "".join(",".join(r) + "\n" for r in rows))
    return {"good": str(good), "nan": str(nan), "missing": str(folder / "missing.csv")}


@pytest.mark.parametrize("args, expected", MEYER_BAD, ids=[f"{a[0]}-{e[:24]}" for a, e in MEYER_BAD])
def test_a_paper_model_says_nothing_before_a_refusal(meyer_files, capsys, args, expected):
    assert main([a.format(**meyer_files) for a in args]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.strip().splitlines() == [err.strip()], err
    assert err.startswith(f"impedax {args[0]}: error: ") and expected in err
