"""``impedax refine DATA [--model MODEL]``: add the missing effects one by one until the fit is adequate."""

from __future__ import annotations

# what --model defaults to (refine's `REFINE_START`; written out here so that the CLI's help needs
# no import of the fitting package, tests/test_cli_basic.py checks the two agree)
MODEL_DEFAULT = "R0 + R1 || C1"

PROGRESS_AFTER_S = 2.0
"""Progress lines go to stderr once a run has taken this long."""


def register(sub) -> None:
    from .diagnose import add_spectrum_command
    from .fit import add_max_steps_option

    p = add_spectrum_command(
        sub,
        "refine",
        help="diagnose, add the best missing effect, refit; repeat until adequate",
        description="Repeat diagnose -> apply the best significant effect -> refit until the verdict is adequate or --max-effects effects were added; "
        "prints the table of steps (the error falls step by step). The final model is refitted from scratch, as impedax fit does. See docs/diagnosis.md.",
        plot_help="save the data with the first and the last model (Nyquist), rms_rel per step and the residuals of every step",
        out_help="the refinement (.csv: the final fit's parameters)",
        run=run,
        model_default=MODEL_DEFAULT,
    )
    p.add_argument("--max-effects", type=int, default=4, metavar="N", help="most effects to add (default 4)")
    add_max_steps_option(p, 100, "the candidate fits of every step (the baseline fit keeps its own)")


def progress_printer(after_s: float = PROGRESS_AFTER_S, stream=None):
    """A progress callback that prints its lines to stderr (``stream``) once ``after_s`` seconds
    have passed. The last line said before then is printed at ``after_s`` if no other has come
    (the first diagnosis says its line at 0 s and may run for several seconds): a slow run is
    never silent past ``after_s``. Its ``close()`` ends the wait; a line is printed at most once."""
    return _Progress(after_s, stream)


class _Progress:
    def __init__(self, after_s: float, stream=None) -> None:
        import threading
        import time

        self._clock = time.monotonic
        self._start = self._clock()
        self._after_s = after_s
        self._stream = stream
        self._lock = threading.Lock()
        self._pending: tuple[float, str] | None = None
        self._timer = threading.Timer(after_s, self._flush)
        self._timer.daemon = True
        self._timer.start()

    def _print(self, elapsed: float, text: str) -> None:
        import sys

        print(f"[{elapsed:5.1f} s] {text}", file=self._stream or sys.stderr, flush=True)

    def _flush(self) -> None:
        with self._lock:
            if self._pending is not None:
                self._print(*self._pending)
                self._pending = None

    def __call__(self, text: str) -> None:
        elapsed = self._clock() - self._start
        with self._lock:
            if elapsed > self._after_s:
                if self._pending is not None:  # the timer has not run yet
                    self._print(*self._pending)
                self._pending = None
                self._print(elapsed, text)
            else:
                self._pending = (elapsed, text)

    def close(self) -> None:
        """No line after this: the run is over (its result is about to be printed)."""
        self._timer.cancel()
        with self._lock:
            self._pending = None


def run(args) -> int:
    from ..errors import ParameterError
    from ..fitting import refine
    from .common import figure_writer, load_selected, plan_outputs, print_result, result_writer
    from .diagnose import effects_option
    from .fit import check_max_steps

    outputs = plan_outputs([("--out", args.out, "result"), ("--plot", args.plot, "figure")], inputs=[args.data], stdout="--json" if args.json else None)
    if args.max_effects < 0:
        raise ParameterError(f"--max-effects must be 0 or more, got {args.max_effects}")
    solver_steps = check_max_steps(args.max_steps)
    effects = effects_option(args.effects)
    data = load_selected(args.data, args.select, single="impedax refine")
    progress = progress_printer()
    try:
        result = refine(
            data, args.model, max_effects=args.max_effects, solver_steps=solver_steps, effects=effects, weighting=args.weighting, noise=args.noise,
            fmin=args.fmin, fmax=args.fmax, progress=progress,
        )
    finally:
        progress.close()
    outputs.save({"--out": result_writer(result), "--plot": figure_writer(result.plot)})
    if not outputs.uses_stdout:
        print_result(result, args.json)
        line = reproduce_line(result, args)
        if line and not args.json:
            print(line)
    return 0


def reproduce_line(refinement, args=None) -> str | None:
    """The ``impedax fit`` command that reproduces the final fit from its values (with the
    run's --select, --weighting, --fmin, --fmax), when a note says a fit from scratch stops
    short of it (``(pass init=)``), else None."""
    import shlex

    if not any("(pass init=)" in note for note in refinement.notes):
        return None
    final = refinement.final
    options = []
    for option, attr in (("--select", "select"), ("--weighting", "weighting"), ("--fmin", "fmin"), ("--fmax", "fmax")):
        value = getattr(args, attr, None)
        for v in value if isinstance(value, list) else [value]:
            if v is not None:
                options.append(f"{option} {shlex.quote(str(v))}")
    starts = " ".join(f"--{'fix' if final.fixed[k] else 'init'} {k}={v:.6g}" for k, v in final.values.items())
    line = f"to reproduce the final fit from its values (a fit from scratch stops short of it): impedax fit DATA {' '.join(options + [''])}--model '{final.model}' {starts}"
    masked = len(refinement.masked_points)
    if masked:  # impedax fit has no option to leave points out
        line += f" (impedax fit keeps the {masked} point(s) the refinement left out, so its rms_rel differs)"
    return line
