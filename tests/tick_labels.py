"""What the figure tests read of tick labels: the visible ones in view, with their boxes on the
canvas (matplotlib's `get_window_extent`, the oracle for labels running into each other)."""


def labels_in_view(axis, renderer):
    """(text, box) of the visible, non-empty tick labels of ``axis`` (major and minor) in view."""
    lo, hi = sorted(axis.get_view_interval())
    out = []
    for tick in [*axis.get_major_ticks(), *axis.get_minor_ticks()]:
        label = tick.label1
        if label.get_visible() and label.get_text() and lo <= tick.get_loc() <= hi:
            out.append((label.get_text(), label.get_window_extent(renderer)))
    return out
