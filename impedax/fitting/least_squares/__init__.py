"""Least-squares fitting: Levenberg–Marquardt solvers, starting guesses, single and batch fits,
and many candidate circuits fitted through one compiled program (used by the diagnosis)."""

from .batch import BatchFitResult as BatchFitResult
from .single import WEIGHTINGS as WEIGHTINGS, FitResult as FitResult, fit as fit
