"""A gripper engineer's material × voltage walk (2026-12-01): `derive` over a batch of fits,
``fixed=``/``init=`` values per spectrum as a DataArray, ``impedax stack`` of files that are
already over a dimension, diagnose's chi2_red beside the noise and the name of its noise
source, the one-spectrum hint naming every dimension, and ``--models`` for ``--model``.
Every spectrum here is SYNTHETIC: numpy formulas with seeded noise."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
import pytest
import xarray as xr

import impedax as ix

from cli_run import run

FREQ = np.geomspace(1.0, 1e6, 31)  # Hz
EPS0 = 8.8541878128e-12  # F/m, CODATA 2018 vacuum permittivity
AREA = 4e-4  # m², a 2 cm × 2 cm gripper pad
MATERIALS = ("glass", "wood")
VOLTS = (50.0, 150.0)  # V
R_EP = {"glass": 2e8, "wood": 5e7}  # Ω, the material's leakage resistance
C_EP = {"glass": 1e-9, "wood": 3e-9}  # F, the material's double-layer capacitance
GAP_0 = {"glass": 4e-6, "wood": 12e-6}  # m, the air gap at no voltage


def gap(material, volt):
    """The air gap [m], shrinking with voltage (an invented law for the SYNTHETIC data)."""
    return GAP_0[material] / (1 + volt / 300.0)


def gripper_data(*, with_c_ep=True, noise=0.01, seed=75):
    """SYNTHETIC: R_EP ∥ C_EP ∥ C_gap (C_gap = ε0 A / u) over material × voltage × frequency,
    ``noise`` relative Gaussian noise per component, and that noise as a sigma column."""
    rng = np.random.default_rng(seed)
    w = 2 * np.pi * FREQ
    z = np.empty((len(MATERIALS), len(VOLTS), FREQ.size), complex)
    for i, m in enumerate(MATERIALS):
        for j, v in enumerate(VOLTS):
            y = 1 / R_EP[m] + 1j * w * EPS0 * AREA / gap(m, v) + (1j * w * C_EP[m] if with_c_ep else 0)
            z[i, j] = 1 / y
    noisy = z + noise * np.abs(z) * (rng.standard_normal(z.shape) + 1j * rng.standard_normal(z.shape))
    return ix.make_spectrum(FREQ, noisy, sigma=noise * np.abs(z), dims=("material", "voltage"), coords={"material": list(MATERIALS), "voltage": list(VOLTS)})


@pytest.fixture(scope="module")
def two_element_batch():
    """R_EP ∥ C_gap fitted to every spectrum of SYNTHETIC data without C_EP (both determined)."""
    return ix.fit("R_EP || C_gap", gripper_data(with_c_ep=False), weighting="sigma")


# --- 1. derive over a batch -----------------------------------------------------------------------

def gap_of(p):
    """u = ε0 A / C_gap [m]."""
    return EPS0 * AREA / p["C_gap"]


def test_derive_of_a_batch_refuses_a_posteriors_keyword(two_element_batch):
    with pytest.raises(ix.ParameterError, match=r"^derive: keyword 'draws' is not taken for a batch of fits \(delta method per spectrum\): it takes the keyword constants besides freq"):
        ix.derive(two_element_batch, gap_of, draws=True)


def test_derive_of_a_batch_is_each_spectrums_derive_over_the_batch_dimensions(two_element_batch):
    batch = two_element_batch
    derived = ix.derive(batch, gap_of)
    assert derived["value"].dims == ("material", "voltage") and derived["stderr"].dims == ("material", "voltage")
    assert derived["material"].values.tolist() == list(MATERIALS) and derived["voltage"].values.tolist() == list(VOLTS)
    c_gap, c_err = batch.values("C_gap"), batch.dataset["stderr"].sel(param="C_gap")
    for m in MATERIALS:
        for v in VOLTS:
            here = derived.sel(material=m, voltage=v)
            # hand delta method: u = k / C, σ_u = k σ_C / C²
            c, s = float(c_gap.sel(material=m, voltage=v)), float(c_err.sel(material=m, voltage=v))
            assert float(here["value"]) == pytest.approx(EPS0 * AREA / c, rel=1e-12)
            assert float(here["stderr"]) == pytest.approx(EPS0 * AREA * s / c**2, rel=1e-9)
            # the single fit's derive of the same spectrum (fit_of: a refit from the batch's optimum)
            one = ix.derive(batch.fit_of(material=m, voltage=v), gap_of)
            assert float(here["value"]) == pytest.approx(float(one["value"]), rel=1e-6)
            assert float(here["stderr"]) == pytest.approx(float(one["stderr"]), rel=1e-3)
            assert float(here["q95"]) == pytest.approx(float(one["q95"]), rel=1e-4)
            # and the truth within 4 standard errors (1 % noise)
            assert abs(float(here["value"]) - gap(m, v)) < 4 * float(here["stderr"])
    assert not derived["at_bound"].any()


def test_derive_of_a_batch_takes_a_drive_voltage_per_spectrum_as_a_constant(two_element_batch):
    """``constants={"V0": DataArray over voltage}``: each spectrum's fn sees its own V0, held
    exactly. Oracle, by hand: F = ε0 A V0² / (2u²) = C² V0² / (2 ε0 A), σ_F = C V0² σ_C / (ε0 A)
    (until 2026-12-03 fn saw the fitted parameters only, so a per-spectrum V0 needed a loop)."""
    batch = two_element_batch
    volts = xr.DataArray(list(VOLTS), dims="voltage", coords={"voltage": list(VOLTS)})

    def force(p):
        return EPS0 * AREA * p["V0"] ** 2 / (2 * gap_of(p) ** 2)

    derived = ix.derive(batch, force, constants={"V0": volts[::-1]})  # (matched by label, in any order)
    c_gap, c_err = batch.values("C_gap"), batch.dataset["stderr"].sel(param="C_gap")
    for m in MATERIALS:
        for v in VOLTS:
            here = derived.sel(material=m, voltage=v)
            c, s = float(c_gap.sel(material=m, voltage=v)), float(c_err.sel(material=m, voltage=v))
            assert float(here["value"]) == pytest.approx(c**2 * v**2 / (2 * EPS0 * AREA), rel=1e-12)
            assert float(here["stderr"]) == pytest.approx(c * v**2 * s / (EPS0 * AREA), rel=1e-9)
            assert float(here["constant_V0"]) == v
    assert derived["jacobian"]["free_param"].values.tolist() == ["R_EP", "C_gap"]  # (V0 held: no column of its own)
    # a number is every spectrum's; on a single fit, the closure's value
    same = ix.derive(batch, force, constants={"V0": 100.0})
    assert np.allclose(same["value"].values, c_gap.transpose("material", "voltage").values ** 2 * 100.0**2 / (2 * EPS0 * AREA), rtol=1e-12)
    one = batch.fit_of(material="glass", voltage=50.0)
    assert float(ix.derive(one, force, constants={"V0": 100.0})["value"]) == pytest.approx(float(ix.derive(one, lambda p: force({**p, "V0": 100.0}))["value"]), rel=1e-14)
    # what is refused, naming it
    with pytest.raises(ix.ParameterError, match=r"constants\['C_gap'\] has the name of a parameter of R_EP \|\| C_gap"):
        ix.derive(batch, force, constants={"C_gap": 1.0})
    with pytest.raises(ix.ParameterError, match=r"constants\['V0'\].*150"):
        ix.derive(batch, force, constants={"V0": xr.DataArray([50.0, 200.0], dims="voltage", coords={"voltage": [50.0, 200.0]})})
    with pytest.raises(ix.ParameterError, match=r"constants\['V0'\] is a DataArray over voltage; a single fit has one spectrum: give a number"):
        ix.derive(one, force, constants={"V0": volts})
    with pytest.raises(ix.ParameterError, match=r"constants\['V0'\] must be finite"):
        ix.derive(batch, force, constants={"V0": float("nan")})
    with pytest.raises(ix.ParameterError, match=r"fn asked for: unknown parameter 'V1' for R_EP \|\| C_gap \(parameters: R_EP, C_gap, V0\)"):
        ix.derive(batch, lambda p: p["V1"] * p["C_gap"], constants={"V0": 1.0})
    with pytest.raises(ix.ParameterError, match=r"keyword 'constant' is not taken .*did you mean constants\?"):
        ix.derive(batch, force, constant={"V0": 1.0})


def test_derive_of_a_batch_over_frequency_and_of_a_batch_saved_without_covariances(two_element_batch):
    batch = two_element_batch

    def magnitude(p, f):
        return jnp.abs(1 / (1 / p["R_EP"] + 2j * jnp.pi * f * p["C_gap"]))

    derived = ix.derive(batch, magnitude)
    assert derived["value"].dims == ("material", "voltage", "frequency")
    assert derived["covariance"].dims == ("material", "voltage", "frequency", "frequency_2")
    r, c = batch.values("R_EP").sel(material="wood", voltage=150.0), batch.values("C_gap").sel(material="wood", voltage=150.0)
    expected = np.abs(1 / (1 / float(r) + 2j * np.pi * FREQ * float(c)))
    np.testing.assert_allclose(derived["value"].sel(material="wood", voltage=150.0).values, expected, rtol=1e-10)
    # a batch written before each spectrum's covariance was stored: each spectrum's fit_of gives it
    older = ix.BatchFitResult.from_xarray(batch.to_xarray().drop_vars(["covariance", "free_param", "free_param_2"]))
    np.testing.assert_allclose(ix.derive(older, gap_of)["stderr"].values, ix.derive(batch, gap_of)["stderr"].values, rtol=1e-3)


# --- 2. fixed= and init= per spectrum ---------------------------------------------------------------

def test_fixed_as_a_dataarray_over_material_is_each_materials_fit_with_its_number():
    data = gripper_data()
    c_ep = xr.DataArray([C_EP["wood"], C_EP["glass"]], dims="material", coords={"material": ["wood", "glass"]})  # (another order than the data's)
    batch = ix.fit("R_EP || C_EP || C_gap", data, fixed={"C_EP": c_ep}, weighting="sigma")
    assert isinstance(batch, ix.BatchFitResult) and batch.dims == ("material", "voltage")
    for m in MATERIALS:
        alone = ix.fit("R_EP || C_EP || C_gap", data.sel(material=[m]), fixed={"C_EP": C_EP[m]}, weighting="sigma")
        for name in ("R_EP", "C_EP", "C_gap"):
            np.testing.assert_allclose(batch.values(name).sel(material=m).values, alone.values(name).sel(material=m).values, rtol=1e-6)
    assert batch.values("C_EP").sel(material="wood").values.tolist() == [C_EP["wood"]] * len(VOLTS)
    assert bool(batch.dataset["fixed"].sel(param="C_EP"))
    # the gap per material × voltage: within 4 standard errors of the truth
    derived = ix.derive(batch, gap_of)
    truth = np.array([[gap(m, v) for v in VOLTS] for m in MATERIALS])
    assert np.all(np.abs(derived["value"].values - truth) < 4 * derived["stderr"].values)
    # a spectrum's own fit keeps its material's value
    assert batch.fit_of(material="wood", voltage=50.0).values["C_EP"] == C_EP["wood"]


def test_init_as_a_dataarray_starts_each_spectrum_and_reaches_the_same_fits(two_element_batch):
    data = gripper_data(with_c_ep=False)
    start = xr.DataArray([[1e-9, 1e-9], [3e-10, 3e-10]], dims=("material", "voltage"), coords={"material": list(MATERIALS), "voltage": list(VOLTS)})
    batch = ix.fit("R_EP || C_gap", data, init={"C_gap": start}, weighting="sigma", n_starts=1)
    np.testing.assert_allclose(batch.values("C_gap").values, two_element_batch.values("C_gap").values, rtol=1e-5)


@pytest.mark.parametrize("value, expected", [
    (xr.DataArray([1e-9, 3e-9], dims="surface", coords={"surface": ["glass", "wood"]}), "is a DataArray over surface; one value per spectrum is over the data's extra dimensions (material, voltage)"),
    (xr.DataArray([1e-9, 3e-9], dims="material", coords={"material": ["glass", "paper"]}), "fixed['C_EP']: its labels along material (glass, paper) are not the data's (glass, wood): not in the data: paper; missing: wood"),
    (xr.DataArray([1e-9, 3e-9], dims="material"), "fixed['C_EP'] has no labels along material; the data's are glass, wood: label it"),
    (xr.DataArray([1e-9, np.nan], dims="material", coords={"material": ["glass", "wood"]}), "a DataArray of one value per spectrum must hold finite numbers"),
])
def test_a_dataarray_not_over_the_datas_spectra_is_refused_by_name(value, expected):
    with pytest.raises(ix.ParameterError) as caught:
        ix.fit("R_EP || C_EP || C_gap", gripper_data(), fixed={"C_EP": value})
    assert expected in str(caught.value), str(caught.value)


@pytest.mark.parametrize("value", [np.array([1e-9, 3e-9]), [1e-9, 3e-9]])
def test_a_bare_array_of_fixed_values_says_to_label_it(value):
    """An array (or list) in fixed= is refused before any fit, with how to give one value per
    spectrum (a walkthrough's note: the message said only "must be a number")."""
    with pytest.raises(ix.ParameterError) as caught:
        ix.fit("R_EP || C_EP || C_gap", gripper_data(), fixed={"C_EP": value})
    assert "fixed['C_EP'] must be a number, got an array of shape (2,): for one value per spectrum of a batch give an xarray.DataArray" in str(caught.value)


def test_a_function_of_one_spectrum_refuses_a_dataarray_and_says_where_it_belongs():
    one = gripper_data().isel(material=0, voltage=0)
    c_ep = xr.DataArray([1e-9, 3e-9], dims="material", coords={"material": list(MATERIALS)})
    with pytest.raises(ix.ParameterError, match=r"fixed\['C_EP'\] must be a number, got an xarray.DataArray over material: one value per spectrum is taken by fit's fixed="):
        ix.diagnose(one, "R_EP || C_EP || C_gap", fixed={"C_EP": c_ep})


# --- 3. impedax stack of files over a dimension ------------------------------------------------------

def test_stack_joins_files_over_voltage_along_a_new_material(tmp_path, capsys):
    data = gripper_data()
    paths = []
    for m in MATERIALS:
        one = data.sel(material=m).drop_vars("material")
        if m == "wood":  # (its voltages in another order: the stack lines them up by label)
            one = one.isel(voltage=[1, 0])
        paths.append(tmp_path / f"{m}.nc")
        ix.save(one, paths[-1])
    out = tmp_path / "all.nc"
    code, _, err = run(["stack", *paths, "--dim", "material", "--out", out], capsys)
    assert code == 0, err
    assert "4 spectra at 31 frequencies along 'material' (glass, wood) × voltage (2)" in err
    stacked = ix.load(out)
    assert stacked["Z"].dims == ("material", "voltage", "frequency")
    assert stacked["voltage"].values.tolist() == list(VOLTS)
    np.testing.assert_allclose(stacked["Z"].values, data["Z"].values, rtol=1e-12)
    np.testing.assert_allclose(stacked["sigma"].values, data["sigma"].values, rtol=1e-12)


def test_stack_refuses_files_of_other_labels_or_over_the_new_dimension(tmp_path, capsys):
    data = gripper_data()
    glass, wood = tmp_path / "glass.nc", tmp_path / "wood.nc"
    ix.save(data.sel(material="glass").drop_vars("material"), glass)
    ix.save(data.sel(material="wood").drop_vars("material").assign_coords(voltage=[50.0, 100.0]), wood)
    code, _, err = run(["stack", glass, wood, "--dim", "material", "--out", tmp_path / "all.nc"], capsys)
    assert code == 2 and "Traceback" not in err
    assert f"{wood}: its labels along voltage (50.0, 100.0) are not {glass}'s (50.0, 150.0): not in {glass}: 100.0; missing here: 150.0" in err, err
    glass_again = tmp_path / "glass_again.nc"  # (a copy: one file given twice is refused before, `stack_files`)
    glass_again.write_bytes(glass.read_bytes())
    code, _, err = run(["stack", glass, glass_again, "--dim", "voltage", "--coords", "a", "b", "--out", tmp_path / "all.nc"], capsys)
    assert code == 2 and "holds spectra over voltage already, voltage among them; the stack adds a new dimension: name it otherwise (--dim)" in err, err
    assert not (tmp_path / "all.nc").exists()


# --- 4. diagnose: chi2_red beside the noise, and the noise's source ------------------------------------

@pytest.mark.slow  # (8–18 s: the baseline's and the KK test's first compilation; no effect is tried)
def test_diagnose_says_what_chi2_red_is_against_and_names_a_sigma_column():
    from impedax.fitting.diagnosis.catalog import EffectCatalog

    one = gripper_data().sel(material="wood", voltage=50.0)
    diagnosis = ix.diagnose(one, "C_gap", effects=EffectCatalog(()), drt_evidence=False)
    first, noise_line = diagnosis.report().splitlines()[0], diagnosis.report().splitlines()[2]
    ratio = diagnosis.noise_ratio
    assert ratio > 5  # (C_gap alone misses the leakage R_EP by far more than the 1 % noise)
    assert f"(modulus weighting: residuals relative to |Z|, not to the noise; against the noise σ given below, chi2_red ≈ {ratio**2:.3g}, as the residuals are {ratio:.3g}× that noise)" in first
    # mean |Δ|²/(2σ²) from the data's own sigma: the figure the note gives
    z, sigma = one["Z"].values, one["sigma"].values
    by_hand = np.mean(np.abs(diagnosis.baseline.z_model - z) ** 2 / (2 * sigma**2))
    assert ratio**2 == pytest.approx(by_hand, rel=0.01)
    assert diagnosis.noise_source == "the data's sigma column" and "trial scatter" not in noise_line


def test_the_chi2_red_note_reads_as_chi2_red_against_the_noise_not_as_a_bound_on_sigma():
    """`Diagnosis._chi2_red_basis` on a stand-in (fast): "against the noise σ below ≈ 1.46e+03"
    read as "σ is below 1460" (walkthrough 2026-12-02); the figure is chi2_red against that σ,
    (the noise ratio)², here 38.2² = 1459.24 by hand."""
    from types import SimpleNamespace as NS

    from impedax.fitting.diagnosis.diagnosis import Diagnosis

    note = Diagnosis._chi2_red_basis(NS(baseline=NS(weighting="modulus"), noise_ratio=38.2))
    assert note == " (modulus weighting: residuals relative to |Z|, not to the noise; against the noise σ given below, chi2_red ≈ 1.46e+03, as the residuals are 38.2× that noise)"
    assert "σ below" not in note
    # under sigma weighting the weighting is named (since 2026-12-06; "" before), and the figure
    # against the noise below only where it differs from the fit's own chi2_red (38.2² = 1459)
    assert Diagnosis._chi2_red_basis(NS(baseline=NS(weighting="sigma", chi2_red=1459.0), noise_ratio=38.2)) == " (sigma weighting: residuals relative to the data's sigma)"
    assert Diagnosis._chi2_red_basis(NS(baseline=NS(weighting="sigma", chi2_red=4000.0), noise_ratio=38.2)).endswith("; against the noise σ given below, chi2_red ≈ 1.46e+03, as the residuals are 38.2× that noise)")


def test_a_sigma_from_trials_is_named_by_its_trials():
    from impedax.fitting.diagnosis.noise import sigma_origin

    # (the standard error of trial means since 2026-12-06, "trial scatter" before: tests/test_remainder_sigma_words.py)
    assert sigma_origin({"sigma_method": "SEM of Re and Im of each measurement over its trials"}) == "the standard error of trial means"
    assert sigma_origin({"n_trials": 5}) == "the standard error of trial means"
    assert sigma_origin({"source": "edl.csv"}) == "sigma column"


# --- 5. the one-spectrum hint names every dimension ----------------------------------------------------

def test_sample_of_a_two_dimensional_file_shows_a_select_for_each_dimension(tmp_path, capsys):
    path = tmp_path / "edl.nc"
    ix.save(gripper_data(), path)
    code, _, err = run(["sample", path, "--model", "R_EP || C_gap"], capsys)
    assert code == 2 and "Traceback" not in err
    assert "(material: glass, wood; voltage: 50.0, 150.0)" in err, err
    assert "pick one with --select material=LABEL --select voltage=LABEL (a label along each dimension), e.g. --select material=glass --select voltage=50.0" in err


# --- 6. a misspelt required option -----------------------------------------------------------------

def test_compare_with_models_for_model_says_did_you_mean(tmp_path, capsys):
    path = tmp_path / "one.csv"
    ix.save(gripper_data().sel(material="wood", voltage=50.0), path)
    code, _, err = run(["compare", path, "--models", "C_gap"], capsys)
    assert code == 2
    assert err.splitlines()[0] == "impedax compare: error: the following arguments are required: --model; did you mean --model? (--models is not an option of impedax compare)"
    code, _, err = run(["compare", path], capsys)  # (nothing misspelt: no guess)
    assert code == 2 and err.splitlines()[0] == "impedax compare: error: the following arguments are required: --model"
