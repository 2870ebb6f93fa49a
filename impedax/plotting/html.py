"""Results in a notebook: the compact HTML that the results' ``_repr_html_`` return.

One helper for every result: a title, an escaped table of rows and, when asked, a figure
inline as a base64 PNG (rendered off-screen with matplotlib's Agg canvas, then closed).
"""

from __future__ import annotations

import base64
import html
import io
import math
from typing import Callable, Mapping, Sequence

import numpy as np

__all__ = ["result_html"]


def _text(value) -> str:
    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return "" if math.isnan(value) else f"{value:.5g}"
    return str(value)


def figure_png(figure) -> str:
    """``figure`` (a matplotlib Figure) as base64 PNG text, drawn on an Agg canvas; closed after."""
    import matplotlib.pyplot as plt
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    try:
        FigureCanvasAgg(figure)
        buffer = io.BytesIO()
        figure.savefig(buffer, format="png", dpi=80)
    finally:
        plt.close(figure)
    return base64.b64encode(buffer.getvalue()).decode("ascii")


def result_html(title: str, rows: Sequence[Mapping[str, object]], *, lines: Sequence[str] = (), figure: Callable | None = None) -> str:
    """A compact HTML block: ``title`` (bold), the ``lines`` (one paragraph each), a table of
    ``rows`` (columns: the keys in order of first appearance) and, if ``figure`` is given, the
    Figure it returns as an inline PNG. Every text is HTML-escaped."""
    columns: dict[str, None] = {}
    for row in rows:
        columns.update(dict.fromkeys(row))
    parts = [f"<div class=\"impedax-result\"><p><b>{html.escape(title)}</b></p>"]
    parts += [f"<p>{html.escape(line)}</p>" for line in lines]
    if rows:
        head = "".join(f"<th>{html.escape(str(c))}</th>" for c in columns)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(_text(row.get(c)))}</td>" for c in columns) + "</tr>" for row in rows)
        parts.append(f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>")
    if figure is not None:
        parts.append(f"<img alt=\"{html.escape(title)}\" src=\"data:image/png;base64,{figure_png(figure())}\"/>")
    parts.append("</div>")
    return "".join(parts)
