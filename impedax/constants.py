"""Physical constants (SI) shared by the models and the reparametrizations of the fitting code, and
the fewest frequencies the analyses take (here, below JAX, so that ``impedax inspect`` can name
them without importing the fitting code)."""

IMPEDAX_VERSION = "0.1.0"
"""impedax's version (``impedax.__version__``; pyproject.toml's ``version``): here, at the bottom
layer, so that every writer can record it (`impedax.io.provenance`)."""

EPSILON_0 = 8.8541878128e-12
"""Vacuum permittivity ε0 [F/m] (CODATA 2018; docs/physics.md, "Conventions")."""

EPSILON_AIR = 1.00059
"""Relative permittivity of air used by Sirin et al. for the gap."""

C_GAP_BOUNDS_F = (1e-15, 1e-4)
"""Prior bounds of C_gap [F], 1 fF–100 µF, whatever the area: the capacitance is what the data
determine, so the bounds of u = ε0 ε_gap A/C_gap follow the area (`impedax.models.gap.gap_bounds`,
`impedax.fitting.gap_thickness_reparametrization`). They hold every fingertip contact
(`FINGERTIP_AREA_M2`) with u between 1 nm and 1 mm (8.9 fF–89 µF). A naive fit's C_gap outside
them counts as run away."""

DRT_POINTS_MIN = 5
"""The fewest frequencies `impedax.fitting.drt` takes (10 real equations for R_∞, L and a few RBFs)."""

CONCLUSIVE_POINTS_MIN = 10
"""The fewest frequencies for a conclusive Kramers–Kronig test (`impedax.fitting.kk`): below it
the chain (M ≤ N − 3 RC elements) is too stiff for the data, its misfit is the chain's own and
the noise estimate follows it, so the test cannot fail."""
