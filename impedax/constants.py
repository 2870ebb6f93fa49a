"""Physical constants (SI) shared by the models and the reparametrizations of the fitting code."""

EPSILON_0 = 8.8541878128e-12
"""Vacuum permittivity ε0 [F/m] (CODATA 2018; docs/physics.md, "Conventions")."""

EPSILON_AIR = 1.00059
"""Relative permittivity of air used by Sirin et al. for the gap."""
