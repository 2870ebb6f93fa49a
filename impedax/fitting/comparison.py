"""Model comparison: rms_rel, reduced chi², AIC, BIC, ΔAIC, Akaike weights and, for nested
models fitted to the same data, the F-test of the extra parameters."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np
import xarray as xr

from ..arguments import checked_arguments, sequence_of
from ..circuits import Circuit, Element
from ..errors import FitError
from .least_squares import FitResult
from .least_squares.branches import undetermined

__all__ = ["compare", "Comparison", "is_nested", "undetermined_names"]


def _nested(a: Circuit, b: Circuit) -> bool:
    """True when ``a`` is ``b`` with elements removed (a series element set to 0, a parallel
    branch opened) and/or CPEs replaced by capacitors (α = 1)."""
    if isinstance(a, Element) and isinstance(b, Element):
        return a.symbol == b.symbol or (a.symbol == "C" and b.symbol in ("CPE", "Q"))
    if isinstance(b, Element):
        return False
    if type(a) is type(b):
        return _subsequence(a.children, b.children)
    return any(_nested(a, child) for child in b.children)


def _subsequence(small, big) -> bool:
    """Each child of ``small`` nested in a distinct child of ``big``, in any order (impedances
    in series and admittances in parallel add in any order: ``R1 || CPE1`` is nested in
    ``CPE1 || (R1 + W1)``)."""

    def match(i: int, used: frozenset) -> bool:
        if i == len(small):
            return True
        return any(j not in used and _nested(small[i], big[j]) and match(i + 1, used | {j}) for j in range(len(big)))

    return len(small) <= len(big) and match(0, frozenset())


def undetermined_names(fit: FitResult) -> list[str]:
    """The free parameters of ``fit`` the data do not determine: off their bounds, nonzero, with
    a relative standard error above 100 % (`branches.undetermined`), as its warnings say."""
    return [n for n in fit.free_names if n not in fit.at_bound and undetermined(fit.values[n], fit.stderr[n])]


def is_nested(simple: Circuit, complex_: Circuit) -> bool:
    """Whether ``simple`` is a special case of ``complex_`` (see `_nested`)."""
    return _nested(simple, complex_) and len(list(simple.elements())) <= len(list(complex_.elements()))


@dataclass(frozen=True, eq=False)
class Comparison:
    """The comparison table, one row per model in the order given; ``best`` has the lowest AIC."""

    rows: tuple[dict, ...]
    f_tests: tuple[dict, ...]
    fits: tuple[FitResult, ...]

    @property
    def best_index(self) -> int:
        """Position of the best model by AIC in ``rows`` and ``fits`` (models may repeat: the
        same circuit fixed and free)."""
        return min(range(len(self.rows)), key=lambda i: self.rows[i]["aic"])

    @property
    def best_determined_index(self) -> int | None:
        """Position of `best_determined`, or None."""
        determined = [i for i, f in enumerate(self.fits) if not undetermined_names(f)]
        return min(determined, key=lambda i: self.rows[i]["aic"]) if determined else None

    @property
    def best(self) -> str:
        return self.rows[self.best_index]["model"]

    @property
    def best_determined(self) -> str | None:
        """The model of lowest AIC among the fits that leave no parameter undetermined
        (`undetermined_names`); None when every fit leaves one."""
        i = self.best_determined_index
        return None if i is None else self.rows[i]["model"]

    def summary(self) -> dict:
        """JSON form used by ``impedax compare --json``."""
        return {"models": [dict(r) for r in self.rows], "best": self.best, "best_determined": self.best_determined, "f_tests": [dict(t) for t in self.f_tests]}

    def _best_mark(self) -> str:
        """The table's mark of the best model by AIC, saying when its fit did not converge or has
        warnings (an undetermined parameter, a gross misfit): the lowest AIC is then no
        endorsement; and when another model gives the same fit (`SAME_FIT_RMS`)."""
        best = self.best_index
        warnings = self.fits[best].warnings
        n = len({w for ws in warnings.values() for w in ws}) if isinstance(warnings, Mapping) else len(warnings)
        mark = "   ← best" + (f" by AIC, with {n} warning(s) below" if n else "")
        if not self.rows[best]["converged"]:
            mark += " (its fit did not converge)"
        if self.rows[best].get("same_fit_as"):
            mark += f"; tied with {self.rows[best]['same_fit_as']}: the same fit, the data cannot tell them apart"
        return mark

    def report(self) -> str:
        """The table, then each model's warnings."""
        lines = [self.table()]
        for fit in self.fits:
            warnings = [w for ws in fit.warnings.values() for w in ws] if isinstance(fit.warnings, Mapping) else list(fit.warnings)
            if warnings:
                lines += [f"{fit.model}:"] + [f"  - {w}" for w in warnings]
        return "\n".join(lines)

    def table(self) -> str:
        extra = [c for c in ("log_evidence", "waic") if any(c in r for r in self.rows)]
        width = max(len(r["model"]) for r in self.rows)
        head = f"{'model':<{width}}  {'k':>2}  {'rms_rel':>9}  {'chi2_red':>10}  {'AIC':>9}  {'BIC':>9}  {'ΔAIC':>7}  {'weight':>6}" + "".join(f"  {c:>12}" for c in extra)
        lines = [head]
        best = self.best_index
        for i, r in enumerate(self.rows):
            line = f"{r['model']:<{width}}  {r['n_params']:>2}  {r['rms_rel'] * 100:>8.3g}%  {r['chi2_red']:>10.4g}  {r['aic']:>9.2f}  {r['bic']:>9.2f}  {r['delta_aic']:>7.2f}  {r['akaike_weight']:>6.3f}"
            line += "".join(f"  {r.get(c, math.nan):>12.2f}" for c in extra)
            if i == best:
                line += self._best_mark()
            else:
                line += "   (did not converge)" if not r["converged"] else ""
                line += f"   (the same fit as {r['same_fit_as']})" if r.get("same_fit_as") else ""
            lines.append(line)
        determined = self.best_determined_index
        if determined != best:
            lines.append(
                f"{self.best} leaves {', '.join(undetermined_names(self.fits[best]))} undetermined; "
                + (f"the best model with every parameter determined is {self.rows[determined]['model']} (ΔAIC {self.rows[determined]['delta_aic']:.2f})" if determined is not None
                   else "so does every other model" if len(self.rows) > 1 else "there is no other model")
            )
        for t in self.f_tests:
            test = f"F = {t['f']:.3g}, p = {t['p_value']:.3g}" if t.get("valid", True) else f"no test: {t['note']}"
            lines.append(f"F-test {t['simple']}  ⊂  {t['complex']}: {test}")
        return "\n".join(lines)

    def to_xarray(self) -> xr.Dataset:
        models = [r["model"] for r in self.rows]
        cols = [c for c in self.rows[0] if c != "model"]
        return xr.Dataset({c: ("model", [r.get(c, math.nan) for r in self.rows]) for c in cols}, coords={"model": models})

    def plot(self):
        """Data with every model's fit, and each model's relative residuals (Figure;
        `plotting.comparison.plot_comparison`)."""
        from ..plotting.comparison import plot_comparison

        return plot_comparison(self)


@checked_arguments(fits=sequence_of(FitResult, attribute="fit", what="FitResult (or Posterior)"))
def compare(fits: Sequence) -> Comparison:
    """Compare least-squares fits of several models to the same data.

    Columns: rms_rel, chi2_red, AIC, BIC, ΔAIC (to the lowest), Akaike weights
    w_i = exp(−ΔAIC_i/2)/Σ exp(−ΔAIC_j/2), and an F-test for each nested pair:
    F = ((χ²_s − χ²_c)/(k_c − k_s)) / (χ²_c/(n − k_c)). Items may also be posteriors with a
    ``fit`` attribute; their ``log_evidence`` and ``waic`` become extra columns.
    """
    items = list(fits)
    if len(items) < 1:
        raise FitError("compare needs at least one fit")
    results = [getattr(x, "fit", x) for x in items]
    ref = results[0]
    for r in results[1:]:
        if r.n_points != ref.n_points or not np.allclose(r.frequency, ref.frequency) or not np.allclose(r.z_data, ref.z_data):
            raise FitError(f"models were fitted to different data ({r.model} vs {ref.model}); compare fits of the same spectrum")
        if r.weighting != ref.weighting:
            raise FitError(f"models were fitted with different weightings ({r.weighting} vs {ref.weighting})")
    aics = np.array([r.aic for r in results])
    delta = aics - aics.min()
    weights = np.exp(-delta / 2)
    weights /= weights.sum()
    rows = []
    for item, r, d, w in zip(items, results, delta, weights):
        row = {"model": r.model, "n_params": r.n_params, "rms_rel": r.rms_rel, "chi2": r.chi2, "chi2_red": r.chi2_red, "aic": r.aic, "bic": r.bic, "delta_aic": float(d), "akaike_weight": float(w), "converged": r.converged}
        for extra in ("log_evidence", "waic"):
            value = getattr(item, extra, None)
            if value is not None:
                row[extra] = float(value() if callable(value) else value)
        rows.append(row)
    for j, r in enumerate(results):  # a fit another model also gives: the data cannot tell them apart
        twin = next((rows[i]["model"] for i in range(len(results)) if i != j and _same_fit(results[i], r)), None)
        rows[j]["same_fit_as"] = twin
    tests = []
    n = 2 * ref.n_points
    from scipy import stats

    for s in results:
        for c in results:
            if s is c or s.n_params >= c.n_params or not is_nested(s.circuit, c.circuit):
                continue
            dk = c.n_params - s.n_params
            denom = c.chi2 / (n - c.n_params)
            f_value = max(s.chi2 - c.chi2, 0.0) / dk / denom if denom > 0 else math.inf
            test = {"simple": s.model, "complex": c.model, "f": float(f_value), "df1": dk, "df2": n - c.n_params, "p_value": float(stats.f.sf(f_value, dk, n - c.n_params)), "valid": True, "note": None}
            if c.chi2 > s.chi2 * (1 + 1e-9):
                test.update(valid=False, note=f"{c.model} fits worse than {s.model}, which it contains: its fit did not reach its optimum")
            elif c.chi2_red < EXACT_CHI2_RED:
                test.update(valid=False, note=f"{c.model} fits the data to rounding (chi2_red {c.chi2_red:.1e}): noise-free data, nothing to test against")
            tests.append(test)
    return Comparison(tuple(rows), tuple(tests), tuple(results))


SAME_FIT_RMS = 1e-3
"""Two fits are one fit when they have as many parameters, χ² within 1e-6 (relative) and model
spectra whose difference (rms, relative to |Z_data|) is below this fraction of their misfit
rms_rel (or below 1e-9): two writings of one impedance function (two arcs in series and the
ladder form), which would split the Akaike weight and the "best" by rounding."""
EXACT_CHI2_RED = 1e-20
"""Below this reduced χ² a fit is exact to rounding (noise-free data): an F-test compares
rounding errors."""


def _same_fit(a: FitResult, b: FitResult) -> bool:
    if a.n_params != b.n_params or not abs(a.chi2 - b.chi2) <= 1e-6 * max(a.chi2, b.chi2, 1e-300):
        return False
    with np.errstate(all="ignore"):
        rms = float(np.sqrt(np.mean(np.abs((a.z_model - b.z_model) / np.abs(a.z_data)) ** 2)))
    return rms < max(SAME_FIT_RMS * max(a.rms_rel, b.rms_rel), 1e-9)
