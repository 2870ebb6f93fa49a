"""Circuit diagrams: every topology draws, every element's name is in the SVG text."""

import re
import sys

import pytest

import impedax as ix
from impedax.cli import main
from impedax.diagram import draw_circuit, save_circuit_diagram

pytest.importorskip("schemdraw")

TOPOLOGIES = [
    "R1",
    "R_f + R_sc || CPE_sc",
    "R0 + C1 + L1 + CPE1 + Q1 + W1 + Wo1 + Ws1 + G1 + CC1 + HN1",  # every element kind
    "R0 || C0 || L0 || W0",
    "(R1 + (R2 || (R3 + (R4 || (R5 + (R6 || (R7 + C7))))))) || C1",  # deeply nested
    "R_EP || C_EP || C_gap + (R_s + C_s) || (R_t + (C_t || L_t))",
]


@pytest.mark.parametrize("model", TOPOLOGIES)
@pytest.mark.parametrize("suffix", [".svg", ".png"])
def test_every_topology_draws_with_all_labels(tmp_path, model, suffix):
    path = tmp_path / f"c{suffix}"
    save_circuit_diagram(model, path)
    assert path.stat().st_size > 500
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # no temporary file left
    if suffix == ".svg":
        texts = re.findall(r"<text[^>]*>([^<]*)", path.read_text())
        for name in ix.parse(model).element_names:
            assert name in texts


def test_values_are_printed_with_units(tmp_path):
    path = tmp_path / "v.svg"
    save_circuit_diagram("R_f + R_sc || CPE_sc + C_gap", path, values={"R_sc": 130e3, "CPE_sc.alpha": 0.8, "C_gap": 413e-12})
    texts = re.findall(r"<text[^>]*>([^<]*)", path.read_text())
    assert "130 kΩ" in texts and "413 pF" in texts and "α=0.8" in texts


def test_unknown_value_name_and_bad_format(tmp_path):
    with pytest.raises(ix.ParameterError, match="R9"):
        draw_circuit("R1 + C1", {"R9": 1.0})
    with pytest.raises(ix.DataError, match="use .png, .svg or .pdf"):
        save_circuit_diagram("R1", tmp_path / "c.jpg")
    assert list(tmp_path.iterdir()) == []


def test_missing_schemdraw_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "schemdraw", None)
    with pytest.raises(ix.ImpedaxError, match=r"pip install impedax\[draw\]"):
        draw_circuit("R1")


def test_cli_draw(tmp_path, capsys):
    out = tmp_path / "d.svg"
    assert main(["draw", "R_f + R_sc || C_sc", "-o", str(out), "--param", "R_sc=1e5"]) == 0
    assert "100 kΩ" in out.read_text() and f"wrote {out}" in capsys.readouterr().err  # (every command says so on stderr)


def _wire_junctions_without_dot(fig):
    """Points where three or more wire directions meet and no filled dot sits, read back from
    the figure's lines and circles (not from the layout code)."""
    import math

    import numpy as np
    from matplotlib.patches import Circle

    ax = fig.axes[0]
    segments, wire_ends = [], set()
    for line in ax.lines:
        xy = line.get_xydata()
        runs = np.split(xy, np.where(np.isnan(xy[:, 0]))[0])
        runs = [r[~np.isnan(r[:, 0])] for r in runs]
        for run in runs:
            segments += [(tuple(a), tuple(b)) for a, b in zip(run[:-1], run[1:]) if not np.allclose(a, b)]
        straight = len(runs) == 1 and (np.ptp(xy[:, 0]) < 1e-9 or np.ptp(xy[:, 1]) < 1e-9)
        if straight:  # a plain wire (elements are zigzags, boxes, plates)
            wire_ends |= {tuple(np.round(xy[0], 6)), tuple(np.round(xy[-1], 6))}
    dots = [tuple(np.round(p.center, 6)) for p in ax.patches if isinstance(p, Circle) and p.get_facecolor()[:3] == (0.0, 0.0, 0.0)]

    def arms(point):
        directions = set()
        for a, b in segments:
            for start, end in ((a, b), (b, a)):
                if math.dist(start, point) < 1e-6:
                    d = np.subtract(end, start)
                    directions.add(tuple(np.round(d / np.hypot(*d), 3)))
            ab, ap = np.subtract(b, a), np.subtract(point, a)
            t = np.dot(ap, ab) / np.dot(ab, ab)
            if 1e-6 < t < 1 - 1e-6 and abs(ab[0] * ap[1] - ab[1] * ap[0]) < 1e-6:  # passes through
                u = ab / np.hypot(*ab)
                directions |= {tuple(np.round(u, 3)), tuple(np.round(-u, 3))}
        return len(directions)

    return sorted((float(x), float(y)) for x, y in wire_ends if arms((x, y)) >= 3 and not any(math.dist((x, y), d) < 1e-6 for d in dots))


@pytest.mark.parametrize("model", [
    "R0 + L1 + (R1 || (C1 + R2 || CPE2)) + R3 || (W3 + C3) || (R4 + Wo4) + Ws5 || CC5 + HN6 + G7",
    "R0 || C0 || L0 || W0",  # middle branches join the rails at T junctions
    "R1 || C1 + R2 || C2",  # two parallel blocks side by side
    *TOPOLOGIES,
])
def test_every_wire_junction_carries_a_dot(model):
    import matplotlib.pyplot as plt

    fig = draw_circuit(model)
    try:
        assert _wire_junctions_without_dot(fig) == []
    finally:
        plt.close(fig)


def _label_boxes(fig):
    """Each text of the figure with its box in data units, measured by matplotlib's renderer
    (not by the layout code)."""
    ax = fig.axes[0]
    fig.canvas.draw()  # (limits and aspect as drawn, as a saved file has them)
    renderer = fig.canvas.get_renderer()
    to_data = ax.transData.inverted()
    return [(t.get_text(), t.get_window_extent(renderer).transformed(to_data)) for t in ax.texts if t.get_text().strip()]


def _vertical_wires(fig):
    """The vertical wires (rails) of the figure as (x, y_low, y_high), from its lines."""
    import numpy as np

    wires = []
    for line in fig.axes[0].lines:
        xy = line.get_xydata()
        if len(xy) >= 2 and not np.isnan(xy).any() and np.ptp(xy[:, 0]) < 1e-9 and np.ptp(xy[:, 1]) > 1e-9:
            wires.append((float(xy[0, 0]), float(xy[:, 1].min()), float(xy[:, 1].max())))
    return wires


LONG_NAMES = [
    ("R_electrolyte + R_charge_transfer || CPE_double_layer + (R_a + R_b || C_b) || (R_c + R_d || C_d)",
     {"R_electrolyte": 12.3, "R_charge_transfer": 1234567.0, "CPE_double_layer.Q": 1.5e-5, "CPE_double_layer.alpha": 0.87}),
    ("R_electrolyte_solution_bulk + R_charge_transfer_anode || CPE_double_layer_anode + Ws_diffusion_in_particles", {"Ws_diffusion_in_particles.tau": 12.5}),
    ("R0 + L0 + (R1 + W1) || CPE1 + R2 || (C2 + R3 || CPE3) + R4 || C4 + G1 + Ws1", {}),
]


@pytest.mark.parametrize("model, values", LONG_NAMES)
def test_labels_neither_overlap_nor_cross_a_wire(model, values):
    """Walkthrough 2026-12-06: a circuit of 10 elements was drawn shrunk into matplotlib's
    default 6.4 × 4.8 in under labels of full size, so 'R_electrolyte' and 'R_charge_transfer'
    ran into one another and 'CPE_double_layer' over both rails of its group. Every label's
    box, as matplotlib measures it, is now clear of every other and of every vertical wire."""
    import matplotlib.pyplot as plt

    fig = draw_circuit(model, values)
    try:
        boxes = _label_boxes(fig)
        assert {text for text, _ in boxes} >= set(ix.parse(model).element_names)
        for i, (a, box_a) in enumerate(boxes):
            for b, box_b in boxes[i + 1:]:
                assert not box_a.overlaps(box_b), f"{a!r} overlaps {b!r}"
            for x, low, high in _vertical_wires(fig):
                crosses = box_a.x0 < x < box_a.x1 and box_a.y0 < high and low < box_a.y1
                assert not crosses, f"{a!r} crosses the wire at x = {x:g}"
    finally:
        plt.close(fig)


def test_labels_keep_their_size_beside_the_parts_in_a_small_and_a_wide_circuit():
    """The name of a resistor is as tall, against the resistor's own length, in 'R1' alone as in
    a circuit of 10 elements: the drawing has one scale (before 2026-12-06 the figure kept
    matplotlib's default size, so a small circuit was blown up and a wide one shrunk)."""
    import matplotlib.pyplot as plt

    heights = []
    for model in ("R1", LONG_NAMES[2][0]):
        fig = draw_circuit(model)
        try:
            heights.append(dict(_label_boxes(fig))["R1"].height)
        finally:
            plt.close(fig)
    assert heights[1] == pytest.approx(heights[0], rel=0.02)


def test_values_of_named_parameters_carry_their_units(tmp_path):
    """A parameter written with its name (an element of several) carries its unit with an SI
    prefix, as a fit's report writes it (walkthrough 2026-12-06: 'τ=0.001', 'Q=2e-05', 'σ=3',
    a unit for the resistances only): τ = 1e-3 s is 1 ms, Q = 2e-5 F s^(α-1) is 20 µF s^(α-1)."""
    path = tmp_path / "u.svg"
    save_circuit_diagram("R_s + (R_ct + W_d) || CPE_dl + G1", path, values={"CPE_dl.Q": 2e-5, "CPE_dl.alpha": 0.85, "W_d.sigma": 3.0, "G1.R": 50.0, "G1.tau": 1e-3})
    texts = "\n".join(re.findall(r"<text[^>]*>([^<]*)", path.read_text()))
    for shown in ("Q=20 µF s^(α-1)", "α=0.85", "σ=3 Ω s^-1/2", "R=50 Ω", "τ=1 ms"):
        assert shown in texts


def test_an_element_drawn_as_a_part_schemdraw_lacks_is_told_the_part_meant():
    """A user's element declared with draw='Resistr' (a typo): the message names the field and
    the schemdraw part it most likely meant, which schemdraw has (walkthrough 2026-12-06: only
    "which schemdraw does not have")."""
    import schemdraw.elements as elm

    spec = ix.ElementSpec("Kd", "drawn element", "Z = R", (ix.ParameterSpec("R", "Ohm", 1.0),), lambda w, r: r + 0 * w, draw="Resistr")
    registry = ix.DEFAULT_REGISTRY.register(spec)
    assert hasattr(elm, "Resistor")
    with pytest.raises(ix.ImpedaxError) as caught:
        draw_circuit("R0 + Kd1", registry=registry)
    assert str(caught.value).startswith("element Kd (drawn element) is drawn as 'Resistr' (its ElementSpec's draw=), which schemdraw does not have: did you mean 'Resistor'?")


def test_a_wire_and_the_lead_of_a_part_meet_on_one_pixel_row():
    """The terminal's wire and the resistor's lead lie on one line (y = 0); rendered at 150 dpi,
    they cover the same pixel rows (walkthrough 2026-12-06: straight wires were snapped to the
    pixel grid and the parts' leads were not, a visible one-pixel step at every joint)."""
    import matplotlib.pyplot as plt
    import numpy as np

    fig = draw_circuit("R1 + R2")
    try:
        fig.set_dpi(150)
        fig.canvas.draw()
        image = np.asarray(fig.canvas.buffer_rgba())[:, :, :3].mean(axis=2)
        ax = fig.axes[0]

        def dark_rows(x):  # the dark pixel rows of the column at data x, near y = 0
            px, py = ax.transData.transform((x, 0.0))
            column, y0 = image[:, int(round(px))], int(round(image.shape[0] - py))
            return [i for i in range(y0 - 6, y0 + 7) if column[i] < 128]

        wire, lead = dark_rows(0.3), dark_rows(1.2)  # the terminal's wire (0 to 0.75), R1's lead (from 0.75)
        assert wire and wire == lead
    finally:
        plt.close(fig)
