"""Test helper: loading a file must fail with one `DataError` that names the file (and line)."""

import pytest

import impedax as ix


def assert_load_names(path, fragment, line=None):
    """``ix.load(path)`` raises `DataError` whose message names ``path``, contains ``fragment``
    and, given ``line``, names that line."""
    with pytest.raises(ix.DataError) as info:
        ix.load(path)
    msg = str(info.value)
    assert str(path) in msg and fragment in msg
    if line is not None:
        assert f"line {line}" in msg
