"""The one check of identification data: signals, input channels and lists of experiments.

Every engine (ARX, LS-SVM NARX, Hammerstein, Wiener) takes one experiment or several, and
reads them here, with the same rules and messages:

* **one experiment**: an input ``u`` of shape (n,) or (n, n_inputs) -- numpy array, pandas
  Series or DataFrame, or a plain (nested) list -- and an output ``y`` of shape (n,) or
  (n, 1).  An (n, 1) column is one experiment of n samples with one input channel; the
  columns of a 2-D input are its channels.
* **several experiments**: a list (or tuple) whose items are arrays, Series or DataFrames,
  one per experiment, for ``u`` and ``y`` alike.  A list of plain numbers or of plain lists
  is one experiment (read as numpy reads it), never several.

Each signal must be non-empty and finite; inputs and outputs both one experiment or both
lists of the same number; every experiment with the same number of input channels.  Bad
data raise :class:`certkit.errors.DataInputError` saying what was expected and found.
"""

from __future__ import annotations

import math

import numpy as np

from certkit.errors import DataInputError


def _array(name: str, x) -> np.ndarray:
    if hasattr(x, "tocsr") or hasattr(x, "todense"):
        raise DataInputError(name, f"expected a dense array, found a sparse "
                                   f"{type(x).__name__} (sparse input is not supported: "
                                   f"convert it with .toarray())")
    try:
        array = np.asarray(x)
        if np.iscomplexobj(array):
            raise DataInputError(name, "expected real numbers, found complex data (Complex "
                                       "data not supported)")
        return array.astype(float)
    except (TypeError, ValueError) as error:
        if isinstance(error, DataInputError):
            raise
        raise DataInputError(name, f"expected numbers (an array, Series, DataFrame or list), "
                                   f"found {type(x).__name__} that is not numeric: "
                                   f"{error}") from None


def _finite(name: str, x: np.ndarray) -> np.ndarray:
    if not np.all(np.isfinite(x)):
        bad = int(np.flatnonzero(~np.isfinite(x).reshape(x.shape[0], -1).all(axis=1))[0])
        raise DataInputError(name, f"expected finite values, found NaN or infinite values "
                                   f"(first at sample {bad})")
    return x


def signal(name: str, x, length: int | None = None) -> np.ndarray:
    """``x`` as a non-empty, finite 1-D float array (of ``length`` samples, when given).

    An (n, 1) column is accepted as n samples."""
    x = _array(name, x)
    if x.ndim == 2 and x.shape[1] == 1:
        x = x[:, 0]
    if x.ndim != 1 or x.size == 0:
        raise DataInputError(name, f"expected a non-empty 1-D signal (one sample per time "
                                   f"step), found shape {x.shape}")
    if length is not None and x.size != length:
        raise DataInputError(name, f"expected {length} samples, found {x.size}")
    return _finite(name, x)


def channels(name: str, x, n_channels: int | None = None, who: str = "the model"
             ) -> np.ndarray:
    """An input as an (n, n_inputs) float array: 1-D means n samples of one channel."""
    x = _array(name, x)
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim == 2 and x.shape[1] == 0:
        raise DataInputError(name, f"expected at least one input channel, found 0 feature(s) "
                                   f"(shape={x.shape}) while a minimum of 1 is required.")
    if x.ndim != 2 or x.shape[0] == 0:
        raise DataInputError(name, f"expected a non-empty input of shape (n_samples,) or "
                                   f"(n_samples, n_inputs), found shape {x.shape}")
    if n_channels is not None and x.shape[1] != n_channels:
        raise DataInputError(name, f"X has {x.shape[1]} features, but {who} is expecting "
                                   f"{n_channels} features as input (input channels, as in "
                                   f"fit)")
    return _finite(name, x)


def is_experiment_list(data) -> bool:
    """Whether ``data`` lists several experiments: a list or tuple of arrays, Series or
    DataFrames (not of numbers or plain lists, which make one experiment)."""
    return (isinstance(data, (list, tuple)) and len(data) > 0
            and all(not isinstance(d, (list, tuple)) and hasattr(d, "__array__")
                    and np.ndim(d) >= 1 for d in data))


def experiments(u, y, names: tuple[str, str] = ("u", "y"), same_length: bool = True,
                n_channels: int | None = None, who: str = "the model"
                ) -> tuple[list[tuple[np.ndarray, np.ndarray]], bool]:
    """Inputs and outputs of one experiment or of several -> (list of (input (n, n_inputs),
    output (n,)) pairs, whether it was one).  ``same_length``: each output as long as its
    input; ``n_channels``: the number of input channels expected (else that of the first)."""
    a, b = names
    listed_u, listed_y = is_experiment_list(u), is_experiment_list(y)
    if isinstance(u, (list, tuple)) and not u:
        raise DataInputError(a, "expected an experiment or a list of experiments, found "
                                "an empty list")
    if listed_u != listed_y:
        found = f"{a} {'a list of' if listed_u else 'one'} experiment" + ("s" * listed_u)
        raise DataInputError(f"{a}, {b}", f"expected both as one experiment (arrays) or both "
                                          f"as lists of arrays, found {found}")
    us = list(u) if listed_u else [u]
    ys = list(y) if listed_y else [y]
    if len(us) != len(ys):
        raise DataInputError(f"{a}, {b}", f"expected as many experiments in {b} as in {a}, "
                                          f"found {len(us)} and {len(ys)}")
    pairs = []
    for k, (ue, ye) in enumerate(zip(us, ys)):
        where = (lambda n: f"{n}[{k}]") if listed_u else (lambda n: n)
        ue = channels(where(a), ue, n_channels, who)
        n_channels = ue.shape[1]
        ye = signal(where(b), ye)
        if same_length and ue.shape[0] != ye.size:
            raise DataInputError(f"{where(a)}, {where(b)}",
                                 f"expected the same number of samples, found {ue.shape[0]} "
                                 f"and {ye.size}")
        pairs.append((ue, ye))
    return pairs, not listed_u


def inputs_only(u, n_channels: int | None = None, name: str = "u", who: str = "the model"
                ) -> tuple[list[np.ndarray], bool]:
    """Inputs of one experiment or of several -> (list of (n, n_inputs) arrays, whether it
    was one)."""
    if is_experiment_list(u):
        return [channels(f"{name}[{k}]", x, n_channels, who) for k, x in enumerate(u)], False
    return [channels(name, u, n_channels, who)], True


def order(name: str, value, minimum: int = 0) -> int:
    """A lag order or delay: an integer ≥ ``minimum``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise DataInputError(name, f"expected an integer, found {value!r}")
    if value < minimum:
        raise DataInputError(name, f"expected an integer >= {minimum}, found {value}")
    return int(value)


def per_channel(name: str, value, n_channels: int, minimum: int = 0) -> tuple[int, ...]:
    """An order given once for every input channel (an int) or per channel (a sequence)."""
    if isinstance(value, (list, tuple, np.ndarray)):
        if len(value) != n_channels:
            raise DataInputError(name, f"expected one value per input channel "
                                       f"({n_channels}), found {len(value)}")
        return tuple(order(f"{name}[{k}]", v, minimum) for k, v in enumerate(value))
    return (order(name, value, minimum),) * n_channels


def positive_number(name: str, value) -> float:
    """A positive finite float (γ, σ², a scale)."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise DataInputError(name, f"expected a positive number, found {value!r}") from None
    if not (math.isfinite(number) and number > 0.0):
        raise DataInputError(name, f"expected a positive finite number, found {value!r}")
    return number


def free_run_folds(lengths: list[int], folds: int, min_length: int
                   ) -> list[tuple[list[tuple[int, slice]], list[tuple[int, slice]]]]:
    """The folds of a free-run cross-validation, as (training pieces, held-out pieces), each
    piece (experiment index, slice of its samples).

    With at least ``folds`` experiments, whole experiments are held out (fold k holds
    experiments k, k + folds, ...); otherwise every experiment is cut into ``folds``
    contiguous segments and fold k holds the k-th segment of each, the remaining segments
    being separate training experiments (lags never cross a cut).  ``min_length``: the
    shortest segment allowed (an initialisation window plus the lags)."""
    folds = order("folds", folds, 2)
    if len(lengths) >= folds:
        whole = [(e, slice(0, n)) for e, n in enumerate(lengths)]
        return [([p for p in whole if p[0] % folds != k], [p for p in whole if p[0] % folds == k])
                for k in range(folds)]
    cuts = []
    for e, n in enumerate(lengths):
        parts = np.array_split(np.arange(n), folds)
        if min(p.size for p in parts) < min_length:
            raise DataInputError("folds", f"expected experiments of at least {folds} x "
                                          f"{min_length} samples for {folds} tuning folds, "
                                          f"found one of {n}")
        cuts.append([(e, slice(int(p[0]), int(p[-1]) + 1)) for p in parts])
    return [([p for c in cuts for j, p in enumerate(c) if j != k], [c[k] for c in cuts])
            for k in range(folds)]
