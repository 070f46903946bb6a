"""certkit.ident.reuse: what a tuning search computes once for many candidates changes no
figure of the search, is kept only inside the search, and within its memory budget."""

from __future__ import annotations

import numpy as np
import pytest

from certkit.ident import NARX, FreeRunCV, tune_free_run
from certkit.ident import reuse

from .conftest import saturating_plant


def _record():
    return saturating_plant(700, seed=3, pole=0.7)


def _search(engine: str):
    u, y = _record()
    options = {"prototypes": 60} if engine == "fixed-size" else {}
    return tune_free_run(NARX(na=1, nb=1, engine=engine, **options), u, y,
                         gamma=(1e0, 1e4), sigma2=(0.1, 10.0), grid=3, refine=False,
                         cost=FreeRunCV(folds=3))


@pytest.mark.filterwarnings("ignore::certkit.ident.search_space.SearchEdgeWarning")
@pytest.mark.parametrize("engine", ["full", "fixed-size"])
def test_a_search_that_reuses_gives_the_costs_of_one_that_computes_everything(engine,
                                                                              monkeypatch):
    made = []

    def counting(kind, key, compute):
        return reuse.kept(kind, key, lambda: made.append(kind) or compute())

    for module in ("certkit.ident.lssvm", "certkit.ident.fixed_size"):
        monkeypatch.setattr(f"{module}.kept", counting)
    _, reused = _search(engine)
    monkeypatch.undo()
    # 9 candidates x 3 folds fitted, then the chosen one on all the data: each fold's rows'
    # part made once (per σ² for the normal equations), not once per fit
    kinds = (["squared distances"] if engine == "full"
             else ["prototypes", "normal equations"])
    per_kind = {kind: made.count(kind) for kind in kinds}
    assert per_kind == ({"squared distances": 3 + 1} if engine == "full"
                        else {"prototypes": 3 + 1, "normal equations": 3 * 3 + 1})
    computed = []

    def compute_always(kind, key, compute):
        computed.append(kind)
        return compute()

    for module in ("certkit.ident.lssvm", "certkit.ident.fixed_size"):
        monkeypatch.setattr(f"{module}.kept", compute_always)
    _, plain = _search(engine)
    assert computed                        # the parts were asked for, and computed each time
    assert [r["cost"] for r in reused.rows] == [r["cost"] for r in plain.rows]
    assert [(r["gamma"], r["sigma2"]) for r in reused.rows] == \
        [(r["gamma"], r["sigma2"]) for r in plain.rows]


def test_parts_are_kept_inside_a_search_only():
    calls = []

    def compute():
        calls.append(1)
        return np.ones(3)

    reuse.kept("x", "k", compute)
    reuse.kept("x", "k", compute)
    assert len(calls) == 2                 # outside reusing(): nothing kept
    with reuse.reusing():
        first = reuse.kept("x", "k", compute)
        with reuse.reusing():              # an inner search shares the outer one's parts
            assert reuse.kept("x", "k", compute) is first
        assert reuse.kept("x", "other", compute) is not first
    assert len(calls) == 4
    reuse.kept("x", "k", compute)          # the outermost search ended: dropped
    assert len(calls) == 5


def test_the_oldest_parts_go_first_beyond_the_budget(monkeypatch):
    monkeypatch.setattr(reuse, "BUDGET", 3 * 800)    # three arrays of 100 float64
    calls = []

    def make(i):
        def compute():
            calls.append(i)
            return np.full(100, float(i))
        return compute

    with reuse.reusing():
        for i in range(4):
            reuse.kept("a", str(i), make(i))         # the 4th pushes out the 1st
        reuse.kept("a", "3", make(3))
        reuse.kept("a", "1", make(1))
        assert calls == [0, 1, 2, 3]                 # 1 and 3 were still kept
        reuse.kept("a", "0", make(0))
        assert calls == [0, 1, 2, 3, 0]              # 0 had gone


def test_the_digest_tells_arrays_apart_by_bytes_shape_and_type():
    a = np.arange(6.0)
    assert reuse.digest(a) == reuse.digest(a.copy())
    assert reuse.digest(a) != reuse.digest(a.reshape(2, 3))
    assert reuse.digest(a) != reuse.digest(a.astype(np.float32))
    b = a.copy()
    b[5] = np.nextafter(b[5], 10.0)
    assert reuse.digest(a) != reuse.digest(b)
    assert reuse.digest(a, 1.0) != reuse.digest(a, 1.0000000000000002)
