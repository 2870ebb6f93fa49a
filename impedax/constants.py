"""Physical constants (SI) shared by the models and the reparametrizations of the fitting code."""

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
