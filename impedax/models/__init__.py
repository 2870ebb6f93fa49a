"""Paper models: Meyer (2012 thesis), Sirin et al., Vezzoli et al., and the SYNTHETIC example data.

Equations, conventions (peak vs time-average force) and assumptions: docs/models.md.
"""

from . import gap as gap, meyer as meyer, peak as peak, sirin as sirin, synthetic as synthetic, vezzoli as vezzoli
from ..constants import EPSILON_0 as EPSILON_0, EPSILON_AIR as EPSILON_AIR
from .meyer import (
    MeyerModel as MeyerModel,
    MeyerPhysical as MeyerPhysical,
    finger_voltage as finger_voltage,
    force_time_average as meyer_force,
    force_peak as meyer_force_peak,
    leaked_charge as leaked_charge,
    meyer_circuit as meyer_circuit,
    meyer_model as meyer_model,
    meyer_parameters as meyer_parameters,
)
from .gap import GapAnalysis as GapAnalysis, gap_analysis as gap_analysis
from .peak import ForceMaximum as ForceMaximum, force_maximum as force_maximum
from .sirin import (
    PaperGapEstimate as PaperGapEstimate,
    admittance_spectrum as admittance_spectrum,
    gap_capacitance_paper as gap_capacitance_paper,
    gap_force_peak as gap_force_peak,
    gap_force_time_average as gap_force_time_average,
    gap_thickness as gap_thickness,
    gap_voltage as gap_voltage,
    impedance_contributions as impedance_contributions,
    paper_gap_estimate as paper_gap_estimate,
    remainder_circuit as remainder_circuit,
    remainder_impedance as remainder_impedance,
    remaining_impedance as remaining_impedance,
    trial_mean as trial_mean,
)
from .synthetic import example_spectra as example_spectra, generate_sirin_synthetic as generate_sirin_synthetic, load_example as load_example
from .vezzoli import electrovibration_force as electrovibration_force, electrovibration_force_peak as electrovibration_force_peak, squeeze_film_lift as squeeze_film_lift, voltage_for_force as voltage_for_force
