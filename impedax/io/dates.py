"""An instrument file's date as the readers record it (``attrs["date"]``): ISO 8601 when the file
establishes it, else as written with ``attrs["date_note"]`` saying why (docs/io.md, "What the
instrument's file says").

Instruments write dates in the order of the computer's locale and do not name it: ``02/04/2018``
is 4 February (month first, MM/DD/YYYY) or 2 April (day first, DD/MM/YYYY). The order is taken as
established when only one reading makes every date of the file a calendar date (a day above 12 in
any of them), or the year comes first; a month written as a name (``Feb. 20, 2020``) is read as such.
"""

from __future__ import annotations

import datetime
import re
from typing import Sequence

__all__ = ["record_date"]

#: Day, month and year in an order the file does not name, or year first, then an optional time:
#: ``02/04/2018 10:02:46``, ``06/15/2023 16:30:52.260``, ``10-12-2018 11:04:34``, ``2018-04-02 10:02:46``.
_NUMERIC = re.compile(r"(\d{1,4})([/.-])(\d{1,2})\2(\d{1,4})(?:[ T]+(\d{1,2})(:\d{2}(?::\d{2}(?:[.,]\d+)?)?))?")
#: A month by name: ``Feb. 20, 2020 15:55:08`` (CH Instruments).
_NAMED = re.compile(r"([A-Za-z]{3})[a-z]*\.?\s+(\d{1,2}),?\s+(\d{4})(?:\s+(\d{1,2})(:\d{2}(?::\d{2}(?:[.,]\d+)?)?))?")
_MONTHS = {name: k + 1 for k, name in enumerate(("jan", "feb", "mar", "apr", "may", "jun", "jul", "aug", "sep", "oct", "nov", "dec"))}
ORDERS = {"month first": "MM/DD/YYYY", "day first": "DD/MM/YYYY"}


def _iso(year: str, month: str | int, day: str, hour: str | None, rest: str | None) -> str | None:
    """ISO 8601 of a date (and time) given as text; None when it is no calendar date."""
    if len(year) != 4 or len(str(month)) > 2 or len(day) > 2:
        return None
    try:
        text = datetime.date(int(year), int(month), int(day)).isoformat()
    except ValueError:
        return None
    return text if hour is None else f"{text}T{int(hour):02d}{rest.replace(',', '.')}"


def _read(date: re.Match, order: str) -> str | None:
    """A `_NUMERIC` ``date`` in ISO 8601 read in ``order`` (a key of `ORDERS`, or "year first")."""
    first, _, second, third, hour, rest = date.groups()
    if order == "year first":
        return _iso(first, second, third, hour, rest)
    month, day = (first, second) if order == "month first" else (second, first)
    return _iso(third, month, day, hour, rest)


def record_date(attrs: dict, dates: Sequence[str]) -> None:
    """``attrs["date"]`` from ``dates``, the date fields of one file (its start first, then any
    other written in the same convention: calibration dates, a technique's start): ISO 8601
    (``2023-06-15T16:30:52.260``) when the order of day and month is established, the text as
    written then kept as ``attrs["date_as_written"]``; else the first as written, and
    ``attrs["date_note"]`` says why (both readings of ``02/04/2018``)."""
    written = dates[0]
    attrs["date"] = written
    named = _NAMED.fullmatch(written)
    if named and named.group(1).lower() in _MONTHS:
        month_name, day, year, hour, rest = named.groups()
        iso = _iso(year, _MONTHS[month_name.lower()], day, hour, rest)
        if iso:
            attrs["date"], attrs["date_as_written"] = iso, written
            return
    found = [_NUMERIC.fullmatch(d) for d in dates]
    if not all(found):
        attrs["date_note"] = f"{written!r} is not read as a date (day, month and year with '/', '-' or '.', or a month by name); kept as written"
        return
    if all(len(m.group(1)) == 4 for m in found):
        orders = ["year first"] if all(_read(m, "year first") for m in found) else []
    else:
        orders = [order for order in ORDERS if all(_read(m, order) for m in found)]
    if len(orders) == 1:
        attrs["date"], attrs["date_as_written"] = _read(found[0], orders[0]), written
    elif not orders:
        attrs["date_note"] = f"{written!r} is no date read month first ({ORDERS['month first']}) nor day first ({ORDERS['day first']}); kept as written"
    else:
        readings = " or ".join(f"{_read(found[0], order)} ({order}, {ORDERS[order]})" for order in orders)
        attrs["date_note"] = (f"{written!r} is ambiguous: {readings}; no day above 12 in the file's dates "
                              f"({', '.join(repr(d) for d in dict.fromkeys(dates))}) tells which; kept as written")
