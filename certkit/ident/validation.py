"""How well a model's output matches a record: error measures (:func:`rmse`, :func:`nrmse`,
:func:`fit_percent`, :func:`max_abs_error`) and the residual whiteness tests of
:func:`residual_analysis` (Ljung, *System Identification: Theory for the User*, 2nd ed.,
Prentice Hall 1999, ch. 16).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import special

from certkit.ident.experiments import signal


# ----------------------------------------------------------------------------- metrics
def _pair(y, y_hat) -> tuple[np.ndarray, np.ndarray]:
    y = signal("y", np.ravel(y))
    return y, signal("y_hat", np.ravel(y_hat), y.size)



def rmse(y, y_hat) -> float:
    """Root-mean-square error √(mean((y − ŷ)²)) [units of y]."""
    y, y_hat = _pair(y, y_hat)
    return float(np.sqrt(np.mean((y - y_hat) ** 2)))



def nrmse(y, y_hat) -> float:
    """RMSE divided by the standard deviation of y (population, ddof = 0) [-]."""
    y, y_hat = _pair(y, y_hat)
    return rmse(y, y_hat) / float(np.std(y))



def fit_percent(y, y_hat) -> float:
    """Fit index 100·(1 − ‖y − ŷ‖/‖y − ȳ‖) [%] (MATLAB ``compare``)."""
    y, y_hat = _pair(y, y_hat)
    return float(100.0 * (1.0 - np.linalg.norm(y - y_hat) / np.linalg.norm(y - y.mean())))



def max_abs_error(y, y_hat) -> float:
    """Largest absolute error max|y − ŷ| [units of y]."""
    y, y_hat = _pair(y, y_hat)
    return float(np.max(np.abs(y - y_hat)))



@dataclass(frozen=True)
class ResidualAnalysis:
    """Whiteness and independence tests of residuals (see :func:`residual_analysis`)."""

    lags: np.ndarray                      # 1 … max_lag
    autocorrelation: np.ndarray           # r_ee(τ) at ``lags``
    autocorrelation_ok: np.ndarray        # |r_ee(τ)| ≤ bound, per lag
    cross_lags: np.ndarray | None         # −max_lag … max_lag
    cross_correlation: np.ndarray | None  # r_eu(τ) at ``cross_lags``
    cross_correlation_ok: np.ndarray | None
    bound: float                          # z_{(1+confidence)/2}/√N

    @property
    def white(self) -> bool:
        """All autocorrelations inside the band."""
        return bool(np.all(self.autocorrelation_ok))



def residual_analysis(residuals, u=None, *, max_lag: int = 25,
                      confidence: float = 0.99) -> ResidualAnalysis:
    """Autocorrelation of residuals and residual↔input cross-correlation with bounds.

    Parameters
    ----------
    residuals : array_like, shape (N,)
        One-step prediction errors e_t (whiteness is a property of the predictor).
    u : array_like, shape (N,), optional
        Input, for the cross-correlation test.
    max_lag : int
        Largest lag τ tested (25 as MATLAB ``resid``).
    confidence : float
        Two-sided level of the band; 0.99 gives ±2.576/√N.

    Returns
    -------
    ResidualAnalysis

    Notes
    -----
    With centred signals, r_ee(τ) = Σ_t e_t e_{t−τ} / Σ_t e_t² and
    r_eu(τ) = Σ_t e_t u_{t−τ} / √(Σ e_t² Σ u_t²) (biased estimates; positive τ pairs the
    residual with earlier inputs).  Under whiteness (resp. independence) each is
    approximately N(0, 1/N), hence the band ±z/√N with z the normal quantile.
    """
    e = signal("residuals", residuals)
    n = e.size
    if not 1 <= max_lag < n:
        raise ValueError(f"max_lag must be between 1 and N − 1, got {max_lag}")
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must lie in (0, 1), got {confidence}")
    e = e - e.mean()
    energy = float(e @ e)
    if energy == 0.0:
        raise ValueError("residuals are constant: correlations are undefined")
    bound = float(special.ndtri(0.5 + confidence / 2.0)) / math.sqrt(n)
    lags = np.arange(1, max_lag + 1)
    auto = np.array([e[tau:] @ e[:-tau] for tau in lags]) / energy
    cross_lags = cross = cross_ok = None
    if u is not None:
        x = signal("u", u, n)
        x = x - x.mean()
        scale = math.sqrt(energy * float(x @ x))
        if scale == 0.0:
            raise ValueError("u is constant: the cross-correlation is undefined")
        cross_lags = np.arange(-max_lag, max_lag + 1)
        cross = np.array([e[tau:] @ x[:n - tau] if tau >= 0 else e[:tau] @ x[-tau:]
                          for tau in cross_lags]) / scale
        cross_ok = np.abs(cross) <= bound
    return ResidualAnalysis(lags, auto, np.abs(auto) <= bound, cross_lags, cross,
                            cross_ok, bound)
