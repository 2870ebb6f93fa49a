"""Distribution of relaxation times (DRT): the hypothesis-free view of a spectrum.

`drt` (Tikhonov-regularised, Gaussian RBF basis, λ by GCV or L-curve, batched with vmap),
closed-form DRTs of circuits in `analytic`, and `unexplained_peaks`: the data's DRT peaks a
fitted circuit does not explain (evidence for the diagnosis), and `suggest_circuit`: a starting
circuit read off the peaks (`DRTResult.suggested_circuit`). See docs/drt.md.
"""

from ._drt import DRT_POINTS_MIN as DRT_POINTS_MIN, drt as drt
from .peaks import Peak as Peak
from .result import DRTBatchResult as DRTBatchResult, DRTResult as DRTResult
from .analytic import (
    AnalyticDRT as AnalyticDRT,
    circuit_drt as circuit_drt,
    havriliak_negami_drt as havriliak_negami_drt,
    r_cpe_drt as r_cpe_drt,
    r_cpe_tau as r_cpe_tau,
    zarc_drt as zarc_drt,
)
from .suggest import SuggestedCircuit as SuggestedCircuit, suggest_circuit as suggest_circuit
from .evidence import PeakEvidence as PeakEvidence, RESOLVED_SIGMAS as RESOLVED_SIGMAS, is_resolved as is_resolved, unexplained_peaks as unexplained_peaks
