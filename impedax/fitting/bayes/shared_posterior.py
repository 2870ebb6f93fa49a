"""The joint posterior of a global fit: parameters shared across spectra and per-spectrum ones.

`sample(..., shared=[...], over="trial")` samples, with emcee, every shared parameter once,
every other free parameter once per spectrum along ``over``, and (proportional noise) one
``sigma_rel`` common to all spectra:

    ln p(y | data) = ln π(y) + Σ_i Σ_k ln N(Re r_ik; 0, σ_ik²) + ln N(Im r_ik; 0, σ_ik²),
    r_ik = Z_model(f_k; s, a_i) − Z_data,ik,

with the same noise models, priors and log sampling of positive parameters as a single
spectrum's posterior (`logprob`). The walkers start around the global least-squares fit
(`least_squares.shared`) as a single spectrum's do (`chain.start_walkers`): in a small ball,
spread over their prior where the fit leaves a parameter undetermined, all strictly inside the
supports. emcee's ensemble moves scale poorly with dimension, so the number of
sampled parameters is limited to `MAX_JOINT_PARAMETERS` (a few spectra).

`SharedPosterior.to_xarray` stores the draws with the data and the start fit (`impedax.write_result`
to .nc); `SharedPosterior.from_xarray` rebuilds the result from the file (`impedax.load`).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import Callable, Mapping, NamedTuple, Sequence

import jax
import jax.numpy as jnp
import numpy as np
import xarray as xr

from ...circuits import Circuit, DEFAULT_REGISTRY, Registry, compile_circuit, parse
from ...errors import DataError, ParameterError
from ...io.netcdf import result_dataset
from ...data import checked_frequencies, column_width, concise_repr, counted, exact_number, report_text, unit_text
from ...warning_groups import grouped_warning_tags, grouped_warnings
from ..derived import draw_indices, draws_band, needs_freq
from ..least_squares import SharedFitResult, fit
from ..least_squares.batch import stored_batch_tags
from ..least_squares.branches import left_to_priors
from ..least_squares.notes import tags_attr
from ..least_squares.result import PARAMETER_UNIT_NAME, parameter_groups, without_sample_advice
from ..parameters import ParameterTable
from ..problem import SIGMA_SOURCES, open_spectrum
from ..frozen import FrozenResult, KeyHintDict, freeze_fields
from .diagnostics import NO_STRAGGLERS, PiledUp, WalkerDraws, circuit_name, Stragglers, chain_warnings, draws_table, figure, interval_warnings, kept_walkers, straggler_warnings, tied_to_bound, walkers_text
from ..stored import StoredProgram
from .logprob import NOISE_MODELS, NOISE_TITLES, NoiseModel, start_weighting, walkers_log_prob
from .chain import AUTO_STEPS, auto_step_cap, ball_scales, capped_at, length_settings, length_text, run_emcee, start_walkers, support_in_sampled_space, undetermined_span
from .posterior import PREDICTIVE_COPIES, Posterior, fixed_rows, html_rows, last_at_prior_edge, marked_rows, chain_figures, checked_copies, sigma_between, with_noise, with_warning_columns
from .priors import SIGMA_REL_PRIOR, Prior, check_prior_inside, coerce_priors, data_scale_range, default_prior, prior_log_density

__all__ = ["SharedPosterior", "sample_shared", "spectrum_labels", "MAX_JOINT_PARAMETERS"]

# emcee's stretch move needs ever longer chains as the dimension grows (its autocorrelation
# time grows roughly linearly with it); beyond this many sampled parameters it does not mix in
# any practical run
MAX_JOINT_PARAMETERS = 60

# `SharedPosterior` warns when the spectra's own noise scales (relative rms residuals at the most
# probable draw) differ by more than this factor: one sigma_rel then fits none of them. Two
# spectra of equal noise on 30 points differ by ~10 % (the rms of 60 Gaussian values has a
# relative sd of 1/√120)
NOISE_SCALE_RATIO = 2.0

# `SharedPosterior.plot` draws one row per spectrum: every spectrum up to this many, else this
# many spread over them
PLOTTED_SPECTRA = 6

SUMMARY_QUANTILES = ("median", "q05", "q16", "q84", "q95")


@dataclass(frozen=True)
class _Structure:
    """What is static about a joint log-probability (hashable: one compilation each)."""

    circuit: Circuit
    registry: Registry
    n_spectra: int
    shared_positions: tuple[int, ...]  # circuit-parameter positions of the shared parameters
    own_positions: tuple[int, ...]  # ... of each spectrum's own free parameters
    has_sigma: bool
    log_scale: tuple[bool, ...]


@functools.lru_cache(maxsize=16)
def _log_prob_functions(st: _Structure):
    """(batched (W, P) → (W,), single) jitted log-posteriors of ``st``, kept across processes
    (`stored.StoredProgram`, ``bayes-shared-…``, keyed by ``st``; as a single spectrum's,
    `logprob.log_prob_functions`)."""
    compiled = compile_circuit(st.circuit, st.registry)
    names = compiled.parameter_names
    n_shared, n_own, m = len(st.shared_positions), len(st.own_positions), st.n_spectra
    log_scale = np.asarray(st.log_scale)

    def impedance(theta, freq):
        return compiled(dict(zip(names, theta)), freq)

    def log_prob(y, args):
        x = jnp.where(log_scale, jnp.exp(y), y)
        prior = jnp.sum(prior_log_density(x, args["code"], args["a"], args["b"], args["lo"], args["hi"], args["log_norm"]) + jnp.where(log_scale, y, 0.0))
        theta = jnp.broadcast_to(args["fixed"][None, :], (m, len(names)))
        theta = theta.at[:, np.asarray(st.shared_positions, int)].set(jnp.broadcast_to(x[None, :n_shared], (m, n_shared)))
        theta = theta.at[:, np.asarray(st.own_positions, int)].set(x[n_shared : n_shared + m * n_own].reshape(m, n_own))
        z = jax.vmap(impedance, in_axes=(0, None))(theta, args["freq"])
        r = z - args["z"]
        sigma = args["scale"] * (x[-1] if st.has_sigma else 1.0)
        ll = jnp.sum(-0.5 * (r.real**2 + r.imag**2) / sigma**2 - 2.0 * jnp.log(sigma) - jnp.log(2.0 * jnp.pi))
        ok = jnp.isfinite(prior) & jnp.isfinite(ll)
        return jnp.where(ok, prior + jnp.where(ok, ll, 0.0), -jnp.inf)

    return StoredProgram("bayes-shared-batched", st, jax.jit(jax.vmap(log_prob, in_axes=(0, None)))), StoredProgram("bayes-shared-single", st, jax.jit(log_prob))


@dataclass(frozen=True, eq=False)
class SharedPosterior(WalkerDraws, PiledUp, FrozenResult):
    """Draws from the joint posterior of a global fit. Immutable.

    ``names`` are the sampled parameters: the ``shared`` ones, then every other free parameter
    per spectrum as ``NAME[dim=coordinate]`` (spectrum order of ``spectra``), then ``sigma_rel``
    (proportional noise); ``draws`` (walker, draw, param) their natural values, ``log_prob``
    the log-posterior, ``fit`` the global least-squares fit the walkers started from (its
    ``dataset["Z"]`` the data), ``sigma`` the data's σ [Ω] if it has one (shaped as that Z),
    ``stragglers`` the run's walkers left out of the draws (`find_stragglers`)."""

    __repr__ = concise_repr  # (the generated one printed every array and Dataset)
    __str__ = report_text  # (print(result): its report)

    circuit: Circuit
    shared: tuple[str, ...]
    over: tuple[str, ...]
    spectra: tuple[str, ...]  # labels of the spectra along ``over``
    names: tuple[str, ...]
    units: tuple[str, ...]
    log_scale: tuple[bool, ...]
    draws: np.ndarray
    log_prob: np.ndarray
    acceptance: np.ndarray
    priors: dict[str, Prior]
    noise: NoiseModel
    fit: SharedFitResult
    sigma: np.ndarray | None = None
    notes: tuple[str, ...] = ()
    settings: dict = field(default_factory=dict)
    registry: Registry = field(default=DEFAULT_REGISTRY, repr=False)
    stragglers: Stragglers = NO_STRAGGLERS

    def __post_init__(self):
        freeze_fields(self)  # read-only arrays and mappings (`impedax.fitting.frozen`)

    @property
    def fixed(self) -> KeyHintDict:
        """The parameters held fixed (name → value), as the start fit holds them: a new dict
        whose missing key names the keys there are (`MissingKey`, as `Posterior.fixed`)."""
        ds = self.fit.dataset
        return KeyHintDict((str(n), float(ds["value"].sel(param=n).values.ravel()[0])) for n in ds["param"].values if bool(ds["fixed"].sel(param=n)))

    @functools.cached_property
    def bounds(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """(lower, upper) bounds of the sampled parameters: the circuit's, (0, ∞) for ``sigma_rel``."""
        specs = self.circuit.parameter_specs(self.registry)
        pairs = [(specs[n].lower, specs[n].upper) if n in specs else (0.0, math.inf) for n in (circuit_name(name) for name in self.names)]
        return tuple(float(lo) for lo, _ in pairs), tuple(float(hi) for _, hi in pairs)

    @functools.cached_property
    def warnings(self) -> tuple[str, ...]:
        """Diagnostics that need attention, as a single spectrum's posterior gives them
        (`Posterior.warnings`): chain length, acceptance, correlations, draws piled up against a
        prior's edge and linearised standard errors far from the posterior's widths, per-spectrum
        parameters named with their spectrum (``R2[cycle=64]``); then notes and the start fit's,
        one line per kind with the spectra it applies to, as a batch's report groups them
        (`_start_fit_warnings`)."""
        out = straggler_warnings(self.stragglers, self.n_walkers + len(self.stragglers.walkers))
        out += chain_warnings(self.names, self.log_scale, self._sampled_space, self.autocorr, self.settings.get("thin", 1), self.mean_acceptance, step_cap=capped_at(self.settings), steps=self.settings.get("steps"))
        out.extend(self._prior_edges.warnings)
        out.extend(self._interval_warnings())
        out.extend(self._noise_scale_warnings())
        out.extend(self.notes)
        out.extend(_start_fit_warnings(self.fit.warnings, len(self.spectra)))
        return tuple(out)

    def spectrum_noise_scales(self) -> np.ndarray:
        """Each spectrum's relative rms residual at the draw of highest posterior density,
        √(mean over its 2N parts of (r_k/|Z_data,k|)²): the sigma_rel that spectrum alone would
        give (spectra in the order of ``spectra``)."""
        best = np.array([int(np.argmax(self.log_prob))])
        values = self._circuit_draws(best)
        impedance = compile_circuit(self.circuit, self.registry)
        z = self.z_data
        out = []
        for row in range(len(self.spectra)):
            model = np.asarray(impedance({n: float(v[row, 0]) for n, v in values.items()}, self.frequency))
            rel = (model - z[row]) / np.abs(z[row])
            out.append(math.sqrt(float(np.mean(np.concatenate([rel.real, rel.imag]) ** 2))))
        return np.asarray(out)

    def _noise_scale_warnings(self) -> list[str]:
        """With proportional noise one ``sigma_rel`` is sampled for every spectrum; where the
        spectra's own scales (`spectrum_noise_scales`) differ by more than `NOISE_SCALE_RATIO`,
        that common scale is too large for some and too small for others, and so are their
        intervals: said, with the spectra at both ends."""
        if self.noise != NoiseModel.PROPORTIONAL or len(self.spectra) < 2:
            return []
        scales = self.spectrum_noise_scales()
        low, high = int(np.argmin(scales)), int(np.argmax(scales))
        if not scales[high] > NOISE_SCALE_RATIO * scales[low]:
            return []
        common = float(np.median(self.samples["sigma_rel"]))
        return [f"one sigma_rel is sampled for all {len(self.spectra)} spectra, but their residuals differ {scales[high] / scales[low]:.2g}×: at the most probable draw "
                f"{self.spectra[low]} misses its data by {scales[low]:.3g} rms (relative), {self.spectra[high]} by {scales[high]:.3g}, against sigma_rel {common:.3g}: "
                "the intervals of the spectra that fit better are too wide and those of the spectra that fit worse too narrow; sample them one at a time, "
                "or give each its own noise (noise='sigma' with the data's sigma)"]

    def _interval_warnings(self) -> list[str]:
        """`interval_warnings` (as `Posterior`'s) for the sampled circuit parameters, each against
        its spectrum's linearised standard error in the global start fit."""
        q = self.quantiles()
        start = _start_of(self.fit.dataset, self.over, self.spectra, self.names)
        names = [n for n in self.names if n in start]
        at_bound = [n for n in names if start[n].at_bound]
        return interval_warnings(
            {n: start[n].stderr for n in names},
            {n: 0.5 * float(q["q84"].sel(param=n) - q["q16"].sel(param=n)) for n in names},
            chain_converged=self.chain_converged,
            at_bound=at_bound,
            piled_up=[n for n in names if n in self._prior_edges.piled_up],
            tied=tied_to_bound(names, _start_covariance(self.fit.dataset, self.over, self.spectra, names), at_bound, self.undetermined),  # (within a spectrum)
        )

    @functools.cached_property
    def undetermined(self) -> tuple[str, ...]:
        """The sampled parameters the global least-squares start found the data do not determine,
        by `Posterior.undetermined`'s rule applied in each one's spectrum: in one of its
        unidentified groups (`SharedFitResult.unidentified_groups_of`), a relative standard error
        above 100 %, or run to a bound by a term that vanishes from Z (`branches.left_to_priors`:
        the battery cycles' R2[cycle=64] at ∞); a shared parameter by its global fit, in any
        spectrum's group."""
        stored = self.fit._stored_groups() or {}  # (a global fit saved by an older version records none)
        grouped = {label: {n for g in parameter_groups(stored.get(label, ())) for n in g} for label in self.spectra}
        start = _start_of(self.fit.dataset, self.over, self.spectra, self.names)
        out = []
        for n, s in start.items():
            row = _spectrum_row(n, self.spectra)
            in_group = any(circuit_name(n) in g for g in grouped.values()) if row is None else circuit_name(n) in grouped[self.spectra[row]]
            if in_group or left_to_priors(s.value, s.stderr, s.at_bound):
                out.append(n)
        return tuple(out)

    def quantiles(self) -> xr.Dataset:
        """median, q05, q16, q84, q95, mean, sd and the 90 % HDI per sampled parameter."""
        return draws_table(self.samples)

    def _by_name(self, q: xr.Dataset, names) -> dict[str, dict]:
        return {
            n: {**{k: float(q[k].sel(param=n)) for k in SUMMARY_QUANTILES}, "unit": self.units[self.names.index(n)], "prior": str(self.priors[n])}
            for n in names
        }

    def summary(self) -> dict:
        """The JSON summary of ``impedax sample --shared``: ``shared`` (quantiles of the shared
        parameters), ``params`` (every sampled parameter), diagnostics and settings."""
        q = self.quantiles()
        return {
            "model": self.model,
            "over": list(self.over),
            "shared": self._by_name(q, self.shared),
            "params": self._by_name(q, self.names),
            "acceptance": self.mean_acceptance,
            "autocorr": dict(self.autocorr),
            "ess": dict(self.ess),
            "warnings": list(self.warnings),
            "chain_converged": self.chain_converged,  # (as `Posterior.summary`'s)
            "warning_tags": self._warning_tags(),  # (as `Posterior.summary`'s: none for the sampling's own, the start fit's for its lines)
            "undetermined": list(self.undetermined),  # (as `Posterior.summary`'s)
            "at_prior_edge": self.at_prior_edge,  # (as `Posterior.summary`'s)
            "piled_up": self.piled_up,
            "straggler_walkers": list(self.stragglers.walkers),  # (as `Posterior.summary`'s)
            "strong_correlations": [c.to_attr() for c in self.strong_correlations],  # (as `Posterior.summary`'s)
            "noise": self.noise.value,
            "walkers": self.n_walkers + len(self.stragglers.walkers),  # (the run's, as `Posterior.summary`)
            "walkers_kept": self.n_walkers,  # (those whose draws the posterior holds)
            "draws": self.n_draws,
            "draws_total": self.n_walkers * self.n_draws,
            **{k: self.settings.get(k) for k in ("steps", "burn", "thin", "seed")},
            "steps_mode": self.settings.get("steps_mode", "fixed"),
            "step_cap": self.settings.get("step_cap"),
            "stopped": self.settings.get("stopped"),
            "fixed": self.fixed,
            "start_fit": self._start_fit_summary(),  # (as `Posterior.summary`'s)
        }

    def _warning_tags(self) -> list[list[str]]:
        """Each of ``warnings``' tags, in their order, as `Posterior.summary`'s ``warning_tags``:
        none for the sampling's own and the notes, the start fit's for the lines of its warnings
        (`_start_fit_tags`), which end ``warnings``."""
        start = _start_fit_tags(self.fit)
        return [[] for _ in range(len(self.warnings) - len(start))] + start

    def _start_fit_summary(self) -> dict:
        """The global least-squares fit the walkers started around, by sampled name (``R1[cycle=0]``,
        a shared one's once): ``values``, ``stderr`` (linearised; None at a bound or where not
        finite, as `Posterior.summary`'s ``start_fit``), ``at_bound``; ``model`` and ``weighting``."""
        start = _start_of(self.fit.dataset, self.over, self.spectra, self.names)
        return {
            "model": self.model, "weighting": self.fit.weighting,
            "values": {n: s.value for n, s in start.items()},
            "stderr": {n: None if s.at_bound or not math.isfinite(s.stderr) else s.stderr for n, s in start.items()},
            "at_bound": [n for n, s in start.items() if s.at_bound],
        }

    def _sampler_text(self) -> str:
        """The run in words (the report's sampler line, the notebook's first)."""
        return (f"emcee, {walkers_text(self.n_walkers, self.stragglers)}, {self.settings.get('steps')} steps ({length_text(self.settings)}burn {self.settings.get('burn')}, "
                f"thin {self.settings.get('thin')}), {self.n_walkers * self.n_draws} draws, acceptance {self.mean_acceptance:.3f}")

    def report(self) -> str:
        q = self.quantiles()
        fixed = self.fixed
        width = column_width([*self.names, *fixed], "parameter")
        lines = [
            f"model      {self.model}   (joint posterior: {', '.join(self.shared)} shared over {', '.join(self.over)}, {counted(len(self.spectra), 'spectrum', 'spectra')})",
            f"noise      {self.noise}: {NOISE_MODELS[self.noise]}",
            f"sampler    {self._sampler_text()}",
            "",
            f"{'parameter':<{width}}  {'median':>11}  {'q05':>11}  {'q95':>11}  {'τ [steps]':>9}  {'ESS':>7}  unit",
        ]
        marks, footnotes = marked_rows(self.undetermined, self.set_by_prior_edge)
        unit_width = max(4, *(len(unit_text(u)) for u in self.units))
        for i, n in enumerate(self.names):
            lines.append(
                f"{n:<{width}}  {float(q['median'][i]):>11.5g}  {float(q['q05'][i]):>11.5g}  {float(q['q95'][i]):>11.5g}  {figure(self.autocorr[n], '9.3g'):>9}  {figure(self.ess[n], '7.0f'):>7}  "
                + (f"{unit_text(self.units[i]):<{unit_width}}  {marks[n]}" if n in marks else unit_text(self.units[i]))
            )
        specs = self.circuit.parameter_specs(self.registry)
        for n, value in fixed.items():  # (as a single spectrum's report: the model's values need them too)
            lines.append(f"{n:<{width}}  {exact_number(value):>11}  {'(fixed)':>11}  {'':>11}  {'':>9}  {'':>7}  {unit_text(specs[n].unit) if n in specs else ''}".rstrip())
        lines += footnotes
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        """The report in a notebook, as `Posterior`'s: what is shared over which spectra, the
        sampler and noise lines, a row per sampled parameter (`to_table`: quantiles, unit, τ,
        ESS, the NOT DETERMINED mark), the footnotes and the warnings."""
        from ...plotting.html import result_html

        title = f"{self.model}: joint posterior ({', '.join(self.shared)} shared over {', '.join(self.over)}, {counted(len(self.spectra), 'spectrum', 'spectra')})"
        lines = [
            f"sampler: {self._sampler_text()}",
            f"noise: {self.noise}: {NOISE_MODELS[self.noise]}",
            *marked_rows(self.undetermined, self.set_by_prior_edge)[1],
            *self.warnings,
        ]
        return result_html(title, html_rows(self.to_table()), lines=lines)  # (the unit as the report writes it: Ω; the report's marks)

    # -- the spectra, and the model over the draws ---------------------------------------
    @property
    def frequency(self) -> np.ndarray:
        """The data's frequencies [Hz]."""
        return np.asarray(self.fit.dataset["frequency"].values, float)

    @property
    def z_data(self) -> np.ndarray:
        """The data [Ω] (spectrum, frequency), spectra in the order of ``spectra``."""
        return np.asarray(self.fit.dataset["Z"].transpose(*self.over, "frequency").values, complex).reshape(len(self.spectra), -1)

    def _circuit_draws(self, pick: np.ndarray) -> dict[str, np.ndarray]:
        """Every circuit parameter at the flat draws ``pick``, (spectrum, draw) each: a shared one
        the same in every spectrum, a per-spectrum one (``R1[trial=3]``) in its own row, a fixed one
        its value."""
        flat = self.draws.reshape(-1, len(self.names))[pick]
        shape = (len(self.spectra), len(pick))
        out = {n: np.full(shape, v) for n, v in self.fixed.items()}
        for i, name in enumerate(self.names):
            if name == "sigma_rel":
                continue
            row, key = _spectrum_row(name, self.spectra), circuit_name(name)
            if row is None:
                out[key] = np.broadcast_to(flat[:, i], shape).copy()
            else:
                out.setdefault(key, np.full(shape, np.nan))[row] = flat[:, i]
        return out

    def predict(self, freq=None, *, max_draws: int = 400, noise: bool = False, copies: int = 1, seed: int = 0) -> np.ndarray:
        """Model impedance [Ω] (spectrum, draws, frequency) over an evenly spaced subset of the
        joint draws, each spectrum with the shared parameters and its own (`Posterior.predict`
        per spectrum). With ``noise`` each draw also carries the likelihood's noise, the
        posterior predictive of new measurements: σ = sigma_rel·|Z_model| (``proportional``)
        or each spectrum's σ interpolated in log f (``sigma``); ``copies`` noisy copies of
        each draw (draws × copies along the second axis)."""
        freq = self.frequency if freq is None else checked_frequencies(freq)
        if noise:
            checked_copies(copies)
        pick = draw_indices(self.n_walkers * self.n_draws, max_draws)
        params = self._circuit_draws(pick)
        compiled = compile_circuit(self.circuit, self.registry)
        fn = jax.jit(jax.vmap(lambda p, f: compiled(p, f), in_axes=(0, None)))
        m = len(self.spectra)
        z = np.asarray(fn({k: jnp.asarray(v.reshape(-1)) for k, v in params.items()}, jnp.asarray(freq))).reshape(m, len(pick), -1)
        if not noise:
            return z
        z, pick = np.repeat(z, copies, axis=1), np.repeat(pick, copies)
        if self.noise == NoiseModel.PROPORTIONAL:
            sigma = self.samples["sigma_rel"][pick][None, :, None] * np.abs(z)
        else:
            data_sigma = self.fit.dataset["Z"].copy(data=np.asarray(self.sigma, float)).transpose(*self.over, "frequency").values.reshape(m, -1)
            sigma = np.broadcast_to(sigma_between(freq, self.frequency, data_sigma)[:, None, :], z.shape)
        return with_noise(z, sigma, seed)

    def plot(self, *, spectra: Sequence[str] | None = None, title: str | None = None, n_lines: int = 40, figsize: tuple[float, float] | None = None):
        """Each spectrum's data with its posterior bands, one row per spectrum: Nyquist (draws
        as thin lines), Bode |Z| and phase with the 68 % and 90 % credible bands and the 90 %
        posterior predictive band (`Posterior.plot`'s panels; matplotlib Figure). ``spectra``:
        the labels to draw (as ``spectra`` names them, "trial=3"); default: every spectrum up
        to `PLOTTED_SPECTRA`, else that many spread evenly over them (the title says so).
        ``figsize`` (width, height) [in] in place of the size that follows the rows."""
        from ...plotting.bayes import plot_joint_posterior_bands

        rows = self._plotted_rows(spectra)
        labels = [self.spectra[i] for i in rows]
        f = np.geomspace(self.frequency.min(), self.frequency.max(), 200)
        shown = "" if len(rows) == len(self.spectra) else f", {len(rows)} of {len(self.spectra)} spectra"
        return plot_joint_posterior_bands(
            self.frequency, self.z_data[rows], labels, f, self.predict(f)[rows], n_lines=n_lines,
            z_predictive=self.predict(f, noise=True, copies=PREDICTIVE_COPIES)[rows],
            title=title or f"{self.model}: joint posterior bands ({self.n_walkers * self.n_draws} draws{shown}; {NOISE_TITLES[self.noise]})", figsize=figsize,
        )

    def _plotted_rows(self, spectra) -> list[int]:
        """The rows of ``spectra`` (labels) in the data, or the default rows of `plot`."""
        if spectra is None:
            m = len(self.spectra)
            return list(range(m)) if m <= PLOTTED_SPECTRA else sorted(set(np.linspace(0, m - 1, PLOTTED_SPECTRA).round().astype(int).tolist()))
        labels = [spectra] if isinstance(spectra, str) else list(spectra)
        unknown = [s for s in labels if s not in self.spectra]
        if unknown or not labels:
            raise ParameterError(f"spectra: {', '.join(map(repr, unknown)) or 'none given'}; this joint posterior's spectra are {', '.join(map(repr, self.spectra))}")
        return [self.spectra.index(s) for s in labels]

    def corner(self, *, truths: Mapping[str, float] | None = None, bins: int = 30, max_points: int = 4000, params: Sequence[str] | None = None):
        """Corner plot of the sampled parameters (`Posterior.corner`; matplotlib Figure).
        ``params``: the names to draw, in that order (``"R1[cycle=64]"``); default every one up
        to `CORNER_MAX_PARAMS`, beyond that the shared parameters, the first spectrum's own and
        the noise's (`default_corner_params`; the title says which)."""
        from ...plotting.bayes import CORNER_MAX_PARAMS, plot_corner

        title = f"{self.model}: joint posterior ({NOISE_TITLES[self.noise]})"
        if params is None and len(self.names) > CORNER_MAX_PARAMS:
            params = self.default_corner_params()
            title += f", the shared parameters, {self.spectra[0]}'s and the noise (others: params=, --corner-params)"
        return plot_corner(self.draws, self.names, self.log_scale, units=self.units, truths=truths, bins=bins, max_points=max_points, title=title, params=params)

    def trace(self, *, params: Sequence[str] | None = None):
        """Trace plot of the sampled parameters (`Posterior.trace`; matplotlib Figure); default
        every one up to `CORNER_MAX_PARAMS`, beyond that those `corner` draws by default."""
        from ...plotting.bayes import CORNER_MAX_PARAMS, plot_trace

        title = f"{self.model}: joint posterior draws ({NOISE_TITLES[self.noise]})"
        if params is None and len(self.names) > CORNER_MAX_PARAMS:
            params = self.default_corner_params()
            title += f", the shared parameters, {self.spectra[0]}'s and the noise (others: params=)"
        return plot_trace(
            self.draws, self.names, self.log_scale, units=self.units, first_step=self.settings.get("burn", 0), thin=self.settings.get("thin", 1),
            autocorr=self.autocorr, title=title, params=params,
        )

    def default_corner_params(self) -> list[str]:
        """The parameters `corner` draws by default beyond `CORNER_MAX_PARAMS`: the shared ones,
        the first spectrum's own (``R1[cycle=0]``) and the noise's (``sigma_rel``), as ``names``
        orders them: one spectrum's correlations with the shared values, where 20 parameters
        on one figure could not be read."""
        return [n for n in self.names if _spectrum_row(n, self.spectra) in (None, 0)]

    def to_table(self) -> list[dict[str, object]]:
        """One row per sampled parameter: name, the summary quantiles, unit, and (as the
        JSON's keys) ``autocorr`` (τ [steps]) and ``ess``, None where unknown, and
        ``undetermined``, as `Posterior.to_table`: the rows the report marks NOT DETERMINED; then
        the fixed parameters' rows and the column ``fixed`` (`fixed_rows`); then
        ``at_prior_edge``: the rows it marks AT PRIOR EDGE; last, on every row,
        ``chain_converged`` and ``warnings`` (`with_warning_columns`)."""
        q = self.quantiles()
        marks, _ = marked_rows(self.undetermined, self.set_by_prior_edge)
        return with_warning_columns(last_at_prior_edge([
            {"name": n, **{k: float(q[k].sel(param=n)) for k in SUMMARY_QUANTILES}, "unit": u, **chain_figures(self.autocorr, self.ess, n), "undetermined": n in marks and n in self.undetermined,
             "fixed": False, "at_prior_edge": n in marks and n not in self.undetermined}
            for n, u in zip(self.names, self.units)
        ] + fixed_rows(self.fixed, self.circuit.parameter_specs(self.registry))), self.chain_converged, self.warnings)

    def derive(self, fn: Callable, freq=None, *, draws: bool = False, max_draws: int | None = None) -> xr.Dataset:
        """`Posterior.derive` over the joint draws: ``fn(params[, freq])`` gets every sampled
        parameter by its name (``R0``, ``R1[trial=3]``, ``sigma_rel``) and the fixed ones;
        ``freq`` defaults to the data's frequencies when ``fn`` takes one."""
        if freq is None and needs_freq(fn):
            freq = np.asarray(self.fit.dataset["frequency"].values, float)
        total = self.n_walkers * self.n_draws
        params = {n: np.full(total, v) for n, v in self.fixed.items()}
        params.update(self.samples)
        return draws_band(fn, freq, params, self.model, draws=draws, max_draws=max_draws, method="joint posterior draws")

    def to_xarray(self) -> xr.Dataset:
        """Draws (walker, draw, param), log_prob, acceptance, diagnostics, quantiles, the data
        (``Z``, ``sigma``) and the global least-squares start (``fit_*``, its dimensions other
        than ``over`` and frequency prefixed too); `SharedPosterior.from_xarray` rebuilds it."""
        clash = sorted(set(self.over) & {"walker", "draw", "param"})
        if clash:
            raise ParameterError(f"cannot store a joint posterior over a dimension named {clash[0]!r}: the draws use that name; rename it in the data")
        q = self.quantiles()
        data = {
            "draws": (("walker", "draw", "param"), self.draws),
            "log_prob": (("walker", "draw"), self.log_prob),
            "acceptance": ("walker", self.acceptance),
            "autocorr": ("param", [self.autocorr[n] for n in self.names], {"units": "steps"}),
            "ess": ("param", [self.ess[n] for n in self.names]),
            "log_scale": ("param", np.asarray(self.log_scale, bool)),
            "is_shared": ("param", np.array([n in self.shared for n in self.names])),
            **{k: ("param", q[k].values) for k in q.data_vars},
        }
        fit_data, fit_coords, stored, stored_dims = _fit_variables(self.fit.dataset, self.over)
        data.update(fit_data)
        if self.sigma is not None:
            data["sigma"] = (self.fit.dataset["Z"].dims, self.sigma, {"units": "ohm"})
        fr = self.fit
        attrs = {
            "impedax_kind": "shared_posterior", "model": self.model, "noise": self.noise.value, "shared": ",".join(self.shared), "over": ",".join(self.over),
            "spectra": list(self.spectra), "units": list(self.units), "priors": {n: [p.kind.value, p.a, p.b] for n, p in self.priors.items()},
            "settings": dict(self.settings), "notes": list(self.notes), "warnings": list(self.warnings),
            "fit": {"weighting": fr.weighting, "warnings": {k: list(v) for k, v in fr.warnings.items()}, "elapsed_s": fr.elapsed_s, "attrs": dict(fr.dataset.attrs),
                    "warning_tags": None if fr.warning_tags is None else {k: tags_attr(v) for k, v in fr.warning_tags.items()}},  # (its warnings' tags, as a joint fit's .nc)
            "fit_variables": stored, "fit_dims": stored_dims, "straggler_walkers": list(self.stragglers.walkers), "stragglers": self.stragglers.to_attr(),
        }
        coords = {"walker": kept_walkers(self.n_walkers, self.stragglers), "draw": np.arange(self.n_draws), "param": list(self.names), "unit": ("param", list(self.units), {"long_name": PARAMETER_UNIT_NAME}), **fit_coords}
        return result_dataset(xr.Dataset(data, coords=coords, attrs=attrs).copy(deep=True))

    @classmethod
    def from_xarray(cls, ds: xr.Dataset, *, registry: Registry | None = None) -> "SharedPosterior":
        """Rebuild a joint posterior from `SharedPosterior.to_xarray` output, read back by
        `impedax.load` or `impedax.io.read_netcdf`, or opened as stored (``xr.open_dataset``).
        A file that is not a complete saved joint posterior raises one `DataError` naming it."""
        from ...io.netcdf import damaged_result, saved_result  # (io is imported only here: rarely needed)

        def variables(attrs):  # beside the draws, the start fit's as the file lists them
            listed = attrs.get("fit_variables")
            return (*_REQUIRED_VARIABLES, *(listed if isinstance(listed, dict) else ()))

        ds = saved_result(ds, "shared_posterior", variables=variables, attrs=_REQUIRED_ATTRS)
        with damaged_result("shared_posterior", ds):
            return cls._rebuild(ds, DEFAULT_REGISTRY if registry is None else registry)

    @classmethod
    def _rebuild(cls, ds: xr.Dataset, registry: Registry) -> "SharedPosterior":
        """`from_xarray` once the file's kind and variables are checked."""
        circuit = parse(ds.attrs["model"], registry)
        names = tuple(str(n) for n in ds["param"].values)
        draws = np.asarray(ds["draws"].transpose("walker", "draw", "param").values, float)
        units, priors = tuple(str(u) for u in ds.attrs["units"]), {str(n): Prior(*v) for n, v in ds.attrs["priors"].items()}
        log_scale = tuple(bool(v) for v in ds["log_scale"].values)
        if len(units) != len(names) or len(log_scale) != len(names) or set(priors) != set(names):
            raise ValueError(f"{len(names)} sampled parameters but {len(units)} units, {len(log_scale)} log_scale flags and priors for {len(priors)}")
        over = tuple(ds.attrs["over"].split(","))
        stored, dims = ds.attrs["fit_variables"], ds.attrs["fit_dims"]
        fit_data, fit_coords = {}, {}
        for name, original in stored.items():
            var = ds[name].variable
            (fit_coords if name in ds.coords else fit_data)[original] = xr.Variable(tuple(dims.get(d, d) for d in var.dims), var.values, var.attrs)
        fa = ds.attrs["fit"]
        fit_ds = xr.Dataset(fit_data, coords=fit_coords, attrs=fa["attrs"])
        fit_warnings = {str(k): tuple(v) for k, v in fa["warnings"].items()}
        fit_result = SharedFitResult(
            circuit=circuit, dataset=fit_ds, weighting=fa["weighting"], warnings=fit_warnings,
            elapsed_s=float(fa["elapsed_s"]), registry=registry, shared=tuple(ds.attrs["shared"].split(",")), over=over,
            warning_tags=stored_batch_tags(fa, fit_warnings),  # (a file written by an older version: none, the words)
        )
        return cls(
            circuit=circuit, shared=tuple(ds.attrs["shared"].split(",")), over=over, spectra=tuple(str(s) for s in ds.attrs["spectra"]), names=names,
            units=units, log_scale=log_scale, draws=draws,
            log_prob=np.asarray(ds["log_prob"].transpose("walker", "draw").values, float), acceptance=np.asarray(ds["acceptance"].values, float),
            priors={n: priors[n] for n in names}, noise=NoiseModel(ds.attrs["noise"]), fit=fit_result,
            sigma=np.asarray(ds["sigma"].transpose(*fit_ds["Z"].dims).values, float) if "sigma" in ds else None, notes=tuple(ds.attrs.get("notes", ())),
            settings=dict(ds.attrs["settings"]), registry=registry,
            stragglers=Stragglers.from_attr(ds.attrs.get("stragglers")),  # (a file written by an older version: none)
        )


# what `SharedPosterior.from_xarray` needs beside the start fit's variables (listed in the file)
_REQUIRED_VARIABLES = ("draws", "log_prob", "acceptance", "log_scale", "param", "Z", "frequency")
_REQUIRED_ATTRS = ("model", "noise", "shared", "over", "spectra", "units", "priors", "settings", "fit", "fit_variables", "fit_dims")
# the data: stored under its own name (so `impedax.load` reads the file as the spectra, with the
# posterior's ``sigma``); the rest of the start fit's dataset is prefixed ``fit_``
_DATA_VARIABLES = ("Z",)


def _fit_variables(fit_ds: xr.Dataset, over: tuple[str, ...]):
    """The global fit's dataset as variables of a posterior's: (data variables, coordinates,
    stored name → its name, stored dimension → its name). ``over`` and frequency are kept."""
    keep = {*over, "frequency"}
    dims = {d: d if d in keep else f"fit_{d}" for d in fit_ds.dims}
    data, coords, stored = {}, {}, {}
    for name, var in fit_ds.variables.items():
        new = xr.Variable(tuple(dims[d] for d in var.dims), var.values, var.attrs)
        if name in fit_ds.coords:
            key = name if name in keep else f"fit_{name}"
            coords[key] = new
        else:
            key = name if name in _DATA_VARIABLES else f"fit_{name}"
            data[key] = new
        stored[key] = str(name)
    return data, coords, stored, {v: k for k, v in dims.items() if k != v}


def _start_fit_warnings(warnings: Mapping[str, tuple[str, ...]], n_spectra: int) -> list[str]:
    """The global start fit's ``warnings`` (spectrum label → its texts, `SharedFitResult.warnings`)
    as lines of a joint posterior's warnings: one per kind of warning with the spectra it applies
    to, grouped as a batch's report groups them (`grouped_warnings`) —
    ``least-squares start (2 of 3 spectra: trial 0, 2): …``, ``(all 3 spectra)``, a global fit's
    own notes ``(shared over trial)`` — and, past the kinds a report lists, how many more (every
    text is in the start fit's warnings)."""
    return grouped_warnings(_start_fit_texts(warnings), n_spectra, head="least-squares start", more="least-squares start: {n} more kinds of warning (every text: the posterior's fit.warnings)")


def _start_fit_texts(warnings: Mapping[str, tuple[str, ...]]) -> dict[str, tuple[str, ...]]:
    """The start fit's warnings by spectrum without their advice to sample (this is the sample the advice asks for)."""
    return {k: tuple(without_sample_advice(w) for w in v) for k, v in warnings.items()}


def _start_fit_tags(fit: SharedFitResult) -> list[list[str]]:
    """The tags of each line of `_start_fit_warnings` (`grouped_warning_tags`): those of the
    start fit's warnings (`BatchFitResult.spectrum_warning_tags`) that the line stands for."""
    tags = {k: fit.spectrum_warning_tags(k) for k in fit.warnings}
    return [list(t) for t in grouped_warning_tags(_start_fit_texts(fit.warnings), tags)]


class _Start(NamedTuple):
    """A sampled circuit parameter in the global least-squares start fit."""

    value: float
    stderr: float  # linearised (at a bound: the linearisation's scale)
    at_bound: bool


def _spectrum_row(name: str, spectra) -> int | None:
    """The spectrum (index into ``spectra``) of a per-spectrum sampled name; None: shared."""
    return list(spectra).index(name[name.index("[") + 1 : -1]) if "[" in name else None


def _start_of(fit_ds: xr.Dataset, over, spectra, names) -> dict[str, _Start]:
    """The global fit ``fit_ds`` at each sampled circuit parameter of ``names`` (``sigma_rel``
    has none): a per-spectrum one's in its spectrum; a shared one's in the first (the same in
    all), at a bound where it is in any."""
    m = len(spectra)
    params = [str(p) for p in fit_ds["param"].values]

    def table(var):
        return np.asarray(fit_ds[var].transpose(*over, "param").values).reshape(m, -1)

    value = table("value")
    stderr = table("linearised_stderr" if "linearised_stderr" in fit_ds else "stderr")
    bound = table("at_bound").astype(bool) if "at_bound" in fit_ds else np.zeros(value.shape, bool)
    out = {}
    for n in names:
        if circuit_name(n) not in params:
            continue
        i, row = params.index(circuit_name(n)), _spectrum_row(n, spectra)
        r = 0 if row is None else row
        out[n] = _Start(float(value[r, i]), float(stderr[r, i]), bool(bound[:, i].any() if row is None else bound[row, i]))
    return out


def _start_covariance(fit_ds: xr.Dataset, over, spectra, names) -> np.ndarray:
    """The global fit's covariance between the sampled parameters ``names`` (natural values): each
    spectrum's among its own parameters; NaN across spectra, for shared parameters (whose walkers
    follow no one spectrum) and where the fit has none."""
    p = len(names)
    out = np.full((p, p), np.nan)
    if "covariance" not in fit_ds:
        return out
    cov = fit_ds["covariance"]
    inner = [d for d in cov.dims if d not in over]
    free = [str(x) for x in fit_ds[inner[0]].values]
    values = np.asarray(cov.transpose(*over, *inner).values, float).reshape(len(spectra), len(free), len(free))
    where = [(_spectrum_row(n, spectra), free.index(circuit_name(n))) if "[" in n and circuit_name(n) in free else None for n in names]
    for a, wa in enumerate(where):
        for b, wb in enumerate(where):
            if wa is not None and wb is not None and wa[0] == wb[0]:
                out[a, b] = values[wa[0], wa[1], wb[1]]
    return out


def spectrum_labels(ds: xr.Dataset, over: Sequence[str]) -> list[str]:
    """The labels of ``ds``'s spectra along the dimensions ``over`` (``cycle=64``; several:
    ``trial=1, session=2``), in the order the joint posterior names its parameters NAME[LABEL]."""
    labels = [[f"{d}={c}" for c in (ds[d].values if d in ds.coords else range(ds.sizes[d]))] for d in over]
    return [", ".join(label[i] for label, i in zip(labels, index)) for index in np.ndindex(*(ds.sizes[d] for d in over))]


def _too_many_parameters(spectra: int, shared: int, own: int, noise: NoiseModel) -> str:
    """The refusal of a joint posterior beyond `MAX_JOINT_PARAMETERS`."""
    sigma = noise is NoiseModel.PROPORTIONAL
    total = shared + spectra * own + int(sigma)
    return (f"the joint posterior of {spectra} spectra has {total} sampled parameters ({shared} shared + {spectra} × {own} own"
            f"{' + sigma_rel' if sigma else ''}); emcee mixes up to {MAX_JOINT_PARAMETERS}: sample fewer spectra or share more parameters")


def _check_joint_size(circuit: Circuit, ds, *, shared, over, fixed, noise: NoiseModel, registry: Registry) -> None:
    """`_too_many_parameters` before the global fit, where the names and dimensions are plain
    (the rest is left to the fit's own checks and the count after it): on the REAL battery cycles
    120–129 with two of 8 parameters shared the refusal came after a 12 s global fit."""
    names = [n.strip() for n in shared.split(",")] if isinstance(shared, str) else list(shared) if isinstance(shared, (list, tuple)) else None
    dims = [over] if isinstance(over, str) else list(over) if isinstance(over, (list, tuple)) else None if over is None else []
    extra = [d for d in ds["Z"].dims if d != "frequency"]
    if dims is None:
        dims = extra if len(extra) == 1 else []
    free = [n for n in circuit.parameter_names(registry) if n not in (fixed or {})]
    if names is None or not dims or set(extra) != set(dims) or not all(isinstance(n, str) and n in free for n in names):
        return
    spectra = math.prod(int(ds.sizes[d]) for d in dims)
    k_shared = len(set(names))
    if k_shared + spectra * (len(free) - k_shared) + int(noise is NoiseModel.PROPORTIONAL) > MAX_JOINT_PARAMETERS:
        raise ParameterError(_too_many_parameters(spectra, k_shared, len(free) - k_shared, noise))


def sample_shared(
    circuit: Circuit, data, *, shared, over, priors: Mapping | None, noise: NoiseModel, walkers: int | None, steps: int | str, burn: int | None, thin: int, seed: int,
    fixed: Mapping[str, float] | None, fmin, fmax, progress, registry: Registry,
) -> SharedPosterior:
    """The joint posterior (module docstring); settings already checked by `sample`."""
    spectrum = open_spectrum(data, fmin=fmin, fmax=fmax)
    ds, source = spectrum.data, spectrum.source
    weighting = start_weighting(noise)
    if noise is NoiseModel.SIGMA and "sigma" not in ds:
        raise DataError(f"noise='sigma' needs a 'sigma' variable in the data (e.g. the SEM of repeated trials): {SIGMA_SOURCES}; use noise='proportional' otherwise", path=source)
    _check_joint_size(circuit, ds, shared=shared, over=over, fixed=fixed, noise=noise, registry=registry)  # (before the global fit: the refusal came after it)
    specs = circuit.parameter_specs(registry)
    user = coerce_priors(priors)
    for n in user:  # (before the global fit too: a misspelt --prior name would cost the fit)
        if n not in specs and n != "sigma_rel":
            raise ParameterError(f"prior for unknown parameter {n!r} (parameters: {', '.join(specs)})")
        if n in (fixed or {}):
            raise ParameterError(f"prior for {n}: the parameter is fixed")
    start = fit(circuit, ds, fixed=fixed or None, shared=shared, over=over, weighting=weighting, registry=registry)
    if start.keep:
        raise ParameterError(f"sample with shared parameters takes one global fit; these data also vary along {', '.join(start.keep)}: select one index of it")
    table = ParameterTable.build(circuit, registry=registry, fixed=fixed)
    own = [n for n in table.free_names if n not in start.shared]
    labels = spectrum_labels(ds, start.over)
    m = len(labels)
    names = [*start.shared, *(f"{n}[{label}]" for label in labels for n in own)] + (["sigma_rel"] if noise is NoiseModel.PROPORTIONAL else [])
    if len(names) > MAX_JOINT_PARAMETERS:
        raise ParameterError(_too_many_parameters(m, len(start.shared), len(own), noise))
    circuit_of = {n: n for n in start.shared} | {f"{n}[{label}]": n for label in labels for n in own}
    z = ds["Z"].transpose(*start.over, "frequency").values.reshape(m, -1)
    fitted = _start_of(start.dataset, start.over, labels, names)
    x0, se, at_bound = [], [], []
    for n in names:
        if n == "sigma_rel":
            x0.append(max(float(np.sqrt(np.mean(start.dataset["rms_rel"].values ** 2))) / math.sqrt(2.0), 1e-4))
            se.append(x0[-1] / math.sqrt(z.size))
            at_bound.append(False)
            continue
        x0.append(fitted[n].value)
        se.append(fitted[n].stderr)
        at_bound.append(fitted[n].at_bound)
    lower = [0.0 if n == "sigma_rel" else float(table.lower[table.names.index(circuit_of[n])]) for n in names]
    upper = [math.inf if n == "sigma_rel" else float(table.upper[table.names.index(circuit_of[n])]) for n in names]
    chosen, wide = {}, []
    freq_all, z_abs_all = np.tile(np.asarray(ds["frequency"].values, float), m), np.abs(z).ravel()
    for n, lo, hi, v, e, edge in zip(names, lower, upper, x0, se, at_bound):
        key = "sigma_rel" if n == "sigma_rel" else circuit_of[n]
        span = None
        if key in user:
            check_prior_inside(n, user[key], lo, hi, key != "sigma_rel" and specs[key].upper_inclusive)
            chosen[n] = user[key]
        elif n == "sigma_rel":
            chosen[n] = SIGMA_REL_PRIOR
        else:  # widened where the global fit leaves the parameter undetermined (`default_prior`), its walkers spread over it
            chosen[n] = default_prior(lo, hi, v, stderr=e, at_bound=edge, scale=data_scale_range(specs[key].unit, freq_all, z_abs_all))
            span = undetermined_span(chosen[n], lo, hi, v, e, edge)
        wide.append(span)
    support = [chosen[n].support(lo, hi) for n, lo, hi in zip(names, lower, upper)]
    for j, n in enumerate(names):  # a fit stopped at its bound starts inside its widened default prior
        if n != "sigma_rel" and circuit_of[n] not in user and 0 < support[j][0] and not support[j][0] < x0[j]:
            x0[j] = min(support[j][0] * (1 + 1e-6), support[j][1])
    log_scale = tuple(bool(lo >= 0) for lo in lower)
    names_all = table.names
    st = _Structure(
        circuit, registry, m, tuple(names_all.index(n) for n in start.shared), tuple(names_all.index(n) for n in own), noise is NoiseModel.PROPORTIONAL, log_scale,
    )
    batched, single = _log_prob_functions(st)
    scale = np.abs(z) if noise is NoiseModel.PROPORTIONAL else ds["sigma"].transpose(*start.over, "frequency").values.reshape(m, -1)
    args = {
        "freq": jnp.asarray(ds["frequency"].values, float), "z": jnp.asarray(z), "scale": jnp.asarray(scale),
        "fixed": jnp.asarray(np.where(np.isnan(table.values), 1.0, table.values)),
        "code": jnp.asarray([chosen[n].code for n in names], jnp.int32), "a": jnp.asarray([chosen[n].a for n in names]), "b": jnp.asarray([chosen[n].b for n in names]),
        "lo": jnp.asarray([s[0] for s in support]), "hi": jnp.asarray([s[1] for s in support]),
        "log_norm": jnp.asarray([chosen[n].log_normaliser(lo, hi) for n, lo, hi in zip(names, lower, upper)]),
    }
    p = len(names)
    walkers = max(64, 4 * p + (4 * p) % 2) if walkers is None else walkers
    if not isinstance(walkers, (int, np.integer)) or walkers < 2 * p or walkers % 2:
        raise ParameterError(f"walkers must be an even number of at least 2 × {p} parameters = {2 * p} (got {walkers!r})")
    if steps == AUTO_STEPS and burn is not None and burn >= auto_step_cap(walkers, p):
        raise ParameterError(f"burn must be below the {auto_step_cap(walkers, p)} steps steps='auto' runs at most (got {burn})")
    lo_y, hi_y = support_in_sampled_space(support, log_scale)
    p0 = start_walkers(
        x0, log_scale, ball_scales(x0, se, log_scale), walkers=walkers, seed=seed, lo_y=lo_y, hi_y=hi_y,
        log_prob_one=lambda y: single(jnp.asarray(y), args), log_prob_all=lambda y: batched(jnp.asarray(y), args),
        where=f"the global least-squares fit of {circuit}", wide=wide, covariance=_start_covariance(start.dataset, start.over, labels, names),
    )
    chain = run_emcee(p0, walkers_log_prob(batched, args), steps=steps, burn=burn, thin=thin, seed=seed, progress=progress)
    draws = np.where(np.asarray(log_scale), np.exp(chain.chain_y), chain.chain_y)
    units = tuple("1" if n == "sigma_rel" else specs[circuit_of[n]].unit for n in names)
    return SharedPosterior(
        circuit=circuit, shared=start.shared, over=start.over, spectra=tuple(labels), names=tuple(names), units=units, log_scale=log_scale,
        draws=draws, log_prob=chain.log_prob, acceptance=chain.acceptance, priors=chosen, noise=noise, fit=start,
        sigma=np.asarray(ds["sigma"].transpose(*start.dataset["Z"].dims).values, float) if "sigma" in ds else None,
        settings={"walkers": int(walkers), "steps": int(chain.steps), **length_settings(chain, walkers), "burn": int(chain.burn), "thin": int(thin), "seed": int(seed), "elapsed_s": float(chain.elapsed_s)},
        registry=registry, stragglers=chain.stragglers,
    )
