"""System identification: LS-SVM, Hammerstein, Wiener and linear (ARX) engines that need no
campaign.  The package imports nothing from the rest of certkit but its error types
(:mod:`certkit.errors`); the drop protocol that applies these engines to a campaign's gear
units is :mod:`certkit.gear_identification`, which uses this package, never the reverse.

The estimators follow scikit-learn (``fit(u, y)``, ``get_params``, ``clone``); see
:mod:`certkit.ident.dynamic_model` for what ``predict`` and ``simulate`` mean on time series
and :mod:`certkit.ident.experiments` for the data they accept.

>>> from certkit.ident import ARX, NARX, HammersteinLSSVM, WienerLSSVM, tune_free_run
"""

from certkit.ident.dynamic_model import DynamicModel
from certkit.ident.ensemble import EnsembleModel
from certkit.ident.fixed_size import FixedSizeLSSVM
from certkit.ident.hammerstein import HammersteinLSSVM
from certkit.ident.linear_models import ARX
from certkit.ident.lssvm import LSSVMRegressor, TuningResult, tune
from certkit.ident.narx import NARX
from certkit.ident.search_space import SearchEdge, SearchEdgeWarning
from certkit.ident.tuning import CostSurface, FoldOutcome, FreeRunCV, tune_free_run
from certkit.ident.validation import fit_percent, nrmse, residual_analysis, rmse
from certkit.ident.wiener import WienerLSSVM

__all__ = ["ARX", "NARX", "HammersteinLSSVM", "WienerLSSVM", "DynamicModel", "EnsembleModel",
           "LSSVMRegressor", "FixedSizeLSSVM", "tune_free_run", "FreeRunCV", "FoldOutcome",
           "CostSurface", "SearchEdge", "SearchEdgeWarning", "tune", "TuningResult", "rmse",
           "nrmse", "fit_percent", "residual_analysis"]
