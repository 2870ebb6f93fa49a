"""A `Reader` or `register_reader` given a missing or wrong argument is one impedax
`ParameterError` naming the argument (docs/io.md, "Adding a reader")."""

import pytest

from impedax.errors import ParameterError
from impedax.io import READERS, Reader, register_reader


def sniff_lab(path, head):
    return None if head.startswith(b"LAB") else "no 'LAB' signature"


def read_lab(path):
    raise AssertionError("not read in these tests")


LAB = Reader("lab", (".lab",), sniff_lab, read_lab)


@pytest.mark.parametrize(
    "make, says",
    [
        # the suffixes forgotten: Python's own error said "missing 1 required positional argument: 'read'"
        (lambda: Reader("lab", sniff_lab, read_lab), r"Reader 'lab': extensions, the second argument, is the function 'sniff_lab': were the suffixes left out\?"),
        (lambda: Reader("lab", ".lab", sniff_lab), r"Reader 'lab': read not given; Reader\(name, extensions, sniff, read\)"),
        (lambda: Reader("lab"), r"Reader 'lab': extensions, sniff, read not given"),
        (lambda: Reader(3, ".lab", sniff_lab, read_lab), r"Reader: name must be non-empty text, got 3 \(int\)"),
        (lambda: Reader("lab", 5, sniff_lab, read_lab), r"Reader 'lab': extensions must be a tuple of suffixes such as \('\.lab',\), got 5 \(int\)"),
        (lambda: register_reader("x"), r"register_reader expects an impedax\.io\.Reader, got 'x' \(str\)"),
        # a text was taken as true: the reader went first
        (lambda: register_reader(LAB, first="yes"), r"register_reader: first must be True .* or False .*, got 'yes' \(str\)"),
        (lambda: register_reader(LAB, "abc"), r"register_reader: readers must be a sequence of impedax\.io\.Reader"),
    ],
)
def test_wrong_reader_arguments_are_named(make, says):
    with pytest.raises(ParameterError, match=says):
        make()


def test_valid_uses_unchanged():
    assert Reader("lab", ".lab", sniff_lab, read_lab).extensions == (".lab",)
    assert register_reader(LAB)[0] is LAB
    after = register_reader(LAB, READERS, first=False)
    assert after[-1] is LAB and len(after) == len(READERS) + 1
    with pytest.raises(TypeError):  # (still a TypeError, as before, for code that caught one)
        Reader("lab", (".lab",), "LAB/1", read_lab)
