"""The one check of identification data: signals and lists of experiments.

Every engine (LS-SVM NARX, Hammerstein, the ARX blocks of the Wiener models) takes one
experiment as arrays or several as lists of arrays, and validates them here, with the same
messages: each signal 1-D, non-empty and finite; inputs and outputs both one experiment or
both lists of the same number; and, where they must, of one length each.
"""

from __future__ import annotations

import numpy as np


def signal(name: str, x, length: int | None = None) -> np.ndarray:
    """``x`` as a non-empty, finite 1-D float array (of ``length`` samples, when given)."""
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array (one sample per time step), "
                         f"got shape {x.shape}")
    if length is not None and x.size != length:
        raise ValueError(f"{name} has {x.size} samples, expected {length}")
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return x


def records(name: str, data) -> tuple[list[np.ndarray], bool]:
    """One 1-D array or a list of them -> (list of validated signals, whether it was one)."""
    if isinstance(data, (list, tuple)):
        if not data:
            raise ValueError(f"{name} lists no experiment")
        if all(np.ndim(d) == 1 for d in data):
            return [signal(f"{name}[{i}]", d) for i, d in enumerate(data)], False
    array = np.asarray(data, dtype=float)
    if array.ndim == 1:
        return [signal(name, array)], True
    raise ValueError(f"{name} must be a 1-D array or a list of 1-D arrays (one per "
                     f"experiment)")


def experiments(u, y, names: tuple[str, str] = ("u", "y"), same_length: bool = True
                ) -> tuple[list[tuple[np.ndarray, np.ndarray]], bool]:
    """Inputs and outputs of one experiment or of several -> (list of (input, output)
    pairs, whether it was one).  ``same_length``: each output as long as its input."""
    (a, b), (us, single_u), (ys, single_y) = names, records(names[0], u), records(names[1], y)
    if single_u != single_y:
        raise ValueError(f"give {a} and {b} both as arrays (one experiment) or both as lists "
                         f"of arrays")
    if len(us) != len(ys):
        raise ValueError(f"{a} has {len(us)} experiments, {b} has {len(ys)}")
    if same_length:
        for k, (ue, ye) in enumerate(zip(us, ys)):
            if ue.size != ye.size:
                raise ValueError(f"experiment {k}: {a} and {b} have different lengths "
                                 f"({ue.size} and {ye.size})")
    return list(zip(us, ys)), single_u
