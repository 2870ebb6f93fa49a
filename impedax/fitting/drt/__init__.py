"""Distribution of relaxation times (DRT): the hypothesis-free view of a spectrum.

`drt` (Tikhonov-regularised, Gaussian RBF basis, λ by GCV or L-curve, batched with vmap),
closed-form DRTs of circuits in `analytic`, and `unexplained_peaks`: the data's DRT peaks a
fitted circuit does not explain (evidence for the diagnosis). See docs/drt.md.
"""

from ._drt import drt as drt
from .peaks import Peak as Peak
from .result import DRTBatchResult as DRTBatchResult, DRTResult as DRTResult
