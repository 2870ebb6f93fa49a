"""What a write does to the file it replaces (impedax.io.atomic, every writer): the permission
bits are kept, a read-only file is refused and kept, a symbolic link is written through.
Oracles: the mode bits set here, the data saved (read back), os.readlink."""

import os
import stat

import numpy as np
import pytest

import impedax as ix
from impedax.cli import main

FREQ = np.geomspace(1.0, 1e5, 21)


def spectrum(r1: float = 1e3):
    return ix.make_spectrum(FREQ, 10.0 + r1 / (1 + 1j * 2 * np.pi * FREQ * r1 * 1e-6))


def mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


@pytest.mark.parametrize("name", ["private.csv", "private.nc"])
def test_replacing_a_private_file_keeps_it_private(tmp_path, name):
    """A 0600 file had become 0644 (world-readable) when saved over."""
    path = tmp_path / name
    ix.save(spectrum(), path)
    os.chmod(path, 0o600)
    ix.save(spectrum(2e3), path)
    assert mode(path) == 0o600
    assert ix.load(path)["Z"].values == pytest.approx(spectrum(2e3)["Z"].values)
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


def test_the_command_line_keeps_the_bits_and_a_new_file_gets_the_umask(tmp_path, capsys):
    kept, new = tmp_path / "kept.csv", tmp_path / "new.csv"
    kept.write_text("an earlier spectrum\n")
    os.chmod(kept, 0o600)
    old_umask = os.umask(0o027)
    try:
        assert main(["simulate", "R1 + C1", "--out", str(kept)]) == 0
        assert main(["simulate", "R1 + C1", "--out", str(new)]) == 0
    finally:
        os.umask(old_umask)
    capsys.readouterr()
    assert mode(kept) == 0o600 and kept.read_text().startswith("frequency_hz,")
    assert mode(new) == 0o666 & ~0o027


def test_a_read_only_file_is_refused_and_kept(tmp_path):
    """A 0444 file had been replaced silently. Refused by its bits: the tests run as root,
    for whom os.access says every file is writable."""
    path = tmp_path / "frozen.csv"
    path.write_text("kept\n")
    os.chmod(path, 0o444)
    with pytest.raises(ix.DataError) as info:
        ix.save(spectrum(), path)
    assert str(info.value) == f"{path}: is read-only, mode 444: impedax does not replace it; make it writable (chmod u+w) or choose another name"
    assert path.read_text() == "kept\n" and mode(path) == 0o444
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frozen.csv"]
    os.chmod(path, 0o644)  # (writable again: replaced)
    ix.save(spectrum(), path)
    assert path.read_text().startswith("frequency_hz,")


def test_saving_to_a_symlink_writes_the_file_it_points_to(tmp_path, monkeypatch):
    """The link had been replaced by a regular file and its target left as it was."""
    monkeypatch.chdir(tmp_path)
    ix.save(spectrum(), "real.csv")
    os.symlink("real.csv", "link.csv")
    ix.save(spectrum(2e3), "link.csv")
    assert os.path.islink("link.csv") and os.readlink("link.csv") == "real.csv"
    assert ix.load("real.csv")["Z"].values == pytest.approx(spectrum(2e3)["Z"].values)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.csv", "real.csv"]
    # through the command line's output transaction as well
    os.symlink("real.nc", "result-link.nc")
    assert main(["inspect", "real.csv", "--out", "result-link.nc"]) == 0
    assert os.path.islink("result-link.nc") and ix.load("real.nc")["Z"].values == pytest.approx(spectrum(2e3)["Z"].values)


def test_a_link_to_a_read_only_file_is_refused_naming_both(tmp_path):
    target = tmp_path / "frozen.csv"
    target.write_text("kept\n")
    os.chmod(target, 0o444)
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    with pytest.raises(ix.DataError, match=rf"^{link}: is read-only \(the file {target} it links to\)"):
        ix.save(spectrum(), link)
    assert target.read_text() == "kept\n" and link.is_symlink()


def test_an_unstorable_attribute_leaves_no_file(tmp_path):
    """xarray's TypeError had leaked; now one DataError naming the attribute, and no file
    (an earlier one at that path is kept)."""
    path = tmp_path / "a.nc"
    with pytest.raises(ix.DataError, match=rf"^{path}: attribute 'thing' of the dataset is <object object"):
        ix.save(spectrum().assign_attrs(thing=object()), path)
    with pytest.raises(ix.DataError, match=r"attribute 'when' of variable 'Z' is"):
        data = spectrum()
        data["Z"].attrs["when"] = 1 + 2j
        ix.save(data, path)
    assert list(tmp_path.iterdir()) == []
