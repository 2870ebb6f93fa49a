"""`impedax gap`'s fits line (`_edl_chi2_text`) and `impedax remaining`'s line on stderr say what
the remainder's sigma is made of from its attrs ``sigma_sources`` (input → "trial scatter" or
"own sigma"), not by searching the prose of ``sigma_method`` for "stated sigma" (until
2026-12-06). Hand-built remainders whose words and sources disagree show which one decides: the
sources are the record; the words are another version's or a different run's."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

import impedax as ix
from impedax.cli import main

FREQ = np.geomspace(10.0, 1e5, 9)
STATED_WORDS = "SEM of Re and Im over the trials of total; the stated sigma of skin and touchscreen (one spectrum each), added in quadrature; sigma = sqrt((sigma_real^2 + sigma_imag^2)/2)"


def _remainder(sources: dict[str, str], words: str):
    """A hand-built trial-mean remainder (30 total trials) with a sigma, ``sigma_sources`` and
    ``sigma_method`` as given."""
    z = 3e5 - 4e5j * np.ones(FREQ.size)
    attrs = {"sigma_method": words, "sigma_sources": sources, "n_trials_total": 30, "n_trials_skin": 1 if sources.get("skin") == "own sigma" else 30,
             "n_trials_touchscreen": 1 if sources.get("touchscreen") == "own sigma" else 30}
    return ix.make_spectrum(FREQ, z, sigma=0.01 * np.abs(z), attrs=attrs)


MIXED = {"total": "trial scatter", "skin": "own sigma", "touchscreen": "trial scatter"}
EVERY = {"total": "trial scatter", "skin": "trial scatter", "touchscreen": "trial scatter"}


def test_gaps_fits_line_follows_the_sources():
    from impedax.models.gap import _edl_chi2_text

    fitted = SimpleNamespace(weighting="sigma", chi2_red=0.09)
    # words of another version that say nothing of a stated sigma; the sources name skin's
    mixed = _edl_chi2_text(fitted, _remainder(MIXED, "(words of another version)"))
    assert "against the remainder's sigma (the SEM of the trial means of total and touchscreen with the stated sigma of skin, one spectrum)" in mixed, mixed
    # words that speak of a stated sigma, sources that hold none: the trial means' SEM alone
    every = _edl_chi2_text(fitted, _remainder(EVERY, STATED_WORDS))
    assert "against the trial means' SEM, below 1 as expected" in every and "stated" not in every, every
    both = {"total": "trial scatter", "skin": "own sigma", "touchscreen": "own sigma"}
    assert "(the SEM of the trial means of total with the stated sigma of skin and touchscreen, one spectrum each)" in _edl_chi2_text(fitted, _remainder(both, STATED_WORDS))


def _remaining_line(monkeypatch, tmp_path, capsys, remainder) -> str:
    """``impedax remaining``'s line on stderr for a run whose remainder is ``remainder`` (the files
    are read and checked as always; the subtraction's result is replaced by the hand-built one)."""
    import impedax.models.gap as gap

    paths = []
    for name, z in (("total", 3e5 - 4e5j), ("skin", 2e4 - 1e4j), ("ts", 1e3 - 5e3j)):
        rng = np.random.default_rng(len(paths))
        paths.append(str(tmp_path / f"{name}.nc"))
        ix.save(ix.make_spectrum(FREQ, z * (1 + 0.01 * rng.standard_normal((3, FREQ.size))), dims=("trial",)), paths[-1])
    monkeypatch.setattr(gap, "gap_remainder", lambda *a, **k: (remainder, []))
    assert main(["remaining", *paths, "--out", str(tmp_path / "rem.nc")]) == 0
    return capsys.readouterr().err


def test_remainings_line_follows_the_sources(monkeypatch, tmp_path, capsys):
    err = _remaining_line(monkeypatch, tmp_path, capsys, _remainder(MIXED, "(words of another version)"))
    assert "sigma: SEM of Re and Im over the trials of total and touchscreen; the stated sigma of skin (one spectrum), added in quadrature: fit with --weighting sigma" in err, err
    err = _remaining_line(monkeypatch, tmp_path, capsys, _remainder(EVERY, STATED_WORDS))
    assert "sigma from their standard errors: fit with --weighting sigma to use it" in err and "stated" not in err, err
