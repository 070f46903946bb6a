"""tune_free_run's n_jobs: the folds scored in worker processes give the numbers, the
reasons and the errors of a search in one process."""

from __future__ import annotations

import pytest

from certkit.errors import DataInputError
from certkit.ident import NARX, FreeRunCV, tune_free_run

from .conftest import saturating_plant

pytestmark = pytest.mark.filterwarnings(
    "ignore::certkit.ident.search_space.SearchEdgeWarning")


def _record():
    return saturating_plant(600, seed=5, pole=0.8)


def _search(n_jobs: int, **options):
    u, y = _record()
    return tune_free_run(NARX(na=1, nb=1, engine="fixed-size", prototypes=40), u, y,
                         orders={"na": [1, 2]}, gamma=(1e-1, 1e7), sigma2=(1e-3, 1e1),
                         grid=4, refine=False, n_jobs=n_jobs, **options)


def test_two_workers_give_every_cost_reason_and_choice_of_one_process():
    one_model, one = _search(1, cost=FreeRunCV(folds=4, divergence=0.05))
    two_model, two = _search(2, cost=FreeRunCV(folds=4, divergence=0.05))
    assert [r["cost"] for r in two.rows] == [r["cost"] for r in one.rows]
    # the tight divergence band rejects some candidates on a fold: the same ones, for the
    # same reasons, the evaluation cut at the same fold
    rejected = [o for o in one.outcomes if o and o[-1].rejected]
    assert rejected, "the check needs rejected candidates"
    assert [[(o.fold, o.status, o.reason) for o in outcome] for outcome in two.outcomes] == \
        [[(o.fold, o.status, o.reason) for o in outcome] for outcome in one.outcomes]
    assert two.best == one.best
    assert (two_model.gamma, two_model.sigma2, two_model.na) == \
        (one_model.gamma, one_model.sigma2, one_model.na)


def test_an_input_error_in_a_worker_reaches_the_caller_as_it_is():
    # held-out blocks of 600/8 = 75 samples are shorter than a 100-sample start: the fold
    # raises certkit's input error in the worker, and the caller gets that error
    for n_jobs in (1, 2):
        with pytest.raises(DataInputError, match="expected held-out pieces longer than the "
                                                 "100-sample window"):
            _search(n_jobs, cost=FreeRunCV(folds=8, n_init=100))


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "2"])
def test_n_jobs_is_a_positive_integer(bad):
    with pytest.raises(DataInputError, match="n_jobs"):
        _search(bad)


def test_workers_score_the_folds_of_a_free_run_cost_only():
    u, y = _record()
    with pytest.raises(DataInputError, match="n_jobs: expected 1 with a cost other than"):
        tune_free_run(NARX(na=1, nb=1), u, y, cost=lambda estimator, pairs: 1.0, n_jobs=2)


def test_a_worker_scores_a_search_of_its_own_in_itself():
    # a forked worker inherits the list of the search's pools: its own searches must not
    # use them (they are the parent's), but score their folds in the worker
    from certkit.ident import workers

    with workers.fold_workers(2):
        pools = workers.running_workers()
        assert len(pools) == 2
        assert pools[0].submit(workers.running_workers).result() is None
    assert workers.running_workers() is None
