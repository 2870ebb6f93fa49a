"""Messages of the fitting code that reach a command-line user name the options to type
(``--weighting modulus``, ``--fmin/--fmax``, ``--noise 1%``), not Python keywords; the Python
API keeps its own words."""

from pathlib import Path

import impedax as ix
from impedax.cli import main
from impedax.cli.common import command_line_words, option_words
from impedax.errors import DataError

REAL = Path(__file__).resolve().parent / "fixtures" / "real"


def test_python_keywords_of_messages_become_options():
    assert command_line_words("the fit is dominated by them; consider weighting='modulus'").endswith("consider --weighting modulus")
    assert command_line_words("a measurement artifact; leave them out (fmin/fmax) or check the file") == "a measurement artifact; leave them out (--fmin/--fmax) or check the file"
    error = DataError("5 frequencies are too few ...: give the noise level, e.g. --noise 1% (noise=0.01), or data with a sigma column")
    assert "e.g. --noise 1%, or data" in option_words("diagnose", error)
    assert "use --weighting unit" in option_words("fit", DataError("zero weight at 1 Hz; drop the point or use weighting='unit'"))
    # a command without --weighting keeps Python's words
    assert "weighting='unit'" in option_words("kk", DataError("use weighting='unit'"))


def test_the_fit_report_names_the_options(capsys):
    path = REAL / "exampleDataPowersuite.txt"
    assert main(["fit", str(path), "--model", "R0 + R1 || CPE1"]) == 0
    out = capsys.readouterr().out
    assert "leave them out (--fmin/--fmax)" in out and "(fmin/fmax)" not in out
    # the Python API's warning keeps its keywords
    assert any("(fmin/fmax)" in w for w in ix.fit("R0 + R1 || CPE1", ix.load(path)).warnings)
