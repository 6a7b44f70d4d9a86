"""The incremental least squares of ZC's cone projections against numpy's."""
import numpy as np
import pytest

from graspforce._core.testing import lstsq_append


def work_arrays(n):
    return np.empty((n, n + 1)), np.empty(n), np.empty((3, n + 1)), np.empty(n + 2)


@pytest.mark.parametrize("n", [2, 3, 6, 12])
def test_growing_columns_match_numpy(n):
    """Columns added one call at a time (the factorization of the earlier ones reused) give
    numpy's least-squares solution at every size, up to a full square system."""
    rng = np.random.default_rng(n)
    D = rng.standard_normal((n, n + 1))
    rhs = rng.standard_normal(n)
    work, wrhs, house, x = work_arrays(n)
    fact = 0
    for q in range(1, n + 1):
        fact = lstsq_append(D, n, q, fact, rhs, x, work, wrhs, house)
        assert fact == q
        truth = np.linalg.lstsq(D[:, :q], rhs, rcond=None)[0]
        assert np.allclose(x[:q], truth, rtol=0, atol=1e-12 * (1 + np.abs(truth).max()))


def test_dropped_column_refactors_from_there():
    """After a column is removed (the later ones shift left, as drop_point does), reusing the
    factorization of the columns before it gives the solution on the remaining columns."""
    n = 6
    rng = np.random.default_rng(1)
    D = rng.standard_normal((n, n))
    rhs = rng.standard_normal(n)
    work, wrhs, house, x = work_arrays(n)
    assert lstsq_append(D, n, 5, 0, rhs, x, work, wrhs, house) == 5
    kept = [0, 1, 3, 4, 5]
    D2 = np.zeros_like(D)
    D2[:, :5] = D[:, kept]
    assert lstsq_append(D2, n, 5, 2, rhs, x, work, wrhs, house) == 5
    truth = np.linalg.lstsq(D[:, kept], rhs, rcond=None)[0]
    assert np.allclose(x[:5], truth, rtol=0, atol=1e-12 * (1 + np.abs(truth).max()))


def test_dependent_column_is_rank_deficient():
    n = 4
    rng = np.random.default_rng(2)
    D = np.zeros((n, 3))
    D[:, :2] = rng.standard_normal((n, 2))
    D[:, 2] = 2.0 * D[:, 0] - 0.5 * D[:, 1]
    work, wrhs, house, x = work_arrays(n)
    fact = lstsq_append(D, n, 2, 0, np.ones(n), x, work, wrhs, house)
    assert fact == 2
    assert lstsq_append(D, n, 3, fact, np.ones(n), x, work, wrhs, house) == -1
