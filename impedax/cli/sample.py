"""``impedax sample DATA --model MODEL``: Bayesian fit with emcee, credible intervals and diagnostics."""

from __future__ import annotations

import sys


def register(sub) -> None:
    from ..arguments import AUTO_MAX_STEPS, CHAIN_TAU_MULTIPLE, MIN_SAMPLER_STEPS, NOISE_MODELS, PRIOR_KINDS  # (the sampler's vocabulary, below JAX: --help imports no JAX)
    from .common import add_model_argument, add_output_options, add_plot_option, add_quiet_option, add_select_option, data_help, number_option, result_out_help
    from .fit import add_bound_option, add_exclude_option, add_shared_options

    p = sub.add_parser(
        "sample",
        help="Bayesian fit (emcee): posterior draws, credible intervals, diagnostics",
        description="Sample the posterior of MODEL's parameters given the spectrum in DATA with emcee, starting from a least-squares fit. Reports medians, 5/16/84/95 % quantiles, acceptance, autocorrelation times, effective sample sizes, Laplace log evidence and WAIC.",
    )
    p.add_argument("data", metavar="DATA", help=data_help("spectrum file"))
    add_select_option(p, several="with --shared")
    add_model_argument(p)
    p.add_argument("--walkers", type=int, metavar="N", help="number of walkers (even, at least 2 × parameters; default max(64, 4 × parameters))")
    p.add_argument("--steps", type=steps_option, default="auto", metavar="N|auto", help=f"steps per walker, at least {MIN_SAMPLER_STEPS}, or auto: until the chain after burn-in is {CHAIN_TAU_MULTIPLE} autocorrelation times long and τ has settled, at most {AUTO_MAX_STEPS} (default auto)")
    p.add_argument("--burn", type=int, metavar="N", help="steps discarded at the start (default a quarter of the steps run)")
    p.add_argument("--thin", type=int, default=1, metavar="N", help="keep every N-th step (default 1)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="random seed (default 0)")
    p.add_argument("--prior", action="append", metavar="NAME=KIND:ARGS", help="prior for one parameter; several after one --prior or --prior repeated, e.g. R1=loguniform:1e2,1e5; kinds: " + "; ".join(PRIOR_KINDS.values()))
    p.add_argument("--noise", default="proportional", type=noise_model_option, choices=[str(m) for m in NOISE_MODELS], help="; ".join(f"{k}: {v}" for k, v in NOISE_MODELS.items())
                   + " (default proportional; proportional noise is what impedax fit calls --weighting modulus, and the start fit is weighted so — "
                   "not fit's --weighting proportional, which divides Re by |Re Z| and Im by |Im Z|)")
    add_shared_options(p)
    p.add_argument("--fmin", type=number_option, help="ignore data below this frequency [Hz]")
    p.add_argument("--fmax", type=number_option, help="ignore data above this frequency [Hz]")
    add_exclude_option(p)
    p.add_argument("--fix", action="append", metavar="NAME=VALUE", help="hold a parameter fixed, in the start fit and the sampling; several after one --fix (--fix R1=1M R0=20) or --fix repeated")
    p.add_argument("--init", action="append", metavar="NAME=VALUE", help="starting value of the least-squares start fit; several after one --init (--init R1=43k C2=5u) or --init repeated; others are guessed from the data")
    add_bound_option(p, " in the start fit and the sampling (the support of its prior; not with --shared)")
    p.add_argument("--max-steps", type=int, default=None, metavar="N", help="Levenberg–Marquardt step limit of the least-squares start fit (default 400; --steps is the sampler's)")
    add_quiet_option(p)
    add_plot_option(p, "save a corner plot of the draws", flag="--corner")
    add_plot_option(p, "save a trace plot: each parameter's draws of every walker against the step, with their median; drift or a stuck walker shows a chain that has not converged; with --shared beyond 10 parameters those --corner draws by default", flag="--trace")
    p.add_argument("--corner-params", action="append", metavar="NAME[,NAME]", help="the parameters --corner draws, in that order (R1,CPE1.Q; with --shared R1[cycle=64]; repeatable; default every one, with --shared beyond 10 the shared ones, the first spectrum's and sigma_rel)")
    add_output_options(p, json="print the result as JSON (progress lines still go to stderr: --quiet drops them)", plot="save data with posterior bands (Nyquist, Bode)", out=result_out_help("the posterior (.nc: draws, diagnostics, start fit, data; .csv: quantiles per parameter)"))
    p.set_defaults(run=run)


# what emcee and the Posterior keep per walker, step and parameter: the chain, its copy after
# burn-in and thinning, and the draws in the result (float64)
CHAIN_BYTES_PER_VALUE = 3 * 8


def steps_option(text: str) -> int | str:
    """``--steps``: a number of steps, or ``auto``."""
    import argparse

    if text.strip().lower() == "auto":
        return "auto"
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid int value: {text!r} (give a number of steps, or auto)") from None


def check_steps(steps: int | str) -> None:
    """``--steps`` of ``impedax sample`` and ``impedax gap``: ``auto`` or at least
    `MIN_SAMPLER_STEPS`, else a `ParameterError` that says why, before any file is read."""
    from ..arguments import CHAIN_TAU_MULTIPLE, MIN_SAMPLER_STEPS
    from ..errors import ParameterError

    if steps != "auto" and steps is not None and steps < MIN_SAMPLER_STEPS:
        raise ParameterError(f"--steps must be at least {MIN_SAMPLER_STEPS} (got {steps}): a shorter chain keeps a few draws per walker near their start, "
                             f"too few for its quantiles and for τ and ESS; --steps auto runs until the chain is {CHAIN_TAU_MULTIPLE} τ long")


def noise_model_option(text: str) -> str:
    """``--noise``: the name of a noise model (argparse checks it against the choices). A level
    (``1%``, ``0.01``) is refused with where it belongs: the sampler samples the level."""
    import argparse

    from ..arguments import reads_as_number

    text = text.strip()
    if text == "modulus":  # (fit's weightings, reached for on sample: "invalid choice" would name no way on)
        raise argparse.ArgumentTypeError("'modulus' is a weighting of impedax fit: sample's --noise proportional is that weighting's noise model "
                                         "(σ_k = sigma_rel·|Z_k|, sigma_rel sampled; the start fit is weighted by |Z|); --noise sigma takes the data's own sigma")
    if text == "unit":
        raise argparse.ArgumentTypeError(f"{text!r} is a weighting of impedax fit: sample's noise models are proportional (σ_k = sigma_rel·|Z_k|, "
                                         "fit's --weighting modulus) and sigma (the data's own sigma)")
    if not reads_as_number(text):
        return text
    raise argparse.ArgumentTypeError(
        f"{text!r} is a noise level; sample's --noise is the noise model (proportional: the level is sampled, as sigma_rel; sigma: "
        "the data's own sigma). A level is what diagnose and refine take as --noise"
    )


def check_sample_size(circuit, walkers, steps, priors, registry=None) -> None:
    """Refuse, before any work, a run whose chain would not fit in memory (`check_memory`;
    ``--steps auto``: a chain as long as its cap)."""
    from ..errors import ParameterError
    from ..fitting.bayes.sampler import auto_step_cap
    from .common import check_memory

    check_steps(steps)
    if walkers is not None and walkers < 2:
        raise ParameterError(f"--walkers must be at least 2 (an even number, at least 2 × the sampled parameters), got {walkers}")
    dims = len(circuit.parameter_names(*(() if registry is None else (registry,)))) + 2  # + the noise parameter, + the log-probability
    chain_walkers = walkers if walkers is not None else max(64, 4 * dims)
    length = auto_step_cap(chain_walkers, dims - 1) if steps == "auto" else steps
    what = f"a chain of up to {length} steps (--steps auto) × {chain_walkers} walkers" if steps == "auto" else f"a chain of {steps} steps × {chain_walkers} walkers"
    check_memory("--steps", float(chain_walkers) * length * dims * CHAIN_BYTES_PER_VALUE, what)


def prefixed_prior(text: str) -> str:
    """``--prior`` text with its two numbers' SI prefixes applied (``R1=loguniform:1k,100k`` →
    ``R1=loguniform:1000.0,100000.0``), as every number of the command line takes them; text it
    cannot read is left for `parse_prior`'s message."""
    from .common import prefixed_number

    head, sep, numbers = text.rpartition(":")
    parts = numbers.split(",")
    if not sep or len(parts) != 2:
        return text
    try:
        return f"{head}:{','.join(repr(prefixed_number(p.strip())) for p in parts)}"
    except ValueError:
        return text


def check_corner_names(names, parameters, fixed, shared, noise) -> None:
    """A `ParameterError` for a ``--corner-params`` name the posterior will not have, before any
    work: the model's ``parameters`` not in ``fixed``, and ``sigma_rel`` with proportional noise;
    with ``shared`` (--shared) the shared ones by name and the others as NAME[LABEL] (the labels
    are checked against the data's once they are read: `check_corner_labels`). The
    names are checked before the start fit and the sampler's compilation, so that a
    ``--corner-params R7`` costs none of them."""
    from ..arguments import unknown_parameter
    from ..errors import ParameterError
    from ..fitting.bayes.logprob import NoiseModel
    from ..plotting.bayes import corner_params

    free = [n for n in parameters if n not in fixed]
    extra = ["sigma_rel"] if NoiseModel(str(noise)) is NoiseModel.PROPORTIONAL else []
    for name in names:
        if name in fixed:
            raise ParameterError(f"--corner-params: {name} is fixed (--fix), not sampled; the sampled parameters: {', '.join([*free, *extra]) if shared is None else ', '.join(_joint_names(free, shared, extra))}")
    if shared is None:
        corner_params(names, [*free, *extra], "--corner-params")
        return
    own = [n for n in free if n not in shared]
    for name in names:
        base, bracket, rest = name.partition("[")
        if not (name in shared or name in extra or (bracket and rest.endswith("]") and len(rest) > 1 and base in own)):
            raise unknown_parameter("--corner-params", name, _joint_names(free, shared, extra))


def check_corner_labels(names, data, over) -> None:
    """A `ParameterError` for a ``--corner-params`` NAME[LABEL] whose LABEL is none of the data's
    spectra along ``over`` (--over; None: the data's only extra dimension), once the data are read
    and before the start fit and the sampling (checked after it, ``R1[cycle=65]`` on the REAL
    battery cycles 0, 64, 129 would cost the whole run). Data whose dimensions ``over`` does not
    name are left to the fit's message."""
    from ..errors import ParameterError
    from ..fitting.bayes.shared_posterior import spectrum_labels

    extra = [d for d in data["Z"].dims if d != "frequency"]
    dims = list(over) if over is not None else extra
    if not dims or (len(dims) > 1 and over is None) or any(d not in extra for d in dims):
        return
    labels = spectrum_labels(data, dims)
    for name in names:
        base, bracket, rest = name.partition("[")
        if bracket and rest[:-1] not in labels:
            raise ParameterError(f"--corner-params: {name}: {rest[:-1]!r} is not a spectrum of the data along {', '.join(dims)} (labels: {', '.join(labels)}); give {base}[LABEL] with one of them")


def check_prior_names(priors, circuit, fixed, args, bounds=None, given_bounds=None) -> None:
    """A `ParameterError` naming ``--prior`` for a prior on a name that is no parameter of the
    circuit (nor ``sigma_rel``, the noise's scale; the sampler judges it against --noise), with the nearest
    name, or on a parameter ``fixed`` (--fix): before the data are read and the start is fitted,
    as --fix and --init are checked (the sampler's own message came after the start fit, without
    the option's name); a uniform or log-uniform prior reaching outside its element's bounds alike."""
    from ..arguments import number_text
    from ..errors import ParameterError
    from .common import check_parameter_names

    from ..fitting.bayes.priors import check_prior_inside

    check_parameter_names(priors, [*circuit.parameter_names(args.registry), "sigma_rel"], "--prior", args.model, args.registry, paper=getattr(args, "paper_model", None))
    specs = circuit.parameter_specs(args.registry)
    for name, prior in priors.items():
        if name in fixed:
            raise ParameterError(f"--prior {name}: {name} is fixed (--fix {name}={number_text(fixed[name])}), so it is not sampled; give one or the other")
        if name in specs:  # (a uniform or log-uniform prior within the element's bounds, then within --bound's: ``bounds``, `checked_bound_options`)
            try:
                check_prior_inside(name, prior, specs[name].lower, specs[name].upper, specs[name].upper_inclusive)
            except ParameterError as exc:
                raise ParameterError(str(exc).replace(f"prior for {name}: ", f"--prior {name}=", 1)) from None
            if bounds and name in bounds:
                lower, upper = bounds[name]
                try:
                    check_prior_inside(name, prior, lower, upper, upper == specs[name].upper and specs[name].upper_inclusive)  # (as the sampler takes --bound: its upper end excluded but where it is the element's own, included)
                except ParameterError as exc:
                    given = f" set by --bound {given_bounds[name][2]}" if given_bounds and name in given_bounds else ""
                    text = str(exc).replace(f"prior for {name}: ", f"--prior {name}=", 1).replace("the parameter's bounds", f"{name}'s bounds", 1)
                    raise ParameterError(f"{text}{given}") from None


def _joint_names(free, shared, extra) -> list[str]:
    """The names a joint posterior's parameters take (for a message): the shared ones, NAME[LABEL] for the others."""
    return [*(n for n in free if n in shared), *(f"{n}[LABEL]" for n in free if n not in shared), *extra]


def run(args) -> int:
    from .. import fit, parse, sample
    from ..errors import ParameterError
    from ..fitting import parse_prior
    from ..fitting.bayes.logprob import start_weighting
    from .common import check_bounds, check_parameter_names, checked_bound_options, comma_names, to_terminal, command_provenance, data_source, exclude_points, figure_options, figure_writer, load_selected, note_skipped_rows, note_unused_sigma, parse_assignments, parse_bounds, plan_outputs, print_result, result_writer, skipped_rows, WithSummaryKeys
    from .fit import check_max_steps, shared_arguments

    circuit = parse(args.model, args.registry)  # syntax errors before anything else
    sharing = shared_arguments(args)
    priors = {}
    for text in args.prior or ():
        read = prefixed_prior(text)
        try:
            name, prior = parse_prior(read)
        except ParameterError as exc:  # (in the words the user typed)
            raise ParameterError(str(exc).replace(repr(read), repr(text))) from None
        if name in priors:
            raise ParameterError(f"--prior: {name} given twice")
        priors[name] = prior
    corner_names = comma_names(args.corner_params) if args.corner_params is not None else None
    if corner_names is not None and args.corner is None:
        raise ParameterError("--corner-params chooses the parameters of --corner FILE: give --corner too")
    if corner_names == []:
        raise ParameterError("--corner-params: no parameter names given")
    outputs = plan_outputs(
        [("--out", args.out, "result"), ("--corner", args.corner, "figure"), ("--plot", args.plot, "figure"), ("--trace", args.trace, "figure")],
        inputs=[args.data], stdout="--json" if args.json else None,
    )
    check_sample_size(circuit, args.walkers, args.steps, priors, args.registry)
    init, fixed = parse_assignments(args.init, "--init"), parse_assignments(args.fix, "--fix")
    given_bounds = parse_bounds(args.bound)
    for flag, given in (("--init", init), ("--fix", fixed), ("--bound", given_bounds)):
        check_parameter_names(given, circuit.parameter_names(args.registry), flag, args.model, args.registry, paper=getattr(args, "paper_model", None))
    check_bounds(fixed, circuit.parameter_specs(args.registry), "--fix")  # (before the data are read and the start is fitted: nothing printed before the refusal)
    bounds = checked_bound_options(given_bounds, circuit.parameter_specs(args.registry), init=init, fixed=fixed)
    if sharing and (init or args.max_steps is not None):
        raise ParameterError("--init and --max-steps are not available with --shared (the joint posterior starts from its own global fit); --fix is available")
    if sharing and bounds:
        raise ParameterError("--bound is not available with --shared (the joint posterior samples within the elements' own bounds); --fix is available")
    check_bounds({k: v for k, v in init.items() if k not in given_bounds}, circuit.parameter_specs(args.registry), "--init")
    check_prior_names(priors, circuit, fixed, args, bounds, given_bounds)
    paper = getattr(args, "paper_model", None)
    max_steps = check_max_steps(args.max_steps) if args.max_steps is not None else None
    if corner_names is not None:  # (before the data are read, the start fitted and the sampler compiled)
        check_corner_names(corner_names, circuit.parameter_names(args.registry), fixed, sharing.get("shared"), args.noise)
    data = load_selected(args.data, args.select, single=None if sharing else "sample", readers=args.readers,
                         or_else="or sample them jointly with --shared NAMES (parameters one value for all, the others one per spectrum)")
    data = exclude_points(data, args.exclude)
    if corner_names is not None and sharing:
        check_corner_labels(corner_names, data, sharing.get("over"))
    if paper:  # (a paper model's values start the least-squares start fit, --init over them; said once, after every check: a refusal is the only line)
        from .common import paper_start, paper_start_note

        print(paper_start_note("sample", paper, args.model, args.paper_values, init, starts=not sharing, fixed=fixed, bounded=given_bounds), file=sys.stderr)
        init = init if sharing else paper_start(args.paper_values, init, held=[*fixed, *given_bounds])
    note_unused_sigma(data, "sample", str(args.noise) == "sigma", "--noise sigma")
    start = None
    if init or max_steps is not None:  # the least-squares start, as `sample` runs it, from the given values or step limit
        start = fit(circuit, data, init=init, fixed=fixed or None, bounds=bounds or None, weighting=start_weighting(args.noise), fmin=args.fmin, fmax=args.fmax, registry=args.registry,
                    **({"max_steps": max_steps} if max_steps is not None else {}))
    posterior = sample(
        circuit, data, priors=priors, noise=args.noise, walkers=args.walkers, steps=args.steps, burn=args.burn, thin=args.thin,
        seed=args.seed, fmin=args.fmin, fmax=args.fmax, progress=not args.quiet, init=start, fixed=fixed or None, bounds=bounds or None, registry=args.registry, **sharing,
    )
    source = data_source(data)
    # what the run settled itself (--steps auto, the default burn-in and walkers), beside the options as given
    chain = getattr(posterior, "settings", None) if isinstance(getattr(posterior, "settings", None), dict) else {}
    settled = {f"{k}_used": chain.get(k) for k in ("steps", "burn") if chain.get(k) is not None}
    if getattr(posterior, "n_walkers", None) is not None:
        settled["walkers_used"] = chain.get("walkers", posterior.n_walkers)  # (the run's: with straggler walkers left out, the draws hold fewer)
    record = command_provenance(args, source=source, data_files=[args.data], **settled)
    read = WithSummaryKeys(posterior, {"skipped_rows": skipped_rows(data), **({"paper_model": paper} if paper else {})})  # (the JSON's, as fit's and inspect --json's)
    if corner_names is not None:  # (before any output is written)
        from ..plotting.bayes import corner_params

        corner_params(corner_names, list(posterior.names), "--corner-params")
    outputs.save({"--out": result_writer(read, source, record), "--corner": figure_writer(lambda: posterior.corner(params=corner_names), source, **figure_options(args)), "--plot": figure_writer(lambda: posterior.plot(), source, **figure_options(args)),
                  "--trace": figure_writer(lambda: posterior.trace(), source, **figure_options(args))})
    if not outputs.uses_stdout:
        with to_terminal(not args.json, table_head="parameter "):  # (wrapped at words on a terminal, as diagnose's report; the table kept)
            print_result(read, args.json, source, record, command="sample")
            if not args.json:
                note_skipped_rows(data, "sample", args.data)
    if posterior.warnings:  # (--quiet drops progress lines only: warnings are said, as gap says them)
        print(f"impedax sample: {len(posterior.warnings)} warning(s); see the {'JSON' + chr(39) + 's warnings' if args.json else 'report'}", file=sys.stderr)
    return 0
