"""The whole Sirin et al. workflow: from three measured spectra to the air-gap thickness, the
gap voltage and the electrostatic force, with uncertainty.

1. remaining impedance Z_R = Z_total − Z_skin − Z_TS from the trial means, with the SEM
   propagated (eq 5; `remaining_impedance`);
2. the paper's estimate: C_gap = mean |Y_R|/ω above the cutoff, u = ε0 ε_gap A/C_gap, bounds
   from the lowest and highest impedances (`paper_gap_estimate`);
3. least-squares fits of the naive model (C_gap alone) and of the EDL parallel model with the
   electrode-polarization branch (`remainder_circuit(ep)`);
4. Bayesian sampling of the EDL model with the gap thickness u itself as a parameter
   (C_gap = ε0 ε_gap A/u; `gap_thickness_reparametrization`);
5. the gap voltage and the PEAK force of eq 1, F = ½ ε0 A |ΔV_gap|²/u², over frequency for a
   drive of amplitude V0, as posterior bands, with and without the EP branch.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from ..circuits import parse
from ..arguments import MAX_SAMPLER_STEPS, MAX_WALKERS, checked_arguments, choice, count, flag, real, seed
from ..errors import CircuitError, DataError
from ..constants import EPSILON_AIR
from .sirin import SIRIN_AREA, SIRIN_DRIVE_V, PaperGapEstimate, gap_force_peak, paper_gap_estimate, remainder_circuit, remaining_impedance, trial_mean

__all__ = ["GapAnalysis", "gap_analysis"]

FORCE_CONVENTION = "peak"  # eq 1 at the voltage amplitude; the time average is half of it


@dataclass(frozen=True, eq=False)
class GapAnalysis:
    """Result of `gap_analysis`. Lengths in m and capacitances in F inside; `summary` gives µm.

    The credible interval of u reflects the noise of the trial means (their SEM per frequency,
    taken as independent across frequencies). Variation of the contact from trial to trial
    that is common to all frequencies of a trial is not in it; the paper's bounds (extreme
    trials) show that spread, so both are reported side by side.

    ``force`` holds the PEAK force [N] bands over frequency (``median``, ``q05``, ``q95``) with
    the EP branch (``with_ep``) and without it (``without_ep``, same C_gap draws).
    """

    remaining: xr.Dataset
    paper: PaperGapEstimate
    naive_fit: object
    edl_fit: object
    posterior: object
    force: xr.Dataset
    area: float
    v0: float
    ep: str
    warnings: tuple[str, ...] = field(default=())

    def _quantiles(self, name: str) -> dict[str, float]:
        draws = self.posterior.parameter_draws()[name]
        q05, q50, q95 = np.quantile(draws, [0.05, 0.5, 0.95])
        return {"value": float(q50), "q05": float(q05), "q95": float(q95)}

    @property
    def c_gap(self) -> dict[str, float]:
        """Posterior median and 90% interval of C_gap [F]."""
        return self._quantiles("C_gap")

    @property
    def gap(self) -> dict[str, float]:
        """Posterior median and 90% interval of the gap thickness u [m]."""
        return self._quantiles("u")

    def summary(self) -> dict:
        """The JSON used by ``impedax gap --json``."""
        gap_um = {k: v * 1e6 for k, v in self.gap.items()}
        with_ep = self.force.sel(branch="with_ep")
        return {
            "c_gap": self.c_gap,
            "gap_um": gap_um,
            "force_n": {
                "frequency_hz": self.force["frequency"].values,
                "median": with_ep["median"].values,
                "q05": with_ep["q05"].values,
                "q95": with_ep["q95"].values,
            },
            "force_without_ep_n": {k: self.force.sel(branch="without_ep")[k].values for k in ("median", "q05", "q95")},
            "convention": FORCE_CONVENTION,
            "paper_method": {
                "c_gap": self.paper.c_gap,
                "gap_um": self.paper.gap * 1e6,
                "gap_bounds_um": [self.paper.gap_lower * 1e6, self.paper.gap_upper * 1e6],
            },
            "model": self.edl_fit.model,
            "naive_rms_rel": self.naive_fit.rms_rel,
            "edl_rms_rel": self.edl_fit.rms_rel,
            "area_m2": self.area,
            "v0": self.v0,
            "warnings": list(self.warnings),
        }

    def to_table(self) -> list[dict[str, object]]:
        """The tidy table of C_gap [F] and u [m]: ``method`` bayes (value: posterior median;
        low/high: the 90% credible interval) and paper (the paper's method; for u its bounds
        from the lowest/highest impedances)."""
        p = self.paper
        interval = lambda q: {"value": q["value"], "low": q["q05"], "high": q["q95"]}  # noqa: E731
        return [
            {"name": "C_gap", "method": "bayes", **interval(self.c_gap), "unit": "F"},
            {"name": "u", "method": "bayes", **interval(self.gap), "unit": "m"},
            {"name": "C_gap", "method": "paper", "value": p.c_gap, "low": None, "high": None, "unit": "F"},
            {"name": "u", "method": "paper", "value": p.gap, "low": p.gap_lower, "high": p.gap_upper, "unit": "m"},
        ]

    def report(self) -> str:
        g, c, p = self.gap, self.c_gap, self.paper
        peak = self.force.sel(branch="with_ep")["median"]
        i = int(np.argmax(peak.values))
        lines = [
            f"gap thickness u = {g['value'] * 1e6:.3f} µm  (90% credible interval {g['q05'] * 1e6:.3f}–{g['q95'] * 1e6:.3f} µm, Bayesian, {self.edl_fit.model})",
            f"paper method    u = {p.gap * 1e6:.3f} µm  (bounds {p.gap_lower * 1e6:.3f}–{p.gap_upper * 1e6:.3f} µm from the lowest/highest impedances)",
            f"C_gap           = {c['value'] * 1e12:.1f} pF (90%: {c['q05'] * 1e12:.1f}–{c['q95'] * 1e12:.1f} pF); paper method {p.c_gap * 1e12:.1f} pF",
            f"fits            naive C_gap: rms_rel {self.naive_fit.rms_rel:.3g};  {self.edl_fit.model}: rms_rel {self.edl_fit.rms_rel:.3g}",
            f"force (peak, V0 = {self.v0:g} V) with EP: max {float(peak[i]) * 1e3:.3g} mN at {float(peak['frequency'][i]):.3g} Hz",
        ]
        lines += [f"warning: {w}" for w in self.warnings]
        return "\n".join(lines)

    def plot(self, *, true_gap: float | None = None):
        """Remaining impedance with both fits, the posterior of u against the paper's bounds
        (and ``true_gap`` [m] when known, e.g. for synthetic data), and the force bands with and
        without the EP branch (matplotlib Figure)."""
        from ..plotting.models import plot_gap_analysis

        return plot_gap_analysis(self, true_gap=true_gap)


    def to_xarray(self) -> xr.Dataset:
        out = self.force.copy()
        for key, value in self.summary().items():
            if key in ("c_gap", "gap_um"):
                for k, v in value.items():
                    out.attrs[f"{key}_{k}"] = v
        out.attrs.update({"convention": FORCE_CONVENTION, "model": self.edl_fit.model, "area_m2": self.area, "v0": self.v0})
        return out


@checked_arguments(
    area=real(positive=True), v0=real(positive=True), ep=choice(("C", "CPE")), eps_gap=real(positive=True), cutoff_hz=real(positive=True),
    steps=count(1, MAX_SAMPLER_STEPS), walkers=count(2, MAX_WALKERS, optional=True), seed=seed, progress=flag,
)
def gap_analysis(
    total: xr.Dataset,
    skin: xr.Dataset,
    touchscreen: xr.Dataset,
    *,
    area: float = SIRIN_AREA,
    v0: float = SIRIN_DRIVE_V,
    ep: str = "CPE",
    eps_gap: float = EPSILON_AIR,
    cutoff_hz: float = 30.0,
    steps: int = 1500,
    walkers: int | None = None,
    seed: int = 0,
    progress: bool = True,
    remainder=None,
    edl_fit=None,
) -> GapAnalysis:
    """Run the Sirin workflow (module docstring) on three spectrum Datasets with trial
    dimensions, all on one frequency grid. ``ep`` picks the EP branch of the EDL model:
    ``"CPE"`` (R_EP || CPE_EP || C_gap, default) or ``"C"`` (R_EP || C_EP || C_gap — note that
    two ideal capacitors in parallel are identified only as their sum). ``remainder`` replaces
    the EDL model by any circuit holding a ``C_gap`` (e.g. the result of `impedax.refine`), and
    ``edl_fit`` reuses a least-squares fit of it. Returns a `GapAnalysis`.
    """
    from ..fitting import fit, gap_thickness_reparametrization, sample

    if not area > 0:
        raise DataError(f"area must be positive (m²), got {area}")
    remaining = remaining_impedance(total, skin, touchscreen)
    paper = paper_gap_estimate(total, skin, touchscreen, area=area, cutoff_hz=cutoff_hz, eps_gap=eps_gap)
    weighting = "sigma" if "sigma" in remaining else "modulus"
    circuit = remainder_circuit(ep) if remainder is None else parse(remainder)
    if "C_gap" not in circuit.element_names:
        raise CircuitError(f"the remainder model {circuit} has no element named C_gap")
    naive = fit(remainder_circuit(None), remaining, weighting=weighting)
    edl = edl_fit if edl_fit is not None else fit(circuit, remaining, weighting=weighting)
    posterior = sample(
        circuit,
        remaining,
        noise="sigma" if weighting == "sigma" else "proportional",
        reparametrization=gap_thickness_reparametrization("C_gap", area=area, eps_r=eps_gap),
        init=edl,
        steps=steps,
        walkers=walkers,
        seed=seed,
        progress=progress,
    )
    freq = remaining["frequency"].values
    z_skin = trial_mean(skin)["Z"].values
    z_ts = trial_mean(touchscreen)["Z"].values
    bands = []
    for branch, model in (("with_ep", str(circuit)), ("without_ep", "C_gap")):
        q = posterior.derive(lambda p, f, m=model: gap_force_peak(p, f, z_skin, z_ts, area=area, v0=v0, remainder=m, eps_gap=eps_gap), freq)
        bands.append(xr.Dataset({k: ("frequency", np.asarray(q[k].values)) for k in ("median", "q05", "q95")}, coords={"frequency": freq}))
    force = xr.concat(bands, dim=xr.DataArray(["with_ep", "without_ep"], dims="branch"))
    force["median"].attrs.update(units="N", convention=FORCE_CONVENTION)
    notes = [f"EDL fit: {w}" for w in edl.warnings] + [f"sampling: {w}" for w in posterior.warnings if not w.startswith("least-squares start")]
    u_lo, u_hi = posterior.parameter_draws()["u"].min(), posterior.parameter_draws()["u"].max()
    if not (paper.gap_lower <= np.median(posterior.parameter_draws()["u"]) <= paper.gap_upper):
        notes.append(f"the Bayesian gap thickness lies outside the paper method's bounds ({paper.gap_lower * 1e6:.2f}–{paper.gap_upper * 1e6:.2f} µm; draws span {u_lo * 1e6:.2f}–{u_hi * 1e6:.2f} µm)")
    return GapAnalysis(remaining, paper, naive, edl, posterior, force, area, v0, ep, tuple(notes))
