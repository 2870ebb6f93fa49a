"""What made a written result: impedax's version, the command and its settings, the data it read
and when it was written (docs/io.md, "Provenance"). One dict, `provenance`, that every writer
records the same way: the JSON key ``provenance``, the netCDF attributes ``impedax_version``,
``written_utc`` and ``provenance`` (the dict as JSON text), and in a CSV table the columns of
`provenance_columns` on every row (a ``#`` header would break ``csv.DictReader`` and
``numpy.genfromtxt(names=True)``, the documented ways to read these tables back).
"""

from __future__ import annotations

import datetime
import json
import os
from typing import Mapping, Sequence

from ..constants import IMPEDAX_VERSION

STDIN_NAME = "<stdin>"
"""Standard input (``-``) in ``data_files``, as `impedax.io.loader.STDIN_NAME` names it."""

__all__ = ["provenance", "provenance_columns", "provenance_attrs", "PROVENANCE_KEY", "PROVENANCE_ATTRS"]

LIST_SEPARATOR = "; "
"""Between a list setting's items in a CSV cell (`provenance_columns`)."""
PROVENANCE_KEY = "provenance"
"""The JSON key and netCDF attribute holding `provenance`."""
PROVENANCE_ATTRS = ("impedax_version", "written_utc", PROVENANCE_KEY)
"""The netCDF attributes of `provenance_attrs`: about the file, so a saved result read back
(`impedax.io.netcdf.saved_result`) leaves them out."""


def provenance(*, command: str | None = None, settings: Mapping[str, object] | None = None, source: str | Mapping[str, str] | None = None,
               data_files: Sequence[str] = ()) -> dict[str, object]:
    """What made a result: ``impedax_version`` (``impedax.__version__``), ``written_utc`` (now,
    ISO 8601 to the second with ``Z``), ``command`` (``impedax fit``; None from Python), its
    ``settings`` (option → value as used, defaults included), ``source`` (the data as the other
    outputs name them: ``path [DIM=LABEL]``, or one per input) and ``data_files`` (their
    absolute paths, so a file moved later is still named; standard input, ``-``, as ``<stdin>``)."""
    written = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0).isoformat().replace("+00:00", "Z")
    return {
        "impedax_version": IMPEDAX_VERSION,
        "written_utc": written,
        "command": command,
        "settings": dict(settings or {}),
        "source": dict(source) if isinstance(source, Mapping) else source,
        "data_files": [STDIN_NAME if p == "-" else os.path.abspath(p) for p in data_files if p],
    }


def _text(value) -> str | None:
    """A setting as one CSV cell: a list as its items joined by ``; `` (``R0 + R1 || C1; R0 +
    R1 || CPE1``; a list of lists, ``--init`` repeated, flattened: ``R0=1; R1=2; C1=3u``), a
    mapping as ``key=value`` joined by ``; ``, None as None (empty). Not a space, which circuit
    texts hold, nor a comma, which ``numpy.genfromtxt`` would split: ``cell.split("; ")``
    reads a list back."""
    if value is None:
        return None
    if isinstance(value, Mapping):
        return LIST_SEPARATOR.join(f"{k}={_text(v)}" for k, v in value.items())
    if isinstance(value, (list, tuple)):
        return LIST_SEPARATOR.join(str(_text(v)) for v in value)
    return value if isinstance(value, (bool, int, float)) else str(value)


def provenance_columns(record: Mapping[str, object]) -> dict[str, object]:
    """`provenance` as CSV columns, the same on every row: ``impedax_version``, ``written_utc``,
    ``command``, ``source``, ``data_files`` and one ``setting_NAME`` per setting."""
    columns = {key: _text(record.get(key)) for key in ("impedax_version", "written_utc", "command", "source", "data_files")}
    columns.update({f"setting_{name}": _text(value) for name, value in (record.get("settings") or {}).items()})
    return columns


def provenance_attrs(record: Mapping[str, object]) -> dict[str, str]:
    """`provenance` as netCDF attributes: ``impedax_version`` and ``written_utc`` as text, and
    the whole record as JSON text under ``provenance`` (``json.loads(ds.attrs["provenance"])``)."""
    return {"impedax_version": str(record["impedax_version"]), "written_utc": str(record["written_utc"]),
            PROVENANCE_KEY: json.dumps(record, default=_plain)}


def _plain(value):
    """A value `json` does not know (a numpy scalar or array, a path) as one it does."""
    item = getattr(value, "tolist", None)
    return item() if callable(item) else str(value)
