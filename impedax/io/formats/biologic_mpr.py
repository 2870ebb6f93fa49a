"""BioLogic EC-Lab binary ``.mpr`` files, through the optional ``galvani`` package.

galvani is GPL-licensed; impedax does not depend on it and imports it only when a ``.mpr`` is
read (``pip install galvani``). Without it, export ``.mpt`` from EC-Lab instead.

Conventions: the impedance module's columns ``freq/Hz``, ``Re(Z)/Ohm`` and ``-Im(Z)/Ohm`` (the
file stores −Z'', negated here), as in the ``.mpt`` export; its ``|Z|/Ohm`` and ``Phase(Z)/deg``
are compared with them (``attrs["polar_columns_note"]`` where they disagree, as for ``.mpt``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from ...errors import DataError
from .._common import column_entry, finish, optional_module
from ..consistency import float_cells, polar_columns_attrs
from ..registry import Reader

__all__ = ["read_biologic_mpr", "READER"]

CONVENTIONS = "binary; via optional galvani (GPL); freq/Hz, Re(Z)/Ohm, -Im(Z)/Ohm negated"
MAGIC = b"BIO-LOGIC MODULAR FILE"


def sniff(path: Path, head: bytes) -> str | None:
    return None if head.startswith(MAGIC) else "no 'BIO-LOGIC MODULAR FILE' signature"


def read_biologic_mpr(path: str | Path) -> xr.Dataset:
    """Read the impedance columns of an EC-Lab ``.mpr`` (see module docstring)."""
    path = Path(path)
    galvani = optional_module("galvani", path, "reading a binary .mpr needs the optional galvani package (GPL): pip install galvani, or export .mpt from EC-Lab")
    try:
        data = galvani.BioLogic.MPRfile(str(path)).data
    except Exception as exc:  # galvani raises ValueError, NotImplementedError, struct.error ...
        raise DataError(f"galvani cannot read this .mpr ({type(exc).__name__}: {exc})", path=path) from None
    names = data.dtype.names or ()
    missing = [n for n in ("freq/Hz", "Re(Z)/Ohm", "-Im(Z)/Ohm") if n not in names]
    if missing:
        raise DataError(f"no impedance columns {missing} in this .mpr (found {list(names)[:8]})", path=path)
    freq = np.asarray(data["freq/Hz"], dtype=float)
    z = np.asarray(data["Re(Z)/Ohm"], dtype=float) - 1j * np.asarray(data["-Im(Z)/Ohm"], dtype=float)
    bad = np.flatnonzero(~np.isfinite(freq) | ~np.isfinite(z))
    if bad.size:
        raise DataError(f"point {bad[0]} is not finite", path=path)
    attrs = {"format": "BioLogic EC-Lab mpr", "instrument": "BioLogic",
             "sign_convention": "-Im(Z)/Ohm holds -Z''; negated to Z''", "units": "Hz, ohm",
             "columns": {"frequency": column_entry("frequency", "freq/Hz", "Hz"), "z_real": column_entry("z_real", "Re(Z)/Ohm", "Ohm"),
                         "z_imag": column_entry("z_imag", "-Im(Z)/Ohm", "Ohm", negated=True)}}
    attrs.update(_polar_attrs(data, names, z, path))
    return finish(path, freq, z, list(range(1, freq.size + 1)), attrs)


def _polar_attrs(data, names, z: np.ndarray, path: Path) -> dict[str, str]:
    """``polar_columns_note`` (`consistency.polar_columns_attrs`) when the record's ``|Z|/Ohm``
    or ``Phase(Z)/deg`` disagrees with Z read from ``Re(Z)/Ohm`` and ``-Im(Z)/Ohm`` beyond the
    rounding of their stored floats; ``{}`` when they agree or neither column is there. Points
    are counted from 0, as the reader's other messages count them."""
    polar = {role: np.asarray(data[name]) for role, name in (("modulus", "|Z|/Ohm"), ("phase", "Phase(Z)/deg")) if name in names}
    if not polar:
        return {}
    stored = {"real": np.asarray(data["Re(Z)/Ohm"]), "imag": np.asarray(data["-Im(Z)/Ohm"]), **polar}
    names = {"real": "Re(Z)/Ohm", "imag": "-Im(Z)/Ohm", "modulus": "|Z|/Ohm", "phase": "Phase(Z)/deg"}
    return polar_columns_attrs(z, polar["modulus"].astype(float) if "modulus" in polar else None, polar["phase"].astype(float) if "phase" in polar else None,
                               range(z.size), names, {role: 1.0 for role in names}, float_cells(stored), path.name, position="point")


READER = Reader("BioLogic EC-Lab mpr", (".mpr",), sniff, read_biologic_mpr, CONVENTIONS)
