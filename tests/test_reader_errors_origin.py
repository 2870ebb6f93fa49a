"""One layer words a user's reader that raises: `impedax.load` names the data file, the reader,
where it was declared (`Reader.origin`: ``--plugin FILE`` on the command line) and the file and
line of its code that raised, in Python and through ``--plugin`` alike (exit 2, no traceback)."""

import sys
import textwrap

import pytest

import impedax as ix
from impedax.io import Reader, register_reader

from cli_run import run

# the reader's code lives in a module beside the plugin, which imports it (a plugin split in two files)
HELPER = textwrap.dedent('''\
    import impedax as ix


    def sniff(path, head):
        return None if head.startswith(b"LABFMT") else "no 'LABFMT' signature"


    def read(path):
        rows = [line.split(";") for line in path.read_text().splitlines()[1:]]
        values = [[float(cell) for cell in row] for row in rows]
        return ix.make_spectrum([v[0] for v in values], [v[1] + 1j * v[2] for v in values])
''')
RAISING_LINE = 10  # (the line of HELPER whose float() meets 'oops', counted by hand)
PLUGIN = textwrap.dedent('''\
    from impedax.io import Reader
    from labhelper import read, sniff

    LAB = Reader("LAB split", (".lab",), sniff, read)
''')


@pytest.fixture()
def files(tmp_path, monkeypatch):
    monkeypatch.delitem(sys.modules, "labhelper", raising=False)  # (each test imports its own copy)
    (tmp_path / "labhelper.py").write_text(HELPER)
    plugin = tmp_path / "labplugin.py"
    plugin.write_text(PLUGIN)
    bad = tmp_path / "bad.lab"
    bad.write_text("LABFMT\n1;100;-5\n10;oops;-3\n")
    return plugin, bad, tmp_path / "labhelper.py"


def test_a_plugin_reader_whose_code_is_in_another_file_is_named_with_that_file_and_line(files, capsys):
    """Until 2026-12-06 the command line's own wrapper named the plugin and looked for the line in
    the plugin file alone: "the reader 'LAB split' of --plugin labplugin.py raised ValueError", no line."""
    plugin, bad, helper = files
    code, out, err = run(["inspect", bad, "--plugin", plugin], capsys)
    assert code == 2 and out == "" and "Traceback" not in err
    assert err.strip() == (f"impedax inspect: error: {bad}: the reader 'LAB split' of --plugin {plugin} ({helper}, line {RAISING_LINE}) "
                           "raised ValueError: could not convert string to float: 'oops'")


def test_the_same_reader_in_python_names_its_file_and_line(files, monkeypatch):
    plugin, bad, helper = files
    monkeypatch.syspath_prepend(str(helper.parent))
    from labhelper import read, sniff

    readers = register_reader(Reader("LAB split", (".lab",), sniff, read))
    with pytest.raises(ix.DataError) as caught:
        ix.load(bad, readers=readers)
    assert str(caught.value) == f"{bad}: the reader 'LAB split' ({helper}, line {RAISING_LINE}) raised ValueError: could not convert string to float: 'oops'"
    assert isinstance(caught.value.__cause__, ValueError)
    # an origin given in Python is named as the command line names a plugin's
    readers = register_reader(Reader("LAB split", (".lab",), sniff, read, origin=f"--plugin {helper}"))
    with pytest.raises(ix.DataError) as caught:
        ix.load(bad, readers=readers)
    assert str(caught.value) == f"{bad}: the reader 'LAB split' of --plugin {helper} (line {RAISING_LINE}) raised ValueError: could not convert string to float: 'oops'"


def test_a_reader_raising_without_a_message_ends_with_the_exception_name(tmp_path, capsys):
    """``raise KeyError()`` had left the command line's message ending in "raised KeyError: "."""
    plugin = tmp_path / "silent.py"
    plugin.write_text(textwrap.dedent('''\
        from impedax.io import Reader


        def read(path):
            raise RuntimeError()


        SILENT = Reader("silent", (".sil",), lambda path, head: path.suffix == ".sil", read)
    '''))
    data = tmp_path / "run.sil"
    data.write_text("anything\n")
    code, out, err = run(["inspect", data, "--plugin", plugin], capsys)
    assert code == 2 and out == "" and "Traceback" not in err
    assert err.strip() == f"impedax inspect: error: {data}: the reader 'silent' of --plugin {plugin} (line 5) raised RuntimeError"


def test_an_origin_that_is_not_text_is_refused():
    with pytest.raises(TypeError, match="origin must be text"):
        Reader("x", (".x",), lambda path, head: None, lambda path: None, origin=3)


def test_a_plugin_reader_returning_no_dataset_or_a_sniff_returning_a_number_names_the_plugin(tmp_path, capsys):
    """Its other faults are named with the plugin as its exceptions are: "reader 'none' returned
    NoneType" named no file (until 2026-12-06)."""
    plugin = tmp_path / "faulty.py"
    plugin.write_text(textwrap.dedent('''\
        from impedax.io import Reader

        NONE = Reader("none", (".non",), lambda path, head: path.suffix == ".non" or "not .non", lambda path: None)
        NUMBER = Reader("number", (".num",), lambda path, head: 1, lambda path: None)
    '''))
    data = tmp_path / "run.non"
    data.write_text("anything\n")
    code, out, err = run(["inspect", data, "--plugin", plugin], capsys)
    assert code == 2 and out == "" and "Traceback" not in err
    assert err.strip() == (f"impedax inspect: error: {data}: reader 'none' of --plugin {plugin} returned NoneType, not a spectrum Dataset "
                           "(build it with impedax.make_spectrum)")
    other = tmp_path / "run.txt"
    other.write_text("not a table\n")
    code, out, err = run(["inspect", other, "--plugin", plugin], capsys)
    assert code == 2 and f"reader 'number' of --plugin {plugin}: its sniff returned int 1" in err


NO_PATH_PLUGIN = textwrap.dedent('''\
    import impedax as ix
    from impedax.io import Reader


    def read(path):
        raise ix.DataError("no 'f;re;im' header line", line=1)


    LAB2 = Reader("lab2", (".lab2",), lambda path, head: path.suffix == ".lab2" or "not .lab2", read)
''')


def test_a_data_error_raised_without_its_path_names_the_file_and_its_line(tmp_path, capsys, monkeypatch):
    """docs/io.md asks readers for DataError(message, path=path, line=n); one that left out path=
    printed the message alone, "impedax inspect: error: no 'f;re;im' header line", its line=1 lost
    with the file (DataError shows a line only after a path). Now the file is given to it."""
    plugin = tmp_path / "lab2plugin.py"
    plugin.write_text(NO_PATH_PLUGIN)
    data = tmp_path / "x.lab2"
    data.write_text("x\n")
    code, out, err = run(["inspect", data, "--plugin", plugin], capsys)
    assert code == 2 and out == "" and "Traceback" not in err
    assert err.strip() == f"impedax inspect: error: {data}, line 1: no 'f;re;im' header line"
    monkeypatch.syspath_prepend(str(tmp_path))
    import lab2plugin

    with pytest.raises(ix.DataError) as caught:
        ix.load(data, readers=register_reader(lab2plugin.LAB2))
    assert str(caught.value) == f"{data}, line 1: no 'f;re;im' header line"
    assert (caught.value.path, caught.value.line) == (str(data), 1)
