"""Least-squares fitting: Levenberg–Marquardt solvers, starting guesses, single and batch fits,
and many candidate circuits fitted through one compiled program (used by the diagnosis)."""

from .batch import BatchFitResult as BatchFitResult
from .result import FitResult as FitResult
from .shared import SharedFitResult as SharedFitResult
from .single import WEIGHTINGS as WEIGHTINGS, fit as fit
