"""``impedax kk DATA``: linear Kramers–Kronig test — is the spectrum itself causal and stationary?"""

from __future__ import annotations


def register(sub) -> None:
    p = sub.add_parser(
        "kk",
        help="linear Kramers-Kronig test of a spectrum (data problems vs model problems)",
        description="Fit a Kramers-Kronig-consistent Voigt chain (Schoenleber et al. 2014) and report where the data are not KK-consistent (drift, movement, non-stationarity). See docs/kk.md.",
    )
    p.add_argument("data", metavar="DATA", help="spectrum file (.csv or .nc) with one spectrum")
    p.add_argument("--method", choices=("linear", "zhit"), default="linear", help="linear: Voigt-chain KK test (default); zhit: |Z| reconstructed from the phase (Z-HIT, docs/drt.md)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE.png", help="save data vs KK fit and the residuals with bad bands shaded")
    p.add_argument("--c", type=float, default=0.85, help="µ cut-off (default 0.85)")
    p.add_argument("--max-rc", type=int, default=None, metavar="M", help="largest number of RC elements tried (default N/2)")
    p.add_argument("--no-inductance", action="store_true", help="no series inductance in the KK model")
    p.add_argument("--no-capacitance", action="store_true", help="no series capacitance in the KK model")
    p.set_defaults(run=run)


def run(args) -> int:
    from ..fitting import kk_test
    from ..io import load
    from .common import check_outputs, emit_json, save_outputs

    check_outputs(args.plot)
    data = load(args.data)
    if args.method == "zhit":
        return _run_zhit(args, data)
    result = kk_test(data, c=args.c, max_rc=args.max_rc, inductance=not args.no_inductance, capacitance=not args.no_capacitance)
    save_outputs(plot=args.plot, figure=result.plot)
    if args.json:
        emit_json({
            "valid": result.valid,
            "rms_rel": result.rms_rel,
            "bad_bands": [[lo, hi] for lo, hi in result.bad_bands],
            "n_rc": result.n_rc,
            "mu": result.mu,
            "mu_reached": result.mu_reached,
            "noise_estimate": result.noise_estimate,
            "frequency_hz": result.frequency,
            "residuals_real": result.residuals_real,
            "residuals_imag": result.residuals_imag,
        })
        return 0
    print(result.summary())
    return 0


def _run_zhit(args, data) -> int:
    from ..fitting import zhit
    from .common import emit_json, save_outputs

    result = zhit(data)
    save_outputs(plot=args.plot, figure=result.plot)
    if args.json:
        emit_json({
            "method": "zhit",
            "valid": result.valid,
            "rms_rel": result.rms_rel,
            "bad_bands": [[lo, hi] for lo, hi in result.bad_bands],
            "noise_estimate": result.noise_estimate,
            "frequency_hz": result.frequency,
            "modulus_zhit_ohm": result.modulus,
            "residuals_modulus": result.residuals,
        })
        return 0
    print(result.summary())
    return 0
