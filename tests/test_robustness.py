"""Every CLI command on hostile input: exit code 2, one clear message, no traceback, no output.

The tables are built to grow: add a command to FILE_COMMANDS (reads a spectrum file),
MODEL_COMMANDS (takes a circuit) or OUTPUT_COMMANDS (writes a file) and it meets every bad
input of the matching table. Placeholders: ``{input}`` the bad file, ``{good}`` a valid
spectrum file, ``{model}`` the bad model, ``{output}`` the bad output path, ``{tmp}`` the
test's folder. docs/robustness.md lists these rows and what impedax does with each.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
import os
import re
import shutil
import unicodedata

import matplotlib
import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

# --- commands -------------------------------------------------------------------------------

FILE_COMMANDS = [  # (id, argv template with {input})
    ("inspect", ["inspect", "{input}"]),
    ("inspect-json", ["inspect", "{input}", "--json", "--out", "{tmp}/converted.nc"]),
    ("fit", ["fit", "{input}", "--model", "R1 + C1", "--json", "--out", "{tmp}/fit.nc"]),
    ("compare", ["compare", "{input}", "--model", "R1", "--model", "R1 + C1"]),
    ("sample", ["sample", "{input}", "--model", "R1 + C1", "--steps", "20", "--json", "--out", "{tmp}/post.nc"]),
    ("gap", ["gap", "{input}", "{tmp}/good.csv", "{tmp}/good.csv", "--area", "130e-6", "--json", "--out", "{tmp}/gap.nc"]),
    ("diagnose", ["diagnose", "{input}", "--model", "R1 + C1", "--json"]),
    ("refine", ["refine", "{input}", "--model", "R1 + C1", "--max-steps", "1", "--json"]),
    ("kk", ["kk", "{input}", "--json"]),
    ("kk-zhit", ["kk", "{input}", "--method", "zhit", "--json"]),
    ("drt", ["drt", "{input}", "--json"]),
    ("gap-skin", ["gap", "{tmp}/good.csv", "{input}", "{tmp}/good.csv", "--area", "130e-6", "--json"]),
    ("remaining", ["remaining", "{input}", "{tmp}/good.csv", "{tmp}/good.csv", "--out", "{tmp}/remaining.nc"]),
    ("stack", ["stack", "{tmp}/good.csv", "{input}", "--out", "{tmp}/stacked.nc"]),
]
MODEL_COMMANDS = [  # (id, argv template with {model})
    ("info", ["info", "{model}"]),
    ("simulate", ["simulate", "{model}", "--out", "{tmp}/out.csv"]),
    ("draw", ["draw", "{model}", "-o", "{tmp}/out.svg"]),
    ("fit", ["fit", "{tmp}/good.csv", "--model", "{model}"]),
    ("compare", ["compare", "{tmp}/good.csv", "--model", "R1", "--model", "{model}"]),
    ("sample", ["sample", "{tmp}/good.csv", "--model", "{model}", "--steps", "20"]),
    ("diagnose", ["diagnose", "{tmp}/good.csv", "--model", "{model}"]),
    ("refine", ["refine", "{tmp}/good.csv", "--model", "{model}"]),
]
PARAM_COMMANDS = [  # (id, argv template with {model} and {param})
    ("simulate", ["simulate", "{model}", "--param", "{param}", "--out", "{tmp}/out.csv"]),
    ("draw", ["draw", "{model}", "--param", "{param}", "-o", "{tmp}/out.png"]),
    ("fit-fix", ["fit", "{tmp}/good.csv", "--model", "{model}", "--fix", "{param}"]),
    ("fit-init", ["fit", "{tmp}/good.csv", "--model", "{model}", "--init", "{param}"]),
]
PRIOR_COMMANDS = [  # (id, argv template with {prior})
    ("sample", ["sample", "{tmp}/good.csv", "--model", "R1 + CPE1", "--steps", "20", "--prior", "{prior}", "--out", "{tmp}/post.nc"]),
]
OUTPUT_COMMANDS = [  # (id, argv template with {output}, output extension)
    ("simulate", ["simulate", "R1 + C1", "--out", "{output}"], ".csv"),
    ("simulate-plot", ["simulate", "R1 + C1", "--plot", "{output}"], ".png"),
    ("draw", ["draw", "R1 + C1", "-o", "{output}"], ".svg"),
    ("inspect", ["inspect", "{good}", "--out", "{output}"], ".nc"),
    ("fit-out", ["fit", "{good}", "--model", "R1 + C1", "--out", "{output}"], ".nc"),
    ("fit-plot", ["fit", "{good}", "--model", "R1 + C1", "--plot", "{output}"], ".png"),
    ("compare-plot", ["compare", "{good}", "--model", "R1", "--model", "R1 + C1", "--plot", "{output}"], ".png"),
    ("compare-out", ["compare", "{good}", "--model", "R1", "--model", "R1 + C1", "--out", "{output}"], ".csv"),
    ("sample-out", ["sample", "{good}", "--model", "R1 + C1", "--steps", "20", "--out", "{output}"], ".nc"),
    ("sample-corner", ["sample", "{good}", "--model", "R1 + C1", "--steps", "20", "--corner", "{output}"], ".png"),
    ("sample-plot", ["sample", "{good}", "--model", "R1 + C1", "--steps", "20", "--plot", "{output}"], ".png"),
    ("diagnose-plot", ["diagnose", "{good}", "--model", "R1 + C1", "--plot", "{output}"], ".png"),
    ("refine-plot", ["refine", "{good}", "--model", "R1 + C1", "--plot", "{output}"], ".png"),
    ("stack", ["stack", "{good}", "{good}", "--coords", "1", "2", "--out", "{output}"], ".nc"),
]

# --- bad inputs -----------------------------------------------------------------------------

GOOD_CSV = "frequency_hz,z_real_ohm,z_imag_ohm\n1,100,-50\n10,100,-5\n"
HEADER = "frequency_hz,z_real_ohm,z_imag_ohm\n"

DIRECTORY = b"<a directory>"  # content marker: the path is a directory
BAD_FILES = [  # (id, file name, content or None for a missing file, message fragment)
    ("missing-file", "nope.csv", None, "file not found"),
    ("empty-file", "empty.csv", b"", "file is empty"),
    ("blank-lines-only", "blank.csv", b"\n\n  \n", "file is empty"),
    ("binary-garbage", "garbage.csv", bytes(range(256)) * 8, "binary file"),
    ("binary-with-txt-extension", "garbage.txt", b"\x7fELF\x02\x01\x01\x00" + bytes(500), "binary file"),
    ("wrong-columns", "wrong.csv", b"voltage,current\n1,2\n", "not a recognised spectrum file"),
    ("header-only", "header.csv", HEADER.encode(), "no data rows"),
    ("numbers-without-header", "nohead.csv", b"1,2,3,4\n4,5,6,7\n", "not a header"),  # 3 columns are read as f, Z', Z''
    ("short-row", "short.csv", (HEADER + "1,2,3\n2,2\n").encode(), "2 fields"),
    ("text-in-number-column", "text.csv", (HEADER + "1,2,3\n2,abc,3\n").encode(), "'abc' is not a number"),
    ("nan-value", "nan.csv", (HEADER + "1,2,3\n2,nan,3\n").encode(), "NaN/Inf"),
    ("inf-frequency", "inf.csv", (HEADER + "inf,2,3\n").encode(), "NaN/Inf"),
    ("overflowing-1e400", "overflow.csv", (HEADER + "1,1e400,3\n").encode(), "NaN/Inf"),
    ("zero-frequency-only", "zero.csv", (HEADER + "0,2,3\n").encode(), "no data rows (skipped: line 2: f = 0"),  # DC rows are skipped and reported
    ("negative-frequency", "neg.csv", (HEADER + "1,2,3\n-5,2,3\n").encode(), "frequency must be positive"),
    ("duplicate-frequency", "dup.csv", (HEADER + "1,2,3\n1,2,3\n").encode(), "duplicate frequency 1 Hz"),
    ("netcdf-extension-not-netcdf", "x.nc", b"hello", "not a readable netCDF"),
    ("gamry-without-zcurve", "x.DTA", b"EXPLAIN\r\nTAG\tEISPOT\r\n", "no ZCURVE table"),
    ("gamry-empty-zcurve", "y.DTA", b"EXPLAIN\nZCURVE\tTABLE\n\tPt\tTime\tFreq\tZreal\tZimag\n\t#\ts\tHz\tohm\tohm\n", "no data rows"),
    ("biologic-bad-header-count", "x.mpt", b"EC-Lab ASCII FILE\r\nNb header lines : 400\r\n", "does not fit"),
    ("biologic-nan", "y.mpt", b"EC-Lab ASCII FILE\nNb header lines : 3\nfreq/Hz\tRe(Z)/Ohm\t-Im(Z)/Ohm\n1\tNaN\t3\n", "NaN/Inf"),
    ("zplot-negative-frequency", "x.z", b"ZPLOT2 ASCII\nEnd Comments\n-1, 0, 0, 0, 10, -5, 0, 0, 3\n", "frequency must be positive"),
    ("labone-different-grids", "dev1_imps.csv", b"chunk;timestamp;size;fieldname\n0;1;2;frequency;1;2\n0;1;2;realz;1;1\n0;1;2;imagz;-1;-1\n1;1;2;frequency;1;3\n1;1;2;realz;1;1\n1;1;2;imagz;-1;-1\n", "different frequency grid"),
    ("autolab-duplicate-frequency", "nova.txt", "Frequency (Hz);Z' (Ω);-Z'' (Ω)\n10;1;1\n10;1;1\n".encode(), "duplicate frequency 10 Hz"),
    ("input-is-a-directory", "adir.csv", DIRECTORY, "is a directory"),
    ("utf32-text", "utf32.csv", (HEADER + "1,2,-3\n").encode("utf-32"), "not a recognised spectrum file"),
    ("ebcdic-text", "ebcdic.csv", (HEADER + "1,2,-3\n").encode("cp500"), "not a recognised spectrum file"),
    ("nul-bytes-in-text", "nul.csv", (HEADER + "1,2,-3\n").encode().replace(b"2", b"\x00"), "binary file"),
    ("bare-carriage-return", "cr.txt", b"a\rb\n", "not a recognised spectrum file"),
]
HDF5_WITHOUT_H5PY = ("hdf5-without-h5py", "sweep.h5", b"\x89HDF\r\n\x1a\n" + bytes(100), "pip install h5py")
if importlib.util.find_spec("h5py") is None:
    BAD_FILES.append(HDF5_WITHOUT_H5PY)

BAD_MODELS = [  # (id, model, message fragment)
    ("unknown-element", "X1 + R1", "unknown element symbol 'X'"),
    ("typo-with-hint", "R1 + Csc", "did you mean C_sc?"),
    ("empty-model", "", "empty circuit"),
    ("unbalanced-parenthesis", "(R1 + C1", "is not closed"),
    ("duplicate-name", "R1 + R1", "duplicate element name"),
    ("random-unicode", "R1 + ☃", "unexpected character '☃'"),
    ("control-character", "R1 +\x07C1", "unexpected character"),
    ("too-many-elements", " + ".join(f"R{k}" for k in range(300)), "more than 256 elements"),
    ("deep-nesting", "(" * 500 + "R1" + ")" * 500, "nested deeper than 64"),
    ("very-long-garbage", "R1 + " + "%" * 200_000, "unexpected character '%'"),
    ("syntax-error-at-start", "+ R1", "expected an element or '(', found '+'"),
    ("syntax-error-in-the-middle", "R1 + + C1", "expected an element or '(', found '+'"),
    ("syntax-error-at-the-end", "R1 + C1 +", "found end of input"),
    ("stray-closing-parenthesis", "R1 + C1)", "unbalanced ')'"),
    ("single-bar", "R1 | C1", "a single '|' is not an operator"),
    ("slash-beside-bars", "R0 + R1 || C1/R2", "parallel is written '||': R1 || C1"),  # ('/' alone is read as parallel, with a note)
    ("cdc-unclosed-group", "R(RC", "unclosed group, expected ')'"),  # (CDC that reads is read, with a note)
    ("dash-for-series", "R0 + R1-C1", "series is written '+'"),  # ('R1-C1' alone is read as impedance.py notation)
    ("mixed-notation-p-group", "R0 + p(R1,C1)", "p(a,b) is a || b in impedax's notation, and the two notations cannot be mixed"),
    ("space-inside-element-name", "R0 + Ws 2", "no space inside an element name: Ws2"),
    ("impedance-py-element-name", "R0 + Zarc1", "impedance.py's Zarc is impedax's CC: CC1"),
    ("en-dash-for-series", "R0 \u2013 R1", "a dash '\u2013': series is written '+' (or '-' in impedance.py's notation)"),
    ("whitespace-only", " \t ", "empty circuit"),
    ("lowercase-symbol", "r1 + C1", "symbols are case-sensitive"),
    ("lowercase-impedance-py-name", "R0 + zarc1", "symbols are case-sensitive, and impedance.py's Zarc is impedax's CC: CC1"),
    ("lowercase-in-impedance-py-string", "R0-p(R1,zarc1)", "symbols are case-sensitive: did you mean Zarc1 (impedax's CC1)?"),
    ("cyrillic-capital-es", "R1 + С1", "did you mean the Latin 'C'?"),
    ("cyrillic-capital-er", "Р1 + C1", "U+0420 CYRILLIC CAPITAL LETTER ER"),
    ("cyrillic-small-o-in-label", "R_sо + C1", "did you mean the Latin 'o'?"),
    ("greek-capital-rho", "R1 + Ρ2", "U+03A1 GREEK CAPITAL LETTER RHO"),
    ("fullwidth-letter", "R1 + Ｃ1", "did you mean the Latin 'C'?"),
    ("fullwidth-plus", "R1 ＋ C1", "did you mean '+'?"),
    ("terminal-escape-sequence", "R1 +\x1b[2J C1", "'\\x1b' (U+001B)"),
    ("right-to-left-override", "R1 + \u202eC1", "U+202E RIGHT-TO-LEFT OVERRIDE"),
    ("nul-character", "R1\x00 + C1", "'\\x00' (U+0000)"),
    ("zero-width-space", "R1 +\u200bC1", "U+200B ZERO WIDTH SPACE"),
    ("huge-series-15k-elements", " + ".join(f"R{k}" for k in range(15_000)), "more than 256 elements"),
    ("huge-garbage-after-escape", "R1 + C1 " + "\x1b" * 100_000, "'\\x1b' (U+001B)"),
]

BAD_PARAMS = [  # (id, model, --param value, message fragment)
    ("unknown-parameter", "R1 + C1", "R2=3", "unknown parameter 'R2'"),
    ("not-a-number", "R1 + C1", "R1=abc", "is not a number"),
    ("nan-parameter", "R1 + C1", "R1=nan", "must be finite"),
    ("overflowing-parameter-1e400", "R1 + C1", "R1=1e400", "must be finite"),
    # (read as 0 until 2026-12-08: "R1=0 is on its lower bound", a value not typed)
    ("underflowing-parameter-1e-400", "R1 + C1", "R1=1e-400", "'1e-400' is too small for a float: it reads as 0"),
    ("negative-resistance", "R1 + C1", "R1=-5", "outside its bounds"),
    ("alpha-above-one", "R1 + CPE1", "CPE1.alpha=1.5", "outside its bounds"),
    ("alpha-just-above-one", "R1 + CPE1", "CPE1.alpha=1.0000001", "CPE1.alpha=1.0000001 is outside its bounds (0, 1]"),
    ("zero-resistance", "R1 + C1", "R1=0", "R1=0 is on its lower bound, which its bounds (0, inf)"),
    ("missing-equals", "R1 + C1", "R1", "expected NAME=VALUE"),
]

BAD_PRIORS = [  # (id, --prior value, message fragment)
    ("unknown-parameter", "R2=uniform:1,2", "unknown parameter 'R2'"),
    ("unknown-kind", "R1=beta:1,2", "unknown prior kind 'beta'"),
    ("one-number", "R1=uniform:1", "takes two numbers"),
    ("not-numbers", "R1=normal:a,b", "are not two numbers"),
    ("reversed-bounds", "R1=uniform:5,1", "must be below"),
    ("loguniform-from-zero", "R1=loguniform:0,10", "positive lower end"),
    ("negative-sd", "R1=normal:1,-2", "standard deviation must be positive"),
    ("infinite", "R1=uniform:1,inf", "must be finite"),
    ("outside-bounds", "CPE1.alpha=uniform:0.5,2", "reaches outside"),
    ("missing-equals", "R1", "expected NAME=KIND:ARGS"),
]

BAD_OUTPUTS = [  # (id, output template without extension, message fragment)
    ("missing-directory", "{tmp}/missing/dir/out", "does not exist"),
    ("output-is-a-directory", "{tmp}/adir", "is a directory"),
    ("parent-is-a-file", "{tmp}/good.csv/out", "does not exist"),
]


BAD_OPTIONS = [  # (id, argv template with {good} a valid spectrum file and {tmp}, message fragment); every command
    ("simulate-points-negative", ["simulate", "R1", "--points", "-1"], "--points must be at least 2"),
    ("simulate-points-zero", ["simulate", "R1", "--points", "0"], "--points must be at least 2"),
    ("simulate-points-not-a-number", ["simulate", "R1", "--points", "ten"], "invalid int value: 'ten'"),
    ("simulate-fmin-zero", ["simulate", "R1", "--fmin", "0"], "--fmin must be positive"),
    ("simulate-fmin-above-fmax", ["simulate", "R1", "--fmin", "100", "--fmax", "1"], "--fmax (1 Hz) is below --fmin (100 Hz)"),
    ("simulate-fmin-above-fmax-kilohertz", ["simulate", "R1", "--fmin", "2e4", "--fmax", "1"], "--fmax (1 Hz) is below --fmin (20 kHz)"),
    # (a bound typed as 9999 was written "10 kHz" until 2026-12-06: as typed where the short form is another number)
    ("fit-fmin-above-fmax-as-typed", ["fit", "{good}", "--model", "R1", "--fmin", "9999", "--fmax", "100"], "--fmax (100 Hz) is below --fmin (9999 Hz)"),
    ("simulate-fmin-infinite", ["simulate", "R1", "--fmin", "inf"], "fmin must be finite"),
    ("simulate-fmax-nan", ["simulate", "R1", "--fmax", "nan"], "fmax must be finite"),
    ("info-unknown-flag", ["info", "R1", "--bogus"], "unrecognized arguments: --bogus"),
    ("command-misspelt", ["fitt", "{good}", "--model", "R1"], "invalid choice: 'fitt'; did you mean fit?"),
    ("info-missing-model", ["info"], "the following arguments are required: MODEL"),
    ("fit-fmin-not-a-number", ["fit", "{good}", "--model", "R1", "--fmin", "abc"], "'abc' is not a number"),
    ("fit-fmin-negative", ["fit", "{good}", "--model", "R1", "--fmin", "-1"], "fmin must be positive"),
    ("fit-fmin-nan", ["fit", "{good}", "--model", "R1", "--fmin", "nan"], "fmin must be finite"),
    ("fit-fmin-above-fmax", ["fit", "{good}", "--model", "R1", "--fmin", "100", "--fmax", "1"], "--fmax (1 Hz) is below --fmin (100 Hz)"),
    ("fit-band-outside-the-data", ["fit", "{good}", "--model", "R1", "--fmin", "1e6"], "no frequencies at or above --fmin = 1 MHz (the data span"),
    ("fit-max-steps-negative", ["fit", "{good}", "--model", "R1", "--max-steps", "-1"], "--max-steps must be at least 1"),
    ("fit-misspelt-option", ["fit", "{good}", "--model", "R1", "--maxsteps", "5"], "unrecognized arguments: --maxsteps 5; did you mean --max-steps?"),
    ("fit-unknown-weighting", ["fit", "{good}", "--model", "R1", "--weighting", "bogus"], "invalid choice: 'bogus'"),
    ("fit-everything-fixed", ["fit", "{good}", "--model", "R1", "--fix", "R1=5"], "every parameter is fixed"),
    ("fit-missing-model", ["fit", "{good}"], "the following arguments are required: --model"),
    ("fit-init-not-a-number", ["fit", "{good}", "--model", "R1 + C1", "--init", "C1=abc"], "is not a number"),
    ("compare-one-model", ["compare", "{good}", "--model", "R1"], "compare needs at least two --model options"),
    ("compare-unknown-weighting", ["compare", "{good}", "--model", "R1", "--model", "C1", "--weighting", "x"], "invalid choice: 'x'"),
    ("compare-max-steps-negative", ["compare", "{good}", "--model", "R1", "--model", "C1", "--max-steps", "-1"], "--max-steps must be at least 1"),
    ("compare-fmin-above-fmax", ["compare", "{good}", "--model", "R1", "--model", "C1", "--fmin", "5", "--fmax", "2"], "--fmax (2 Hz) is below --fmin (5 Hz)"),
    ("sample-steps-zero", ["sample", "{good}", "--model", "R1", "--steps", "0"], "--steps must be at least 20"),
    ("sample-steps-not-a-number", ["sample", "{good}", "--model", "R1", "--steps", "many"], "invalid int value: 'many'"),
    ("sample-burn-beyond-steps", ["sample", "{good}", "--model", "R1", "--steps", "20", "--burn", "30"], "burn must be an integer from 0 to steps"),
    ("sample-one-walker", ["sample", "{good}", "--model", "R1", "--steps", "20", "--walkers", "1"], "walkers must be at least 2"),
    ("sample-thin-zero", ["sample", "{good}", "--model", "R1", "--steps", "20", "--thin", "0"], "thin must be at least 1"),
    ("sample-seed-negative", ["sample", "{good}", "--model", "R1", "--steps", "20", "--seed", "-1"], "seed must be at least 0"),
    ("sample-seed-not-a-number", ["sample", "{good}", "--model", "R1", "--steps", "20", "--seed", "abc"], "invalid int value: 'abc'"),
    ("sample-unknown-noise", ["sample", "{good}", "--model", "R1", "--noise", "bogus"], "invalid choice: 'bogus'"),
    ("kk-c-above-one", ["kk", "{good}", "--c", "2"], "--c must be between 0 and 1"),
    ("kk-max-rc-negative", ["kk", "{good}", "--max-rc", "-1"], "--max-rc must be at least 1"),
    ("kk-unknown-method", ["kk", "{good}", "--method", "bogus"], "invalid choice: 'bogus'"),
    ("drt-lambda-negative", ["drt", "{good}", "--lam", "-1"], "lam must be a positive finite number"),
    ("drt-lambda-not-a-number", ["drt", "{good}", "--lam", "abc"], "expected 'auto' or a positive number"),
    ("drt-lambda-a-rule", ["drt", "{good}", "--lam", "gcv"], "expected 'auto' or a positive number; the rule that chooses λ is --lam-method gcv (with --lam auto, the default)"),
    ("drt-unknown-lambda-method", ["drt", "{good}", "--lam-method", "bogus"], "invalid choice: 'bogus'"),
    ("diagnose-unknown-effect", ["diagnose", "{good}", "--model", "R1", "--effects", "bogus"], "unknown effect 'bogus'"),
    ("diagnose-noise-negative", ["diagnose", "{good}", "--model", "R1", "--noise", "-1"], "noise must be positive"),
    ("diagnose-noise-percent-above-100", ["diagnose", "{good}", "--model", "R1", "--noise", "150%"], "a noise level is below 100 % of |Z|"),
    ("diagnose-effects-empty", ["diagnose", "{good}", "--model", "R1", "--effects", ""], "--effects '' names no effect"),
    ("diagnose-effects-empty-item", ["diagnose", "{good}", "--model", "R1", "--effects", "diffusion,,constant_phase"], "--effects 'diffusion,,constant_phase': item 2 of 3 is empty"),
    ("refine-effects-trailing-comma", ["refine", "{good}", "--effects", "diffusion,"], "--effects 'diffusion,': item 2 of 2 is empty"),
    ("fit-plot-pgf", ["fit", "{good}", "--model", "R1", "--plot", "{tmp}/fit.pgf"], "'.pgf' needs a LaTeX install"),
    ("diagnose-max-steps-negative", ["diagnose", "{good}", "--model", "R1", "--max-steps", "-1"], "--max-steps must be at least 1"),
    ("diagnose-fmin-above-fmax", ["diagnose", "{good}", "--model", "R1", "--fmin", "5", "--fmax", "2"], "--fmax (2 Hz) is below --fmin (5 Hz)"),
    ("refine-max-steps-negative", ["refine", "{good}", "--model", "R1", "--max-steps", "-1"], "--max-steps must be at least 1"),
    ("refine-max-effects-negative", ["refine", "{good}", "--model", "R1", "--max-effects", "-1"], "--max-effects must be 0 or more"),
    ("refine-unknown-effect", ["refine", "{good}", "--model", "R1", "--effects", "nope"], "unknown effect 'nope'"),
    ("force-unknown-model", ["force", "bogus"], "invalid choice: 'bogus'"),
    ("force-points-negative", ["force", "meyer", "--points", "-1"], "--points must be at least 2"),
    ("force-fmin-zero", ["force", "meyer", "--fmin", "0"], "--fmin must be positive"),
    ("force-fmin-above-fmax", ["force", "vezzoli", "--fmin", "100", "--fmax", "1"], "--fmax (1 Hz) is below --fmin (100 Hz)"),
    ("force-unknown-parameter", ["force", "meyer", "--param", "bogus=1"], "unknown parameter 'bogus'"),
    ("force-negative-area", ["force", "meyer", "--param", "area=-1"], "must be positive"),
    ("force-parameter-not-a-number", ["force", "vezzoli", "--param", "h_i=abc"], "'abc' is not a number"),
    ("gap-negative-area", ["gap", "{good}", "{good}", "{good}", "--area", "-1"], "--area must be positive"),
    ("gap-area-not-a-number", ["gap", "{good}", "{good}", "{good}", "--area", "big"], "'big' is not a number"),
    ("gap-zero-drive-voltage", ["gap", "{good}", "{good}", "{good}", "--area", "1e-4", "--v0", "0"], "--v0 must be positive"),
    ("gap-too-few-steps", ["gap", "{good}", "{good}", "{good}", "--area", "1e-4", "--steps", "0"], "--steps must be at least 20"),
    ("gap-unknown-branch", ["gap", "{good}", "{good}", "{good}", "--area", "1e-4", "--ep", "RC"], "invalid choice: 'RC'"),
    ("gap-pooled-and-hierarchical", ["gap", "{good}", "{good}", "{good}", "--area", "1e-4", "--pooled", "--method", "hierarchical"], "--pooled and --method hierarchical contradict each other"),
    ("gap-missing-spectrum", ["gap", "{good}", "{good}", "--area", "1e-4"], "give DATA_SKIN and DATA_TS both (the remainder total − skin − touchscreen) or neither"),
    ("draw-missing-output", ["draw", "R1"], "the following arguments are required: -o/--out"),
    ("inspect-unknown-flag", ["inspect", "{good}", "--bogus"], "unrecognized arguments: --bogus"),
    ("demo-unknown-flag", ["demo", "--bogus"], "unrecognized arguments: --bogus"),
    ("stack-coords-count", ["stack", "{good}", "{good}", "--coords", "1", "--out", "{tmp}/s.nc"], "--coords: 1 label for 2 files"),
    ("stack-same-file-twice", ["stack", "{good}", "{good}", "--out", "{tmp}/s.nc"], "is given twice (files 1 and 2 of 2)"),
    ("stack-out-csv", ["stack", "{good}", "{good}", "--coords", "1", "2", "--out", "{tmp}/s.csv"], "a stack of spectra is written as netCDF"),
    ("unknown-command", ["bogus"], "invalid choice: 'bogus'"),
]

ONE_POINT_CSV = HEADER + "10,100,-50\n"
TWO_POINTS_CSV = HEADER + "10,100,-50\n20,100,-25\n"
SIX_POINTS_CSV = HEADER + "".join(f"{10 ** k:g},{100 + 1e3 / (1 + (10 ** k / 30) ** 2):.6g},{-1e3 * (10 ** k / 30) / (1 + (10 ** k / 30) ** 2):.6g}\n" for k in range(6))  # (an RC arc)
HUGE_VALUES_CSV = HEADER + "".join(f"{10 ** (k / 4):g},1e300,-1e300\n" for k in range(20))
# (SYNTHETIC: 12 points of 100 Ω − j·100/f Ω, the one at 10 Hz written as 0,0, as an instrument may write a point it lost)
ZERO_POINT_CSV = HEADER + "".join(f"{10 ** (k / 4):g},{0 if k == 4 else 100},{0 if k == 4 else -100 / 10 ** (k / 4):g}\n" for k in range(12))
UNDATA = [  # (id, file content, argv template with {input}, message fragment): valid files these analyses cannot use
    ("fit-one-point", ONE_POINT_CSV, ["fit", "{input}", "--model", "R1 + C1"], "data.csv: 2 free parameters but only 2 real data values (1 frequency)"),
    ("compare-one-point", ONE_POINT_CSV, ["compare", "{input}", "--model", "R1 + C1", "--model", "R1 + C1 + R2"], "free parameters but only 2 real data values"),
    ("sample-one-point", ONE_POINT_CSV, ["sample", "{input}", "--model", "R1 + C1", "--steps", "20"], "free parameters but only 2 real data values"),
    ("diagnose-one-point", ONE_POINT_CSV, ["diagnose", "{input}", "--model", "R1"], "diagnose needs at least 4 frequencies"),
    ("diagnose-two-points", TWO_POINTS_CSV, ["diagnose", "{input}", "--model", "R1"], "diagnose needs at least 4 frequencies"),
    ("diagnose-six-points-no-noise", SIX_POINTS_CSV, ["diagnose", "{input}", "--model", "R1 + C1"], "6 frequencies are too few to tell the model's misfit from noise"),
    ("refine-one-point", ONE_POINT_CSV, ["refine", "{input}", "--model", "R1"], "refine needs at least 4 frequencies"),
    ("kk-one-point", ONE_POINT_CSV, ["kk", "{input}"], "the KK test needs at least 4 frequencies"),
    ("zhit-two-points", TWO_POINTS_CSV, ["kk", "{input}", "--method", "zhit"], "Z-HIT needs at least 6 frequencies"),
    ("drt-two-points", TWO_POINTS_CSV, ["drt", "{input}"], "the DRT needs at least 5 frequencies"),
    ("fit-huge-values", HUGE_VALUES_CSV, ["fit", "{input}", "--model", "R1 + C1"], "outside the range impedax analyses"),
    ("compare-huge-values", HUGE_VALUES_CSV, ["compare", "{input}", "--model", "R1", "--model", "R1 + C1"], "outside the range impedax analyses"),
    ("sample-huge-values", HUGE_VALUES_CSV, ["sample", "{input}", "--model", "R1 + C1", "--steps", "20"], "outside the range impedax analyses"),
    ("diagnose-huge-values", HUGE_VALUES_CSV, ["diagnose", "{input}", "--model", "R1 + C1"], "outside the range impedax analyses"),
    ("kk-huge-values", HUGE_VALUES_CSV, ["kk", "{input}"], "outside the range impedax analyses"),
    ("drt-huge-values", HUGE_VALUES_CSV, ["drt", "{input}"], "outside the range impedax analyses"),
    # (a point with Z = 0: each says where, as kk does; drt said "at some frequency", sample "somewhere" until 2026-12-08)
    ("kk-zero-point", ZERO_POINT_CSV, ["kk", "{input}"], "data.csv: Z is exactly zero at 10 Hz; the 1/|Z| weighting needs |Z| > 0"),
    ("drt-zero-point", ZERO_POINT_CSV, ["drt", "{input}"], "data.csv: Z is exactly zero at 10 Hz; the relative weighting 1/|Z| needs |Z| > 0"),
    ("sample-zero-point", ZERO_POINT_CSV, ["sample", "{input}", "--model", "R1 + C1", "--steps", "20"], "data.csv: Z is exactly zero at 10 Hz; --noise proportional (σ = sigma_rel·|Z|) needs |Z| > 0: drop those points"),
]


# --- the harness ----------------------------------------------------------------------------


def _fill(template: list[str], **values: str) -> list[str]:
    return [arg.format(**values) if "{" in arg and len(arg) < 200 else arg for arg in template]


def _run(argv: list[str], capsys) -> tuple[int, str, str]:
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's own errors (a bad choice, a missing argument, --help)
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


MAX_MESSAGE = 300  # characters of the error message (the caret line's padding not counted)


def message_length(text: str) -> int:
    """Characters of an error message, not counting the spaces that put a caret under its column."""
    return len(re.sub(r"\n +\^", "\n^", text.strip()))


def _check_failure(code, out, err, fragment, tmp_path, before, *, circuit=False, usage=False):
    """Exit 2; one error message containing ``fragment``, under MAX_MESSAGE characters, with no
    raw control or formatting character; no traceback; the folder unchanged.

    ``circuit``: the message is a circuit error (reason, the source around the column, a caret,
    a hint: four lines). ``usage``: argparse's usage lines come before the message."""
    assert code == 2, (code, err)
    assert fragment in err, err
    assert "Traceback" not in err and "Traceback" not in out
    assert not [ch for ch in err if ch != "\n" and unicodedata.category(ch) in ("Cc", "Cf")], repr(err[:300])
    lines = err.strip().splitlines()
    errors = [i for i, line in enumerate(lines) if "error:" in line]
    assert len(errors) == 1, err  # one message
    first = errors[0]
    message = "\n".join(lines[first:])
    if circuit:
        assert len(lines) - first <= 4, err
    elif not usage:
        assert first <= 1 and len(lines) == first + 1, err  # after at most one notice line
    if "formats tried" not in message:  # (the one exception: the reason the text is no table, its header's names, and a count of the formats tried)
        assert message_length(message) < MAX_MESSAGE, f"{message_length(message)} characters: {err[:400]}"
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing written, no temp files


@pytest.fixture
def workdir(tmp_path):
    (tmp_path / "good.csv").write_text(GOOD_CSV)
    (tmp_path / "adir.csv").mkdir()
    (tmp_path / "adir.svg").mkdir()
    (tmp_path / "adir.png").mkdir()
    (tmp_path / "adir.nc").mkdir()
    return tmp_path


@pytest.mark.parametrize("command", FILE_COMMANDS, ids=[c[0] for c in FILE_COMMANDS])
@pytest.mark.parametrize("case", BAD_FILES, ids=[c[0] for c in BAD_FILES])
def test_bad_input_file(command, case, workdir, capsys):
    _, template = command
    _, name, content, fragment = case
    path = workdir / name
    if content is DIRECTORY:
        path.mkdir(exist_ok=True)
    elif content is not None:
        path.write_bytes(content)
    before = sorted(p.name for p in workdir.iterdir())
    code, out, err = _run(_fill(template, input=str(path), tmp=str(workdir)), capsys)
    _check_failure(code, out, err, fragment, workdir, before)
    assert str(path) in err  # the message names the file


def test_input_path_is_a_directory(workdir, capsys):
    code, out, err = _run(["inspect", str(workdir / "adir.csv")], capsys)
    _check_failure(code, out, err, "is a directory", workdir, sorted(p.name for p in workdir.iterdir()))


@pytest.mark.parametrize("command", MODEL_COMMANDS, ids=[c[0] for c in MODEL_COMMANDS])
@pytest.mark.parametrize("case", BAD_MODELS, ids=[c[0] for c in BAD_MODELS])
def test_bad_model(command, case, workdir, capsys):
    _, template = command
    _, model, fragment = case
    before = sorted(p.name for p in workdir.iterdir())
    argv = [model if a == "{model}" else a.format(tmp=str(workdir)) for a in template]
    code, out, err = _run(argv, capsys)
    _check_failure(code, out, err, fragment, workdir, before, circuit=True)
    assert "at column" in err  # the message names the column


@pytest.mark.parametrize("command", PARAM_COMMANDS, ids=[c[0] for c in PARAM_COMMANDS])
@pytest.mark.parametrize("case", BAD_PARAMS, ids=[c[0] for c in BAD_PARAMS])
def test_bad_parameter(command, case, workdir, capsys):
    _, template = command
    _, model, param, fragment = case
    before = sorted(p.name for p in workdir.iterdir())
    argv = [model if a == "{model}" else param if a == "{param}" else a.format(tmp=str(workdir)) for a in template]
    code, out, err = _run(argv, capsys)
    _check_failure(code, out, err, fragment, workdir, before)


@pytest.mark.parametrize("command", PRIOR_COMMANDS, ids=[c[0] for c in PRIOR_COMMANDS])
@pytest.mark.parametrize("case", BAD_PRIORS, ids=[c[0] for c in BAD_PRIORS])
def test_bad_prior(command, case, workdir, capsys):
    _, template = command
    _, prior, fragment = case
    before = sorted(p.name for p in workdir.iterdir())
    argv = [prior if a == "{prior}" else a.format(tmp=str(workdir)) for a in template]
    code, out, err = _run(argv, capsys)
    _check_failure(code, out, err, fragment, workdir, before)


@pytest.mark.parametrize("command", OUTPUT_COMMANDS, ids=[c[0] for c in OUTPUT_COMMANDS])
@pytest.mark.parametrize("case", BAD_OUTPUTS, ids=[c[0] for c in BAD_OUTPUTS])
def test_unwritable_output(command, case, workdir, capsys):
    _, template, ext = command
    _, output, fragment = case
    before = sorted(p.name for p in workdir.iterdir())
    argv = _fill(template, output=output.format(tmp=str(workdir)) + ext, good=str(workdir / "good.csv"), tmp=str(workdir))
    code, out, err = _run(argv, capsys)
    _check_failure(code, out, err, fragment, workdir, before)


def test_model_overflow_is_reported_not_written(workdir, capsys):
    before = sorted(p.name for p in workdir.iterdir())
    code, out, err = _run(["simulate", "R1 + L1", "--param", "L1=1e308", "--out", str(workdir / "o.csv")], capsys)
    _check_failure(code, out, err, "not finite (overflow)", workdir, before)


def test_huge_but_finite_values_are_read_exactly(workdir, capsys):
    """1e300 Ω is absurd but finite: impedax reads it unchanged rather than guessing."""
    path = workdir / "huge.csv"
    path.write_text(HEADER + "1,1e300,-1e300\n1e300,1,-1\n")
    ds = ix.load(path)
    np.testing.assert_array_equal(ds["Z"].values, [1e300 - 1e300j, 1 - 1j])
    code, out, err = _run(["inspect", str(path)], capsys)
    assert code == 0 and "Traceback" not in err


@pytest.mark.parametrize("case", BAD_OPTIONS, ids=[c[0] for c in BAD_OPTIONS])
def test_bad_option(case, workdir, capsys):
    _, template, fragment = case
    if case[0] == "fit-plot-pgf" and shutil.which(matplotlib.rcParams["pgf.texsystem"]):
        pytest.skip("LaTeX is installed here: PGF figures can be written")
    before = sorted(p.name for p in workdir.iterdir())
    code, out, err = _run(_fill(template, good=str(workdir / "good.csv"), tmp=str(workdir)), capsys)
    _check_failure(code, out, err, fragment, workdir, before, usage=True)


@pytest.mark.parametrize("case", UNDATA, ids=[c[0] for c in UNDATA])
def test_data_the_analysis_cannot_use(case, workdir, capsys):
    _, content, template, fragment = case
    path = workdir / "data.csv"
    path.write_text(content)
    before = sorted(p.name for p in workdir.iterdir())
    code, out, err = _run(_fill(template, input=str(path), tmp=str(workdir)), capsys)
    _check_failure(code, out, err, fragment, workdir, before)


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root reads any file")
@pytest.mark.parametrize("command", FILE_COMMANDS, ids=[c[0] for c in FILE_COMMANDS])
def test_unreadable_file(command, workdir, capsys):
    path = workdir / "locked.csv"
    path.write_text(GOOD_CSV)
    path.chmod(0)
    before = sorted(p.name for p in workdir.iterdir())
    code, out, err = _run(_fill(command[1], input=str(path), tmp=str(workdir)), capsys)
    _check_failure(code, out, err, "ermission", workdir, before)


# --- the Python API ---------------------------------------------------------------------------
# Each row: (id, function, call on the namespace of spectra below, expected error type, message
# fragment naming the argument). Every public entry point meets the same classes of bad
# argument: no data / the wrong container, the wrong type, NaN or infinity, a negative or huge
# count, a bool where a number belongs, an unknown keyword, and data the method cannot use.


class Spectra:
    """Spectra and objects the API rows use, built once."""

    def __init__(self):
        import xarray as xr

        freq = ix.log_frequencies(1.0, 1e5, 21)
        z = 100.0 + 1.0 / (1j * 2 * np.pi * freq * 1e-6)
        self.good = ix.make_spectrum(freq, z)
        self.one = ix.make_spectrum([10.0], [100 - 5j])
        self.two = ix.make_spectrum([10.0, 20.0], [100 - 5j, 100 - 2j])
        self.huge = ix.make_spectrum(freq, np.full(freq.size, 1e300 - 1e300j))
        self.string_frequency = self.good.assign_coords(frequency=[str(f) for f in freq])
        self.real_dataarray = xr.DataArray(np.abs(z), dims="frequency", coords={"frequency": freq})
        self.no_frequency_dataarray = xr.DataArray(z, dims="f")
        self.pair = (freq, z)
        self.trials = ix.make_spectrum(freq, np.stack([z, 1.01 * z]), dims=("trial",), coords={"trial": [0, 1]})
        self.freq, self.z = freq, z
        self.zero_trials = xr.Dataset({"Z": (("trial", "frequency"), np.zeros((0, freq.size), complex))}, coords={"frequency": freq})
        self.zero_modulus = ix.make_spectrum(freq, np.where(np.arange(freq.size) == 5, 0j, z))
        self.khz = xr.Dataset({"Z": ("frequency", z)}, coords={"frequency": ("frequency", freq / 1e3, {"units": "kHz"})})
        self.kohm = xr.Dataset({"Z": ("frequency", z / 1e3, {"units": "kOhm"})}, coords={"frequency": freq})
        self._fit = None

    @property
    def fit(self):
        """A fit of ``good`` (made once, when a row needs it)."""
        if self._fit is None:
            self._fit = ix.fit(RC, self.good)
        return self._fit


_spectra = None


def spectra() -> Spectra:
    global _spectra
    if _spectra is None:
        _spectra = Spectra()
    return _spectra


P, D, C, CS, F = ix.ParameterError, ix.DataError, ix.CircuitError, ix.CircuitSyntaxError, ix.FitError
RC = "R1 + C1"
RCPE = "R0 + R1 || CPE1"
RCPE_VALUES = {"R0": 10.0, "R1": 1e3, "CPE1.Q": 1e-6, "CPE1.alpha": 0.9}
FREQ = np.geomspace(1.0, 1e5, 31)
API_CASES = [
    # fit
    ("fit-data-none", "fit", lambda s: ix.fit(RC, None), D, "data must be a spectrum Dataset"),
    ("fit-data-numpy-array", "fit", lambda s: ix.fit(RC, np.array([1.0, 2.0])), D, "got array([1., 2.]) (ndarray)"),
    ("fit-data-list", "fit", lambda s: ix.fit(RC, [1, 2, 3]), D, "data must be a spectrum Dataset"),
    ("fit-data-real-dataarray", "fit", lambda s: ix.fit(RC, s.real_dataarray), D, "a DataArray of complex Z over a 'frequency' dimension"),
    ("fit-data-dataarray-without-frequency", "fit", lambda s: ix.fit(RC, s.no_frequency_dataarray), D, "has dims ('f',)"),
    ("fit-data-string-frequency", "fit", lambda s: ix.fit(RC, s.string_frequency), D, "frequency coordinate must be real numbers"),
    ("fit-data-nul-in-path", "fit", lambda s: ix.fit(RC, "a\x00b.csv"), D, "cannot contain a NUL character"),
    ("fit-data-huge-values", "fit", lambda s: ix.fit(RC, s.huge), D, "outside the range impedax analyses"),
    ("fit-data-one-point", "fit", lambda s: ix.fit(RC, s.one), F, "2 free parameters but only 2 real data values"),
    ("fit-circuit-none", "fit", lambda s: ix.fit(None, s.good), CS, "a circuit must be text, got NoneType"),
    ("fit-init-list", "fit", lambda s: ix.fit(RC, s.good, init=[1, 2]), P, "init must be a mapping"),
    ("fit-init-string-value", "fit", lambda s: ix.fit(RC, s.good, init={"R1": "abc"}), P, "init['R1'] must be a number, got 'abc'"),
    ("fit-init-bool-value", "fit", lambda s: ix.fit(RC, s.good, init={"R1": True}), P, "init['R1'] must be a number, got True"),
    ("fit-init-nan", "fit", lambda s: ix.fit(RC, s.good, init={"R1": float("nan")}), P, "init['R1'] must be finite"),
    ("fit-init-unknown-name", "fit", lambda s: ix.fit(RC, s.good, init={"R2": 1.0}), P, "init: unknown parameter 'R2'"),
    ("fit-init-integer-key", "fit", lambda s: ix.fit(RC, s.good, init={1: 1.0}), P, "init: parameter names are strings"),
    ("fit-fixed-list", "fit", lambda s: ix.fit(RC, s.good, fixed=[1]), P, "fixed must be a mapping"),
    ("fit-fixed-infinite", "fit", lambda s: ix.fit(RC, s.good, fixed={"R1": float("inf")}), P, "fixed['R1'] must be finite"),
    ("fit-bounds-not-a-pair", "fit", lambda s: ix.fit(RC, s.good, bounds={"R1": 5}), P, "bounds['R1'] must be a pair"),
    ("fit-bounds-strings", "fit", lambda s: ix.fit(RC, s.good, bounds={"R1": ("a", "b")}), P, "bounds['R1']: lower must be a number"),
    ("fit-bounds-reversed", "fit", lambda s: ix.fit(RC, s.good, bounds={"R1": (10, 1)}), P, "bounds for R1: lower 10 must be below upper 1"),
    ("fit-bounds-mapping", "fit", lambda s: ix.fit(RC, s.good, bounds={"R1": {"lower": 1, "upper": 2}}), P, "bounds['R1'] must be a pair (lower, upper), e.g. (1, 2), not a dict"),
    ("fit-fixed-just-above-bound", "fit", lambda s: ix.fit(RCPE, s.good, fixed={"CPE1.alpha": 1.0000001}), P, "fixed: CPE1.alpha=1.0000001 is outside its bounds (0, 1]"),
    ("fit-init-on-own-bound", "fit", lambda s: ix.fit(RC, s.good, init={"R1": 200}, bounds={"R1": (1, 200)}), P, "init: R1=200 is on its upper bound, which its bounds (1, 200) exclude: a starting value must lie strictly inside"),
    ("fit-init-just-above-own-bound", "fit", lambda s: ix.fit(RC, s.good, init={"R1": 200.00001}, bounds={"R1": (1, 200)}), P, "init: R1=200.00001 is outside its bounds (1, 200)"),
    ("fit-seed-string", "fit", lambda s: ix.fit(RC, s.good, seed="abc"), P, "seed must be an integer, got 'abc'"),
    ("fit-seed-bool", "fit", lambda s: ix.fit(RC, s.good, seed=True), P, "seed must be an integer, got True"),
    ("fit-seed-negative", "fit", lambda s: ix.fit(RC, s.good, seed=-1), P, "seed must be at least 0"),
    ("fit-seed-huge", "fit", lambda s: ix.fit(RC, s.good, seed=10**30), P, "seed=1000000000000000000000000000000 is above the limit"),
    ("fit-fmin-string", "fit", lambda s: ix.fit(RC, s.good, fmin="abc"), P, "fmin must be a number, got 'abc'"),
    ("fit-fmin-nan", "fit", lambda s: ix.fit(RC, s.good, fmin=float("nan")), P, "fmin must be finite"),
    ("fit-fmin-negative", "fit", lambda s: ix.fit(RC, s.good, fmin=-1.0), P, "fmin must be positive"),
    ("fit-fmin-above-fmax", "fit", lambda s: ix.fit(RC, s.good, fmin=1e4, fmax=10.0), P, "fmax (10 Hz) is below fmin (10 kHz)"),
    ("fit-fmin-just-above-fmax", "fit", lambda s: ix.fit(RC, s.good, fmin=100.0001, fmax=100.0), P, "fmax (100 Hz) is below fmin (100.0001 Hz)"),
    ("fit-band-outside-the-data", "fit", lambda s: ix.fit(RC, s.good, fmin=1e7), D, "no frequencies at or above fmin = 10 MHz"),
    ("fit-max-steps-negative", "fit", lambda s: ix.fit(RC, s.good, max_steps=-1), P, "max_steps must be at least 1, got -1"),
    ("fit-batch-max-steps-negative", "fit", lambda s: ix.fit(RC, s.trials, max_steps=-1), P, "max_steps must be at least 1, got -1"),
    ("fit-max-steps-float", "fit", lambda s: ix.fit(RC, s.good, max_steps=2.5), P, "max_steps must be an integer, got 2.5"),
    ("fit-max-steps-huge", "fit", lambda s: ix.fit(RC, s.good, max_steps=10**12), P, "max_steps=1000000000000 is above the limit"),
    ("fit-n-starts-huge", "fit", lambda s: ix.fit(RC, s.good, n_starts=10**9), P, "n_starts=1000000000 is above the limit"),
    ("fit-n-starts-zero", "fit", lambda s: ix.fit(RC, s.good, n_starts=0), P, "n_starts must be at least 1"),
    ("fit-weighting-unknown", "fit", lambda s: ix.fit(RC, s.good, weighting="modulos"), P, "unknown weighting 'modulos'; did you mean 'modulus'?"),
    ("fit-weighting-number", "fit", lambda s: ix.fit(RC, s.good, weighting=3), P, "unknown weighting 3"),
    ("fit-weighting-capitals", "fit", lambda s: ix.fit(RC, s.good, weighting="MODULUS"), P, "unknown weighting 'MODULUS'; did you mean 'modulus'?"),
    ("fit-registry-string", "fit", lambda s: ix.fit(RC, s.good, registry="x"), P, "registry must be Registry"),
    ("fit-unknown-keyword", "fit", lambda s: ix.fit(RC, s.good, max_step=3), P, "fit() has no argument 'max_step'; did you mean max_steps?"),
    ("fit-too-many-positional", "fit", lambda s: ix.fit(RC, s.good, None), P, "fit() takes 2 positional arguments"),
    ("fit-frequency-and-z-apart", "fit", lambda s: ix.fit(RC, s.good.frequency.values, s.good.Z.values), P, "a spectrum given as arrays is one argument, the pair (frequency, Z): fit(circuit, (frequency, Z))"),
    ("kk-frequency-and-z-apart", "fit", lambda s: ix.kk_test(list(s.good.frequency.values), list(s.good.Z.values)), P, "kk_test() takes 1 positional argument (data), got 2: a spectrum given as arrays is one argument, the pair (frequency, Z): kk_test((frequency, Z))"),
    ("fit-missing-data", "fit", lambda s: ix.fit(RC), P, "fit() needs the argument data"),
    # sample
    ("sample-data-none", "sample", lambda s: ix.sample(RC, None, steps=10), D, "data must be a spectrum Dataset"),
    ("sample-data-list", "sample", lambda s: ix.sample(RC, [1.0, 2.0], steps=10), D, "data must be a spectrum Dataset"),
    ("sample-steps-negative", "sample", lambda s: ix.sample(RC, s.good, steps=-1), P, "steps must be at least 1"),
    ("sample-steps-string", "sample", lambda s: ix.sample(RC, s.good, steps="abc"), P, "steps must be an integer, got 'abc'"),
    ("sample-steps-huge", "sample", lambda s: ix.sample(RC, s.good, steps=10**9), P, "steps=1000000000 is above the limit"),
    ("sample-walkers-huge", "sample", lambda s: ix.sample(RC, s.good, steps=10, walkers=10**9), P, "walkers=1000000000 is above the limit"),
    ("sample-chain-too-large", "sample", lambda s: ix.sample(RC, s.good, steps=10**6, walkers=1000), P, "steps × walkers = 1,000,000,000 is above the limit"),
    ("sample-walkers-one", "sample", lambda s: ix.sample(RC, s.good, steps=10, walkers=1), P, "walkers must be at least 2"),
    ("sample-thin-zero", "sample", lambda s: ix.sample(RC, s.good, steps=10, thin=0), P, "thin must be at least 1"),
    ("sample-burn-float", "sample", lambda s: ix.sample(RC, s.good, steps=10, burn=1.5), P, "burn must be an integer, got 1.5"),
    ("sample-seed-string", "sample", lambda s: ix.sample(RC, s.good, steps=10, seed="abc"), P, "seed must be an integer, got 'abc'"),
    ("sample-noise-unknown", "sample", lambda s: ix.sample(RC, s.good, steps=10, noise="bogus"), P, "unknown noise model 'bogus'"),
    ("sample-priors-list", "sample", lambda s: ix.sample(RC, s.good, steps=10, priors=[1]), P, "priors must be a mapping"),
    ("sample-progress-string", "sample", lambda s: ix.sample(RC, s.good, steps=10, progress="no"), P, "progress must be True or False"),
    ("sample-fmin-above-fmax", "sample", lambda s: ix.sample(RC, s.good, steps=10, fmin=10.0, fmax=1.0), P, "fmax (1 Hz) is below fmin (10 Hz)"),
    ("sample-fmin-above-fmax-millihertz", "sample", lambda s: ix.sample(RC, s.good, steps=10, fmin=0.05, fmax=0.002), P, "fmax (2 mHz) is below fmin (50 mHz)"),
    ("sample-unknown-keyword", "sample", lambda s: ix.sample(RC, s.good, step=10), P, "sample() has no argument 'step'; did you mean steps?"),
    # diagnose
    ("diagnose-data-none", "diagnose", lambda s: ix.diagnose(None, RC), D, "data must be a spectrum Dataset"),
    ("diagnose-data-numpy-array", "diagnose", lambda s: ix.diagnose(np.zeros(3), RC), D, "data must be a spectrum Dataset"),
    ("diagnose-one-point", "diagnose", lambda s: ix.diagnose(s.one, "R1"), D, "diagnose needs at least 4 frequencies"),
    ("diagnose-two-points", "diagnose", lambda s: ix.diagnose(s.two, "R1"), D, "diagnose needs at least 4 frequencies"),
    ("diagnose-effects-string", "diagnose", lambda s: ix.diagnose(s.good, RC, effects="bogus"), P, "effects must be an EffectCatalog"),
    ("diagnose-kk-number", "diagnose", lambda s: ix.diagnose(s.good, RC, kk=3), P, "kk must be KKResult"),
    ("diagnose-noise-string", "diagnose", lambda s: ix.diagnose(s.good, RC, noise="abc"), P, "noise must be a number, got 'abc'"),
    ("diagnose-noise-negative", "diagnose", lambda s: ix.diagnose(s.good, RC, noise=-0.01), P, "noise must be positive"),
    ("diagnose-seed-string", "diagnose", lambda s: ix.diagnose(s.good, RC, seed="abc"), P, "seed must be an integer, got 'abc'"),
    ("diagnose-max-steps-negative", "diagnose", lambda s: ix.diagnose(s.good, RC, max_steps=-1), P, "max_steps must be at least 1"),
    ("diagnose-weighting-unknown", "diagnose", lambda s: ix.diagnose(s.good, RC, weighting="bogus"), P, "unknown weighting 'bogus'"),
    ("diagnose-drt-evidence-number", "diagnose", lambda s: ix.diagnose(s.good, RC, drt_evidence=1), P, "drt_evidence must be True or False"),
    ("diagnose-unknown-keyword", "diagnose", lambda s: ix.diagnose(s.good, RC, effect=None), P, "diagnose() has no argument 'effect'; did you mean effects?"),
    # refine
    ("refine-data-none", "refine", lambda s: ix.refine(None, RC), D, "data must be a spectrum Dataset"),
    ("refine-max-steps-negative", "refine", lambda s: ix.refine(s.good, RC, max_steps=-1), P, "max_steps must be at least 1"),
    ("refine-max-steps-huge", "refine", lambda s: ix.refine(s.good, RC, max_steps=10**7), P, "max_steps=10000000 is above the limit 1,000,000"),
    ("refine-max-steps-zero", "refine", lambda s: ix.refine(s.good, RC, max_steps=0, max_effects=1), P, "max_steps must be at least 1"),
    ("refine-max-effects-huge", "refine", lambda s: ix.refine(s.good, RC, max_effects=10**6), P, "max_effects=1000000 is above the limit 64"),
    ("refine-effects-string", "refine", lambda s: ix.refine(s.good, RC, effects="bogus"), P, "effects must be an EffectCatalog"),
    ("refine-n-starts-bool", "refine", lambda s: ix.refine(s.good, RC, n_starts=True), P, "n_starts must be an integer, got True"),
    ("refine-one-point", "refine", lambda s: ix.refine(s.one, "R1"), D, "refine needs at least 4 frequencies"),
    # compare
    ("compare-none", "compare", lambda s: ix.compare(None), P, "fits must be a list"),
    ("compare-string", "compare", lambda s: ix.compare("R1"), P, "fits must be a list"),
    ("compare-numbers", "compare", lambda s: ix.compare([1, 2]), P, "fits[0] must be a FitResult"),
    ("compare-empty", "compare", lambda s: ix.compare([]), F, "compare needs at least one fit"),
    # kk_test, zhit, drt
    ("kk-data-none", "kk_test", lambda s: ix.kk_test(None), D, "got NoneType"),
    ("kk-data-list", "kk_test", lambda s: ix.kk_test([1, 2, 3]), D, "got list"),
    ("kk-data-real-dataarray", "kk_test", lambda s: ix.kk_test(s.real_dataarray), D, "a DataArray of complex Z"),
    ("kk-data-string-frequency", "kk_test", lambda s: ix.kk_test(s.string_frequency), D, "frequency coordinate must be real numbers"),
    ("kk-data-huge-values", "kk_test", lambda s: ix.kk_test(s.huge), D, "outside the range impedax analyses"),
    ("kk-pair-with-nan", "kk_test", lambda s: ix.kk_test((s.pair[0], s.pair[1] * np.nan)), D, "non-finite value"),
    ("kk-pair-negative-frequency", "kk_test", lambda s: ix.kk_test((-s.pair[0], s.pair[1])), D, "frequency must be positive"),
    ("kk-pair-duplicate-frequency", "kk_test", lambda s: ix.kk_test((np.ones(21), s.pair[1])), D, "duplicate frequency 1 Hz at points 0, 1"),
    ("kk-one-point", "kk_test", lambda s: ix.kk_test(s.one), D, "needs at least 4 frequencies"),
    ("kk-c-string", "kk_test", lambda s: ix.kk_test(s.good, c="abc"), P, "c must be between 0 and 1"),
    ("kk-n-rc-negative", "kk_test", lambda s: ix.kk_test(s.good, n_rc=-1), P, "n_rc must be at least 1"),
    ("kk-n-rc-huge", "kk_test", lambda s: ix.kk_test(s.good, n_rc=10**9), P, "n_rc=1000000000 is above the limit"),
    ("kk-max-rc-huge", "kk_test", lambda s: ix.kk_test(s.good, max_rc=10**9), P, "max_rc=1000000000 is above the limit"),
    ("kk-inductance-string", "kk_test", lambda s: ix.kk_test(s.good, inductance="yes"), P, "inductance must be True or False"),
    ("kk-thresholds-unknown", "kk_test", lambda s: ix.kk_test(s.good, thresholds={"x": 1}), P, "unknown threshold 'x'"),
    ("kk-unknown-keyword", "kk_test", lambda s: ix.kk_test(s.good, nrc=3), P, "kk_test() has no argument 'nrc'; did you mean n_rc?"),
    ("zhit-data-none", "zhit", lambda s: ix.zhit(None), D, "got NoneType"),
    ("zhit-one-point", "zhit", lambda s: ix.zhit(s.one), D, "Z-HIT needs at least 6 frequencies"),
    ("zhit-noise-floor-string", "zhit", lambda s: ix.zhit(s.good, noise_floor="abc"), P, "noise_floor must be a number"),
    ("zhit-run-length-negative", "zhit", lambda s: ix.zhit(s.good, run_length=-1), P, "run_length must be at least 1"),
    ("drt-data-none", "drt", lambda s: ix.drt(None), D, "got NoneType"),
    ("drt-one-point", "drt", lambda s: ix.drt(s.one), D, "the DRT needs at least 5 frequencies"),
    ("drt-method-unknown", "drt", lambda s: ix.drt(s.good, method="bogus"), P, "unknown DRT method 'bogus'"),
    ("drt-lambda-string", "drt", lambda s: ix.drt(s.good, lam="abc"), P, "lam must be 'auto' or a positive number"),
    ("drt-lambda-negative", "drt", lambda s: ix.drt(s.good, lam=-1.0), P, "lam must be a positive finite number"),
    ("drt-points-per-decade-zero", "drt", lambda s: ix.drt(s.good, points_per_decade=0), P, "points_per_decade must be at least 1"),
    ("drt-points-per-decade-huge", "drt", lambda s: ix.drt(s.good, points_per_decade=1e9), P, "points_per_decade must be at most 1000"),
    ("drt-max-iter-negative", "drt", lambda s: ix.drt(s.good, max_iter=-1), P, "max_iter must be at least 1"),
    ("drt-signed-string", "drt", lambda s: ix.drt(s.good, signed="no"), P, "signed must be True or False"),
    # load, save, parse, make_spectrum, log_frequencies
    ("load-missing-file", "load", lambda s: ix.load("no/such/file.csv"), D, "file not found"),
    ("save-unknown-extension", "save", lambda s: ix.save(s.good, "out.xyz"), D, "unknown output format '.xyz'"),
    ("parse-none", "parse", lambda s: ix.parse(None), CS, "a circuit must be text, got NoneType"),
    ("parse-bytes", "parse", lambda s: ix.parse(b"R1"), CS, "a circuit must be text, got bytes"),
    ("parse-registry-number", "parse", lambda s: ix.parse("R1", 3), P, "registry must be a Registry"),
    ("parse-cyrillic-letter", "parse", lambda s: ix.parse("R1 + С1"), CS, "did you mean the Latin 'C'?"),
    ("parse-huge-circuit", "parse", lambda s: ix.parse(" + ".join(f"R{k}" for k in range(15_000))), CS, "more than 256 elements"),
    ("from-cdc-none", "from_cdc", lambda s: ix.from_cdc(None), CS, "a circuit must be text"),
    ("from-impedance-py-number", "from_impedance_py", lambda s: ix.from_impedance_py(3), CS, "a circuit must be text"),
    ("make-spectrum-strings", "make_spectrum", lambda s: ix.make_spectrum(["a"], [1]), D, "frequency must be numbers"),
    ("make-spectrum-sizes-differ", "make_spectrum", lambda s: ix.make_spectrum([1, 2], [1j]), D, "Z has 1 values along frequency but there are 2"),
    ("make-spectrum-negative-frequency", "make_spectrum", lambda s: ix.make_spectrum([-1.0, 2.0], [1j, 1j]), D, "frequency must be positive"),
    ("make-spectrum-duplicate-frequency", "make_spectrum", lambda s: ix.make_spectrum([2.0, 2.0], [1j, 1j]), D, "duplicate frequency 2 Hz"),
    ("make-spectrum-nan", "make_spectrum", lambda s: ix.make_spectrum([1.0, 2.0], [1j, np.nan]), D, "non-finite value"),
    ("make-spectrum-bool-z", "make_spectrum", lambda s: ix.make_spectrum([1.0, 2.0], [True, False]), D, "Z must be numbers"),
    ("make-spectrum-empty", "make_spectrum", lambda s: ix.make_spectrum([], []), D, "frequency is empty: no data"),
    ("make-spectrum-frequency-in-coords", "make_spectrum", lambda s: ix.make_spectrum(s.freq, s.z, coords={"frequency": 2 * s.freq}), P, "frequency given twice"),
    ("make-spectrum-frequency-in-dims", "make_spectrum", lambda s: ix.make_spectrum(s.freq, np.stack([s.z, s.z]), dims=("trial", "frequency")), P, "leave 'frequency' out of dims"),
    ("make-spectrum-coords-wrong-length", "make_spectrum", lambda s: ix.make_spectrum(s.freq, np.stack([s.z, s.z]), dims=("trial",), coords={"trial": [1, 2, 3]}), D, "coords['trial'] has 3 labels but Z has 2 entries"),
    ("make-spectrum-coords-not-in-dims", "make_spectrum", lambda s: ix.make_spectrum(s.freq, np.stack([s.z, s.z]), dims=("trial",), coords={"session": [1, 2]}), P, "coords names 'session', which is not a dimension of Z"),
    ("make-spectrum-unknown-keyword", "make_spectrum", lambda s: ix.make_spectrum(s.freq, s.z, sigmaa=1), P, "make_spectrum() has no argument 'sigmaa'; did you mean sigma?"),
    ("validate-spectrum-zero-trials", "validate_spectrum", lambda s: ix.validate_spectrum(s.zero_trials), D, "dimension 'trial' of Z has length 0"),
    ("fit-data-zero-trials", "fit", lambda s: ix.fit(RC, s.zero_trials), D, "dimension 'trial' of Z has length 0"),
    ("kk-batch-data-zero-trials", "kk_test_batch", lambda s: ix.kk_test_batch(s.zero_trials), D, "dimension 'trial' of Z has length 0"),
    ("drt-data-zero-trials", "drt", lambda s: ix.drt(s.zero_trials), D, "dimension 'trial' of Z has length 0"),
    ("validate-spectrum-sigma-other-dimension", "validate_spectrum", lambda s: ix.validate_spectrum(s.good.assign(sigma=("x", np.ones(5)))), D, "sigma must be a standard deviation [Ω] per point of Z, over Z's dimensions"),
    ("validate-spectrum-sigma-dimension-not-in-z", "validate_spectrum", lambda s: ix.validate_spectrum(s.good.assign(sigma=("trial", np.ones(3)))), D, "got dims ('trial',) with shape (3,)"),
    ("validate-spectrum-sigma-scalar", "validate_spectrum", lambda s: ix.validate_spectrum(s.good.assign(sigma=0.5)), D, "got a single value; make_spectrum(..., sigma=value) spreads"),
    ("validate-spectrum-sigma-text", "validate_spectrum", lambda s: ix.validate_spectrum(s.good.assign(sigma=("frequency", ["a"] * s.freq.size))), D, "sigma must be real numbers"),
    ("validate-spectrum-sigma-complex", "validate_spectrum", lambda s: ix.validate_spectrum(s.good.assign(sigma=("frequency", np.ones(s.freq.size) * (1 + 1j)))), D, "got dtype complex128"),
    ("validate-spectrum-sigma-bool", "validate_spectrum", lambda s: ix.validate_spectrum(s.good.assign(sigma=("frequency", np.ones(s.freq.size, bool)))), D, "got dtype bool"),
    ("validate-spectrum-sigma-zero", "validate_spectrum", lambda s: ix.validate_spectrum(s.good.assign(sigma=("frequency", np.arange(s.freq.size, dtype=float)))), D, "sigma must be positive and finite; at f=1 Hz (point 0) it is 0"),
    ("validate-spectrum-frequency-in-khz", "validate_spectrum", lambda s: ix.validate_spectrum(s.khz), D, "frequency has units 'kHz', but impedax works in Hz: multiply the values by 1000"),
    ("validate-spectrum-z-in-kohm", "validate_spectrum", lambda s: ix.validate_spectrum(s.kohm), D, "Z has units 'kOhm', but impedax works in ohm: multiply the values by 1000"),
    ("drt-data-zero-modulus", "drt", lambda s: ix.drt(s.zero_modulus), D, "Z is exactly zero at 17.8 Hz; the relative weighting 1/|Z| needs |Z| > 0"),
    ("sample-data-zero-modulus", "sample", lambda s: ix.sample(RC, s.zero_modulus, steps=20), D, "Z is exactly zero at 17.8 Hz; noise='proportional' (σ = sigma_rel·|Z|) needs |Z| > 0"),
    ("fit-data-zero-modulus", "fit", lambda s: ix.fit(RC, s.zero_modulus), D, "zero or non-finite weight at f=17.8 Hz (point 5), where |Z| = 0 Ω; drop the point or use weighting='unit'"),
    ("write-result-arguments-swapped", "write_result", lambda s: ix.write_result("r.json", s.fit), P, "the arguments look swapped"),
    ("derive-fn-not-callable", "derive", lambda s: ix.derive(s.fit, 3), P, "fn must be a function of the parameters"),
    ("save-unstorable-attribute", "save", lambda s: ix.save(s.good.assign_attrs(thing=object()), "a.nc"), D, "attribute 'thing' of the dataset is <object object"),
    ("save-json-extension", "save", lambda s: ix.save(s.good, "x.json"), D, "use .nc, .nc4, .cdf (netCDF), .csv, .txt, .tsv"),
    # (a name ending in '/' was a file named without it until 2026-12-08: "out/" wrote a CSV named "out")
    ("save-folder-name", "save", lambda s: ix.save(s.good, "out/"), D, "out/: ends with '/', so it names a folder, not a file; give a file name in it, e.g. out/spectrum.csv"),
    ("write-result-folder-name", "write_result", lambda s: ix.write_result(s.fit, "results/"), D, "results/: ends with '/', so it names a folder, not a file"),
    # (a wrong keyword was Python's TypeError "load() got an unexpected keyword argument" until 2026-12-08)
    ("load-unknown-keyword", "load", lambda s: ix.load("x.csv", cycle=3), P, "load() has no argument 'cycle' (it takes path, readers, sweep)"),
    ("save-misspelt-keyword", "save", lambda s: ix.save(s.good, "x.nc", provenence={}), P, "save() has no argument 'provenence'; did you mean provenance?"),
    ("write-result-misspelt-keyword", "write_result", lambda s: ix.write_result(s.fit, "x.json", sorce="a"), P, "write_result() has no argument 'sorce'; did you mean source?"),
    ("stack-files-misspelt-keyword", "stack_files", lambda s: ix.stack_files(["x.csv"], coord=[1]), P, "stack_files() has no argument 'coord'; did you mean coords?"),
    ("draw-circuit-misspelt-keyword", "draw_circuit", lambda s: ix.draw_circuit(RC, valus={}), P, "draw_circuit() has no argument 'valus'; did you mean values?"),
    ("write-result-empty-name", "write_result", lambda s: ix.write_result(s.fit, ""), D, "empty file name: no output file was named"),
    ("draw-circuit-file-name-as-values", "draw_circuit", lambda s: ix.draw_circuit(RC, "circuit.svg"), P, "draw_circuit returns a matplotlib Figure; to write a file call impedax.save_circuit_diagram(circuit, 'circuit.svg')"),
    ("log-frequencies-string", "log_frequencies", lambda s: ix.log_frequencies("a", 2.0, 3), P, "fmin must be a number"),
    ("log-frequencies-huge", "log_frequencies", lambda s: ix.log_frequencies(1.0, 2.0, 10**12), P, "points=1000000000000 is above the limit"),
    ("log-frequencies-float-points", "log_frequencies", lambda s: ix.log_frequencies(1.0, 2.0, 2.5), P, "points must be an integer"),
    # models
    ("gap-thickness-string", "models.gap_thickness", lambda s: ix.models.gap_thickness("abc"), P, "c_gap must be numbers"),
    ("gap-thickness-negative", "models.gap_thickness", lambda s: ix.models.gap_thickness(-1e-9), P, "c_gap must be positive"),
    ("gap-thickness-nan", "models.gap_thickness", lambda s: ix.models.gap_thickness(np.array([1e-9, np.nan])), P, "c_gap must be finite"),
    ("gap-thickness-area-zero", "models.gap_thickness", lambda s: ix.models.gap_thickness(1e-9, area=0.0), P, "area must be positive"),
    ("electrovibration-frequency-string", "models.electrovibration_force", lambda s: ix.models.electrovibration_force("abc"), P, "freq must be numbers"),
    ("electrovibration-frequency-negative", "models.electrovibration_force", lambda s: ix.models.electrovibration_force(-5.0), P, "freq must be positive"),
    ("electrovibration-unknown-keyword", "models.electrovibration_force", lambda s: ix.models.electrovibration_force(100.0, h=1.0), P, "has no argument 'h'"),
    ("voltage-for-force-string", "models.voltage_for_force", lambda s: ix.models.voltage_for_force("a", 10.0), P, "force must be numbers"),
    ("meyer-force-params-none", "models.meyer_force", lambda s: ix.models.meyer_force(None, [1.0]), P, "params must be a mapping"),
    ("meyer-force-missing-parameter", "models.meyer_force", lambda s: ix.models.meyer_force({"C_s": 1e-9}, [1.0]), P, "params lacks C_i"),
    ("meyer-model-unknown-variant", "models.meyer_model", lambda s: ix.models.meyer_model("bogus"), P, "unknown Meyer variant 'bogus'"),
    ("finger-voltage-frequency-zero", "models.finger_voltage", lambda s: ix.models.finger_voltage({}, [0.0]), P, "freq must be positive"),
    ("gap-voltage-missing-parameter", "models.gap_voltage", lambda s: ix.models.gap_voltage({"R_EP": 1.0}, [1.0], 1.0, 1.0), P, "params lacks"),
    ("gap-force-lengths-differ", "models.gap_force_peak", lambda s: ix.models.gap_force_peak({"R_EP": 1e8, "CPE_EP.Q": 4e-9, "CPE_EP.alpha": 0.3, "C_gap": 4e-10}, np.geomspace(1, 1e6, 61), np.ones(10) * 1e3, np.ones(61) * 1e3), P, "z_skin has 10 values, freq has 61"),
    ("gap-force-no-branch-names", "models.gap_force_peak", lambda s: ix.models.gap_force_peak({"R_EP": 1e8, "C_gap": 4e-10}, [1.0], 1.0, 1.0), P, "(ep='CPE') or R_EP, C_EP, C_gap (ep='C')"),
    ("gap-force-u-not-c-gap", "models.gap_force_peak", lambda s: ix.models.gap_force_peak({"R_EP": 1e8, "CPE_EP.Q": 4e-9, "CPE_EP.alpha": 0.3, "u": 2.8e-6}, [1.0], 1.0, 1.0), P, "pass post.circuit_samples()"),
    ("gap-voltage-dataset-skin", "models.gap_voltage", lambda s: ix.models.gap_voltage({"C_gap": 4e-10}, s.good["frequency"], s.good, 1.0, ep=None), P, "z_skin is a Dataset; pass its complex impedance"),
    ("meyer-force-other-variant", "models.meyer_force", lambda s: ix.models.meyer_force(ix.models.meyer_model("cpe").params, [1e3], variant="rc"), P, "pass variant='cpe'"),
    ("write-result-meyer-model", "write_result", lambda s: ix.write_result(ix.models.meyer_model("cpe"), "m.nc"), P, "save m.to_xarray(freq) with impedax.io.write_netcdf"),
    ("gap-analysis-too-few-steps", "models.gap.gap_analysis", lambda s: gap_analysis(s.good, s.good, s.good, method="pooled", steps=5), P, "steps must be at least 20, got 5"),
    ("remaining-impedance-none", "models.remaining_impedance", lambda s: ix.models.remaining_impedance(None, None, None), D, "total: expected a spectrum Dataset"),
    ("gap-analysis-area-negative", "models.gap.gap_analysis", lambda s: gap_analysis(s.good, s.good, s.good, area=-1.0), P, "area must be positive"),
    ("gap-analysis-steps-huge", "models.gap.gap_analysis", lambda s: gap_analysis(s.good, s.good, s.good, steps=10**9), P, "steps=1000000000 is above the limit"),
    ("gap-analysis-unknown-branch", "models.gap.gap_analysis", lambda s: gap_analysis(s.good, s.good, s.good, ep="RC"), P, "unknown ep 'RC'"),
    # compiled circuits and probes
    ("compiled-vector-too-short", "CompiledCircuit.vector", lambda s: ix.compile_circuit(RCPE).vector(np.ones(3), FREQ), P, "theta has 3 values (last axis), the circuit has 4 parameters (R0, R1, CPE1.Q, CPE1.alpha)"),
    ("compiled-vector-too-long", "CompiledCircuit.vector", lambda s: ix.compile_circuit(RCPE).vector(np.ones(6), FREQ), P, "theta has 6 values (last axis), the circuit has 4 parameters"),
    ("compiled-vector-strings", "CompiledCircuit.vector", lambda s: ix.compile_circuit(RCPE).vector(["a", "b", "c", "d"], FREQ), P, "theta must be an array of the circuit's 4 parameter values"),
    ("compiled-jacobian-too-short", "CompiledCircuit.value_and_jacobian", lambda s: ix.compile_circuit(RCPE).value_and_jacobian([1.0, 2.0, 3.0], FREQ), P, "theta has 3 values (last axis), the circuit has 4 parameters"),
    ("compiled-jacobian-two-vectors", "CompiledCircuit.value_and_jacobian", lambda s: ix.compile_circuit(RCPE).value_and_jacobian(np.ones((2, 4)), FREQ), P, "theta must be one vector of the 4 parameters"),
    ("compiled-jacobian-negative-frequency", "CompiledCircuit.value_and_jacobian", lambda s: ix.compile_circuit(RCPE).value_and_jacobian(np.ones(4), -FREQ), D, "freq must be positive and finite"),
    ("compiled-value-list-of-two", "CompiledCircuit", lambda s: ix.compile_circuit(RCPE)({**RCPE_VALUES, "R0": [1.0, 2.0]}, FREQ), P, "params['R0'] has shape (2,), which does not broadcast against freq's shape (31,)"),
    ("compiled-value-array-of-three", "CompiledCircuit", lambda s: ix.compile_circuit(RCPE)({**RCPE_VALUES, "R0": np.ones(3)}, FREQ), P, "params['R0'] has shape (3,), which does not broadcast against freq's shape (31,)"),
    ("probe-missing-parameter", "voltage_across", lambda s: ix.voltage_across(RC, "C1")({"R1": 1.0}, FREQ), P, "missing parameter(s) C1 for circuit R1 + C1"),
    ("probe-negative-frequency", "voltage_across", lambda s: ix.voltage_across(RC, "C1")({"R1": 1.0, "C1": 1e-6}, -FREQ), D, "freq must be positive and finite"),
    ("probe-value-wrong-shape", "current_through", lambda s: ix.current_through(RC, "R1")({"R1": 1.0, "C1": np.ones(3)}, FREQ), P, "params['C1'] has shape (3,)"),
    ("probe-target-empty-set", "voltage_across", lambda s: ix.voltage_across(RC, set()), P, "target names no element"),
    ("probe-target-none", "voltage_across", lambda s: ix.voltage_across(RC, None), P, "target must be an element name or a set of element names"),
    ("probe-target-number", "voltage_across", lambda s: ix.voltage_across(RC, 3), P, "target must be an element name or a set of element names"),
    ("probe-target-number-in-set", "voltage_across", lambda s: ix.voltage_across(RC, {"C1", 3}), P, "target: element names are text, got 3"),
    ("probe-target-unknown", "voltage_across", lambda s: ix.voltage_across(RC, "c1"), C, "no element(s) 'c1' in R1 + C1; did you mean 'C1'?"),
    # load and save
    ("load-path-none", "load", lambda s: ix.load(None), D, "a file path (str or pathlib.Path) is needed, got None"),
    ("load-path-number", "load", lambda s: ix.load(3), D, "got 3 (int)"),
    ("load-nul-in-path", "load", lambda s: ix.load("a\x00b.csv"), D, "cannot contain a NUL character"),
    ("save-dataset-none", "save", lambda s: ix.save(None, "out.csv"), D, "save takes a spectrum Dataset"),
    ("save-path-none", "save", lambda s: ix.save(s.good, None), D, "a file path (str or pathlib.Path) is needed, got None"),
    ("stack-files-one-path", "stack_files", lambda s: ix.stack_files("day01.csv"), P, "paths must be a list of files, got the single 'day01.csv'"),
    ("stack-files-empty", "stack_files", lambda s: ix.stack_files([]), P, "paths is empty"),
    ("stack-files-dim-frequency", "stack_files", lambda s: ix.stack_files(["a.csv"], dim="frequency"), P, "'frequency' is every spectrum's own dimension"),
    ("stack-files-dim-number", "stack_files", lambda s: ix.stack_files(["a.csv"], dim=3), P, "dim must be the name of the new dimension"),
    ("stack-files-dim-blank", "stack_files", lambda s: ix.stack_files(["a.csv"], dim="a b"), P, "dim: 'a b' cannot name a dimension: ' ' cannot stand in it"),
    ("stack-files-dim-nan", "stack_files", lambda s: ix.stack_files(["a.csv"], dim="nan"), P, "dim: 'nan' cannot name a dimension: it reads as a number"),
    ("stack-files-coords-count", "stack_files", lambda s: ix.stack_files(["a.csv", "b.csv"], coords=[1]), P, "coords: 1 label for 2 files"),
    ("stack-files-coords-repeated", "stack_files", lambda s: ix.stack_files(["a.csv", "b.csv"], coords=[1, 1.0]), P, "the label 1 is given twice"),
    ("stack-files-missing-file", "stack_files", lambda s: ix.stack_files(["no/such/file.csv"]), D, "file not found"),
]



def gap_analysis(*args, **kwargs):
    from impedax.models.gap import gap_analysis as run

    return run(*args, progress=False, **kwargs) if "progress" not in kwargs else run(*args, **kwargs)


def _check_api_failure(call, error, fragment, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ix.ImpedaxError) as info:
        call(spectra())
    message = str(info.value)
    assert isinstance(info.value, error), (type(info.value).__name__, message)
    assert fragment in message, message
    assert message_length(message) < MAX_MESSAGE, message
    assert not [ch for ch in message if ch != "\n" and unicodedata.category(ch) in ("Cc", "Cf")], repr(message)
    assert list(tmp_path.iterdir()) == []  # nothing written


@pytest.mark.parametrize("case", API_CASES, ids=[c[0] for c in API_CASES])
def test_api_bad_argument(case, tmp_path, monkeypatch):
    _, _, call, error, fragment = case
    _check_api_failure(call, error, fragment, tmp_path, monkeypatch)





# --- docs/robustness.md against the tables ----------------------------------------------------

DOC = Path(__file__).resolve().parent.parent / "docs" / "robustness.md"
DOC_TABLES = {  # test → (its rows, the command ids a doc reference may end with)
    "test_bad_input_file": (BAD_FILES + [HDF5_WITHOUT_H5PY] * (HDF5_WITHOUT_H5PY not in BAD_FILES), FILE_COMMANDS),
    "test_bad_model": (BAD_MODELS, MODEL_COMMANDS),
    "test_bad_parameter": (BAD_PARAMS, PARAM_COMMANDS),
    "test_bad_prior": (BAD_PRIORS, PRIOR_COMMANDS),
    "test_unwritable_output": (BAD_OUTPUTS, OUTPUT_COMMANDS),
    "test_bad_option": (BAD_OPTIONS, []),
    "test_data_the_analysis_cannot_use": (UNDATA, []),
    "test_api_bad_argument": (API_CASES, []),
}


def test_doc_lists_every_row():
    """Every row of every table appears in docs/robustness.md, every test id there is a row of
    its table, and the doc's lists of commands are the tables' (so the page cannot drift)."""
    text = DOC.read_text(encoding="utf-8")
    references = re.findall(r"`(test_[a-z_]+)\[([^\]`]+)\]`", text)
    for test, (rows, commands) in DOC_TABLES.items():
        ids = {row[0] for row in rows}
        suffixes = {"*"} | {c[0] for c in commands}
        documented = {ref for name, ref in references if name == test}
        for ref in documented:
            every_row = ref.startswith("*-") and ref[2:] in suffixes  # (every row for one command)
            assert every_row or ref in ids or any(ref == f"{i}-{s}" for i in ids for s in suffixes), f"docs/robustness.md: {test}[{ref}] is no row"
        for row_id in ids:
            assert row_id in documented or any(ref.startswith(row_id + "-") and ref[len(row_id) + 1 :] in suffixes for ref in documented), f"row {row_id} of {test} is not in docs/robustness.md"
    for label, table in (("FILE_COMMANDS", FILE_COMMANDS), ("MODEL_COMMANDS", MODEL_COMMANDS), ("PARAM_COMMANDS", PARAM_COMMANDS), ("OUTPUT_COMMANDS", OUTPUT_COMMANDS)):
        listed = re.search(rf"\(`{label}`\): (.*)", text)
        assert listed and listed.group(1).split(", ") == [c[0] for c in table], label


def test_harness_has_at_least_300_rows():
    """The issue's bar: 300 bad inputs, CLI and API together (each a test of its own)."""
    cli = len(BAD_FILES) * len(FILE_COMMANDS) + len(BAD_MODELS) * len(MODEL_COMMANDS) + len(BAD_PARAMS) * len(PARAM_COMMANDS)
    cli += len(BAD_PRIORS) * len(PRIOR_COMMANDS) + len(BAD_OUTPUTS) * len(OUTPUT_COMMANDS) + len(BAD_OPTIONS) + len(UNDATA)
    assert cli >= 300 and len(API_CASES) >= 100, (cli, len(API_CASES))
    commands = {t[0] for table in (FILE_COMMANDS, MODEL_COMMANDS, PARAM_COMMANDS, OUTPUT_COMMANDS) for _, t, *_ in table} | {r[1][0] for r in BAD_OPTIONS}
    from impedax.cli import COMMAND_HELP

    assert set(COMMAND_HELP) <= commands, set(COMMAND_HELP) - commands  # every command meets the harness


@pytest.mark.parametrize("position", ["start", "middle", "end"])
def test_circuit_error_shows_at_most_80_characters_with_the_caret_on_the_culprit(position):
    """A 15 000-element series used to be echoed whole (125 kB); now a window of at most 80
    characters, and the caret stands under the offending character."""
    parts = [f"R{k}" for k in range(15_000)]
    index = {"start": 0, "middle": 7_000, "end": 14_999}[position]
    parts[index] = "R%"
    source = " + ".join(parts)
    column = source.index("%")
    with pytest.raises(ix.CircuitSyntaxError) as info:
        ix.parse(source)
    assert info.value.column == column and info.value.source == source  # the whole text stays on the error
    _, shown, caret, _ = str(info.value).split("\n")
    assert len(shown.strip()) <= 80
    assert shown[caret.index("^")] == "%"


def test_escaped_source_keeps_the_caret_aligned():
    """Escaping widens characters (ESC → \\x1b); the caret moves with them."""
    with pytest.raises(ix.CircuitSyntaxError) as info:
        ix.parse("R1 + \x1b\u202e + %")
    _, shown, caret, _ = str(info.value).split("\n")
    assert "\\x1b\\u202e" in shown and shown[caret.index("^")] == "\\"  # the ESC, the first offender


def test_complex_dataarray_is_fitted_like_its_dataset():
    """A DataArray of complex Z over `frequency` is converted to the data model, not refused."""
    good = spectra().good
    from_array, from_dataset = ix.fit(RC, good["Z"], n_starts=1), ix.fit(RC, good, n_starts=1)
    assert from_array.values == pytest.approx(from_dataset.values, rel=1e-9)
