"""A command's `.nc` gives a fit's warnings in the command's words (`dataset_in_command_words`);
the attributes that hold one of those warnings as a value (`data_limit_note`, `misfit_note`,
`data_limit_hint`) must be in the same words, or a fit read back finds its note among its
warnings no more (`result.fit_data_limit`, `fit_blaming_note`)."""

import xarray as xr

from impedax.cli.common import command_line_words, dataset_in_command_words

NOTE = "the data's noise limit the fit; raise max_steps to check"


def test_a_note_held_as_a_value_is_worded_as_the_warning_it_names():
    ds = xr.Dataset(attrs={"warnings": [NOTE], "data_limit_note": NOTE, "misfit_note": NOTE, "data_limit_hint": "; hint: raise max_steps"})
    out = dataset_in_command_words(ds, "fit").attrs
    expected = command_line_words(NOTE, "fit")
    assert expected != NOTE and "--max-steps" in expected  # (the oracle: the phrase the command line says)
    assert list(out["warnings"]) == [expected]
    assert out["data_limit_note"] == expected and out["misfit_note"] == expected
    assert out["data_limit_hint"] == "; hint: raise --max-steps"
