"""``impedax kk DATA``: linear Kramers–Kronig test — is the spectrum itself causal and stationary?"""

from __future__ import annotations


def register(sub) -> None:
    from .common import add_select_option

    p = sub.add_parser(
        "kk",
        help="linear Kramers-Kronig test of a spectrum (data problems vs model problems)",
        description="Fit a Kramers-Kronig-consistent Voigt chain (Schoenleber et al. 2014) and report where the data are not KK-consistent (drift, movement, non-stationarity). See docs/kk.md.",
    )
    p.add_argument("data", metavar="DATA", help="spectrum file (.csv or .nc) with one spectrum, or one picked with --select")
    p.add_argument("--method", choices=("linear", "zhit"), default="linear", help="linear: Voigt-chain KK test (default); zhit: |Z| reconstructed from the phase (Z-HIT, docs/drt.md)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE.png", help="save data vs KK fit and the residuals with bad bands shaded")
    p.add_argument("--c", type=float, default=0.85, help="µ cut-off (default 0.85)")
    p.add_argument("--max-rc", type=int, default=None, metavar="M", help="largest number of RC elements tried (default N/2)")
    p.add_argument("--no-inductance", action="store_true", help="no series inductance in the KK model")
    p.add_argument("--no-capacitance", action="store_true", help="no series capacitance in the KK model")
    add_select_option(p)
    p.set_defaults(run=run)


# JSON key → attribute of the result, per method (the keys are the public contract)
_KK_JSON = {
    "valid": "valid", "rms_rel": "rms_rel", "bad_bands": "bad_bands", "n_rc": "n_rc", "mu": "mu", "mu_reached": "mu_reached",
    "noise_estimate": "noise_estimate", "frequency_hz": "frequency", "residuals_real": "residuals_real", "residuals_imag": "residuals_imag",
}
_ZHIT_JSON = {
    "valid": "valid", "rms_rel": "rms_rel", "bad_bands": "bad_bands", "noise_estimate": "noise_estimate",
    "frequency_hz": "frequency", "modulus_zhit_ohm": "modulus", "residuals_modulus": "residuals",
}


def run(args) -> int:
    from ..fitting import kk_test, zhit
    from .common import emit_json, figure_writer, load_selected, plan_outputs

    outputs = plan_outputs([("--plot", args.plot, "figure")], inputs=[args.data])
    data = load_selected(args.data, args.select, single="impedax kk")
    if args.method == "zhit":
        result, keys, extra = zhit(data), _ZHIT_JSON, {"method": "zhit"}
    else:
        result = kk_test(data, c=args.c, max_rc=args.max_rc, inductance=not args.no_inductance, capacitance=not args.no_capacitance)
        keys, extra = _KK_JSON, {}
    outputs.save({"--plot": figure_writer(result.plot)})
    if args.json:
        out = {key: getattr(result, attribute) for key, attribute in keys.items()}
        out["bad_bands"] = [[lo, hi] for lo, hi in result.bad_bands]
        emit_json({**extra, **out})
    else:
        print(result.summary())
    return 0
