"""Energy absorbed by strut and tyre, and their efficiencies, from load and travel histories."""

from __future__ import annotations

import numpy as np

# 3-point Gauss-Legendre nodes and weights on [0, 1]: exact for polynomials of degree 5,
# which is the degree of (cubic load spline) x (derivative of the cubic travel spline).
_GL_NODES = 0.5 + 0.5 * np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
_GL_WEIGHTS = 0.5 * np.array([5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0])


def absorbed_energy(time: np.ndarray, load: np.ndarray, travel: np.ndarray) -> float:
    """Energy absorbed over the loading stroke, E = ∫ F ds from contact to maximum travel [J].

    Parameters
    ----------
    time : array
        Sample times [s], strictly increasing, starting at touchdown.
    load : array
        Force through the element [N].
    travel : array
        Element travel (strut stroke or tyre deflection) [m].

    Notes
    -----
    E = ∫ F(t)·ds/dt dt over [t_0, t(argmax s)], integrated by :func:`work_until`.
    """
    return work_until(time, load, travel, int(np.argmax(np.asarray(travel, dtype=float))))


def work_until(time: np.ndarray, load: np.ndarray, travel: np.ndarray, end: int) -> float:
    """Work of ``load`` on ``travel`` from the first sample to sample ``end``, ∫ F ds [J].

    Notes
    -----
    W = ∫ F(t)·ds/dt dt over [t_0, t_end].  Load and travel are interpolated by cubic
    splines in time (the time grid is regular, so nothing divides by a small travel step
    near maximum compression) and each interval's polynomial product is integrated
    exactly by 3-point Gauss-Legendre quadrature.  Fourth-order accurate in the sample
    interval; exact when F is linear in s.
    """
    # scipy is imported here, not at the top: scipy.interpolate and scipy.signal add about
    # 0.25 s to every start-up (python -X importtime), and only time series need them
    from scipy.interpolate import CubicSpline

    if end < 1:
        return 0.0
    t = np.asarray(time, dtype=float)[: end + 1]
    f = np.asarray(load, dtype=float)[: end + 1]
    s = np.asarray(travel, dtype=float)[: end + 1]
    if end == 1:
        return float(0.5 * (f[0] + f[1]) * (s[1] - s[0]))
    load_spline = CubicSpline(t, f, bc_type="not-a-knot")
    travel_rate = CubicSpline(t, s, bc_type="not-a-knot").derivative()
    widths = np.diff(t)
    points = t[:-1, None] + widths[:, None] * _GL_NODES[None, :]
    integrand = load_spline(points) * travel_rate(points)
    return float(np.sum(widths * (integrand @ _GL_WEIGHTS)))


def efficiency(energy: float, peak_load: float, max_travel: float) -> float | None:
    """η = E/(F_peak·δ_max): the share of the rectangle F_peak·δ_max the element absorbs."""
    if peak_load <= 0 or max_travel <= 0:
        return None
    return energy / (peak_load * max_travel)
