"""Fitting and validation of spectra."""

from ._kk import KKBatchResult as KKBatchResult, KKResult as KKResult, kk_test as kk_test, kk_test_batch as kk_test_batch
