"""Wrong types in every argument of impedax's public functions, run in one process (not a test:
a tool, the Python side of tests/cli_fuzz_matrix.py).

    PYTHONPATH=$PWD python tests/api_fuzz_matrix.py [WORD]

Each call passes one bad value (a list, a dict, None, text, a missing path, a folder, arrays of
the wrong shape, a complex number, Datasets without Z or of one point, bytes, bools, NaN, a
generator, an object, a set, 10**400) in one argument. A call is flagged when it raises anything
but an `ImpedaxError`, when its message is over 600 characters, or when it runs over 120 s
(docs/robustness.md, "The command-line matrix")."""

import os
import signal
import sys
import tempfile
import traceback

import numpy as np
import xarray as xr

import impedax as ix
from impedax.errors import ImpedaxError

os.chdir(tempfile.mkdtemp())
f = np.geomspace(1, 1e5, 21); z = 10 + 100/(1+2j*np.pi*f*1e-4)
ds = ix.make_spectrum(f, z)
os.makedirs("adir", exist_ok=True)
RC = "R0 + R1 || C1"
bad_values = {
 "list-numbers": [1.0, 2.0, 3.0], "list-complex": list(z), "dict": {"a": 1}, "None": None, "empty-str": "", "missing-path": "nope.csv",
 "dir": "adir", "2d-array": np.ones((3, 3)), "complex-scalar": 1+2j, "ds-no-Z": xr.Dataset({"x": ("frequency", f)}, coords={"frequency": f}),
 "dataarray-real": xr.DataArray(np.abs(z), dims="frequency", coords={"frequency": f}), "bytes": b"R1", "True": True, "int": 3, "nan": float("nan"),
 "tuple-3": (f, z, z), "tuple-mismatch": (f, z[:5]), "generator": (x for x in range(3)), "ds-one-point": ds.isel(frequency=[3]),
 "object": object(), "set": {1, 2}, "neg-int": -5, "huge-int": 10**400,
}
calls = {
 "fit(circuit=X)": lambda v: ix.fit(v, ds), "fit(data=X)": lambda v: ix.fit(RC, v), "fit(init=X)": lambda v: ix.fit(RC, ds, init=v),
 "fit(fixed=X)": lambda v: ix.fit(RC, ds, fixed=v), "fit(bounds=X)": lambda v: ix.fit(RC, ds, bounds=v), "fit(weighting=X)": lambda v: ix.fit(RC, ds, weighting=v),
 "fit(fmin=X)": lambda v: ix.fit(RC, ds, fmin=v), "fit(max_steps=X)": lambda v: ix.fit(RC, ds, max_steps=v), "fit(n_starts=X)": lambda v: ix.fit(RC, ds, n_starts=v),
 "fit(shared=X)": lambda v: ix.fit(RC, ds, shared=v), "fit(registry=X)": lambda v: ix.fit(RC, ds, registry=v), "fit(progress=X)": lambda v: ix.fit(RC, ds, progress=v),
 "kk_test(X)": lambda v: ix.kk_test(v), "kk_test(c=X)": lambda v: ix.kk_test(ds, c=v), "kk_test(max_rc=X)": lambda v: ix.kk_test(ds, max_rc=v),
 "drt(X)": lambda v: ix.drt(v), "drt(lam=X)": lambda v: ix.drt(ds, lam=v), "zhit(X)": lambda v: ix.zhit(v),
 "diagnose(X)": lambda v: ix.diagnose(v, RC), "diagnose(circuit=X)": lambda v: ix.diagnose(ds, v), "diagnose(noise=X)": lambda v: ix.diagnose(ds, RC, noise=v),
 "refine(X)": lambda v: ix.refine(v, RC), "refine(max_effects=X)": lambda v: ix.refine(ds, RC, max_effects=v),
 "compare(models=X)": lambda v: ix.compare(v, ds), "compare(data=X)": lambda v: ix.compare([RC, "R0 + C1"], v),
 "sample(X)": lambda v: ix.sample(RC, v, steps=20), "sample(steps=X)": lambda v: ix.sample(RC, ds, steps=v), "sample(walkers=X)": lambda v: ix.sample(RC, ds, steps=20, walkers=v),
 "sample(priors=X)": lambda v: ix.sample(RC, ds, steps=20, priors=v),
 "load(X)": lambda v: ix.load(v), "save(X, path)": lambda v: ix.save(v, "out.nc"), "save(ds, X)": lambda v: ix.save(ds, v),
 "make_spectrum(f=X)": lambda v: ix.make_spectrum(v, z), "make_spectrum(z=X)": lambda v: ix.make_spectrum(f, v), "make_spectrum(sigma=X)": lambda v: ix.make_spectrum(f, z, sigma=v),
 "parse(X)": lambda v: ix.parse(v), "validate_spectrum(X)": lambda v: ix.validate_spectrum(v), "log_frequencies(X)": lambda v: ix.log_frequencies(v, 1e3, 5),
 "log_frequencies(n=X)": lambda v: ix.log_frequencies(1, 1e3, v), "write_result(X)": lambda v: ix.write_result(v, "out.json"),
 "write_result(r, X)": lambda v: ix.write_result(FIT, v), "derive(X)": lambda v: ix.derive(v, lambda p: p["R0"]), "derive(fn=X)": lambda v: ix.derive(FIT, v),
 "compile_circuit(X)": lambda v: ix.compile_circuit(v), "compiled(params=X)": lambda v: ix.compile_circuit(RC)(v, f), "compiled(freq=X)": lambda v: ix.compile_circuit(RC)({"R0": 1, "R1": 1, "C1": 1e-6}, v),
 "voltage_across(X)": lambda v: ix.voltage_across(RC, v), "to_cdc(X)": lambda v: ix.to_cdc(v), "from_cdc(X)": lambda v: ix.from_cdc(v),
 "from_impedance_py(X)": lambda v: ix.from_impedance_py(v), "stack_files(X)": lambda v: ix.stack_files(v), "draw_circuit(X)": lambda v: ix.draw_circuit(v),
 "FitResult.predict(X)": lambda v: FIT.predict(v), "kk_test_batch(X)": lambda v: ix.kk_test_batch(v),
}
FIT = ix.fit(RC, ds)
class T(BaseException): pass
def alarm(*a): raise T()
signal.signal(signal.SIGALRM, alarm)
n = 0; flagged = []
only = sys.argv[1] if len(sys.argv) > 1 else ""
for cname, call in calls.items():
    if only and only not in cname: continue
    for vname, v in bad_values.items():
        if vname == "generator": v = (x for x in range(3))
        n += 1
        signal.alarm(120)
        try:
            call(v)
            res = "ok"
        except ImpedaxError as e:
            res = "impedax"
            if len(str(e)) > 600: flagged.append((cname, vname, f"long message {len(str(e))}"))
        except T:
            res = "timeout"; flagged.append((cname, vname, "timeout"))
        except BaseException as e:
            res = type(e).__name__
            tb = traceback.format_exc().strip().splitlines()
            flagged.append((cname, vname, f"{type(e).__name__}: {str(e)[:200]} @ {[l for l in tb if 'File' in l][-1].strip()[:150]}"))
        finally:
            signal.alarm(0)
print(n, "calls,", len(flagged), "flagged")
for x in flagged: print("FLAG", *x)
sys.exit(1 if flagged else 0)
