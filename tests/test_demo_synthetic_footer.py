"""Every figure the demo writes says its data are SYNTHETIC (`impedax.demo.synthetic_footer`)."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from impedax.demo import SYNTHETIC_FOOTER, synthetic_footer  # noqa: E402


@pytest.fixture
def fig():
    figure, axes = plt.subplots(1, 2, layout="constrained")
    for ax in axes:
        ax.set_xlabel("frequency [Hz]")
    yield figure
    plt.close(figure)


def footer_of(fig):
    return [text for text in fig.texts if text.get_text() == SYNTHETIC_FOOTER]


def test_a_figure_gets_the_synthetic_line_under_its_axes(fig):
    synthetic_footer(fig)
    assert "SYNTHETIC" in SYNTHETIC_FOOTER
    (footer,) = footer_of(fig)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    line = footer.get_window_extent(renderer)
    for ax in fig.axes:  # (below every axis label, inside the figure)
        assert line.y1 <= ax.xaxis.label.get_window_extent(renderer).y0 + 0.5
    assert line.y0 >= 0 and line.x0 >= 0 and line.x1 <= fig.bbox.x1


def test_an_alarm_heading_keeps_its_words_and_style(fig):
    fig.suptitle("SAMPLING UNRELIABLE: the bands may be wrong", color="tab:red", fontweight="bold")
    synthetic_footer(fig)
    assert fig.get_suptitle() == "SAMPLING UNRELIABLE: the bands may be wrong"
    (footer,) = footer_of(fig)
    assert footer.get_color() != "tab:red" and footer.get_fontweight() == "normal"


def test_a_figure_that_says_it_already_is_left_as_it_is(fig):
    fig.axes[1].set_title("Force on the finger (SYNTHETIC data)")
    synthetic_footer(fig)
    assert footer_of(fig) == []


def test_applied_twice_it_says_it_once(fig):
    synthetic_footer(fig)
    synthetic_footer(fig)
    assert len(footer_of(fig)) == 1
