"""The Gram-matrix screen decides exactly as the SVD does."""

import numpy as np

from rankloci.numeric.svd import numeric_rank_drop, rank_deficient

SEED = 3


def test_screen_agrees_with_svd_on_regular_and_singular_batches():
    rng = np.random.default_rng(SEED)
    J = rng.normal(size=(400, 6, 7))
    # make every other matrix exactly rank deficient: last row a combination of two others
    J[::2, 5] = 0.3 * J[::2, 0] - 1.7 * J[::2, 2]
    # and a few nearly singular ones just above and just below the threshold
    J[1:40:4, 5] = J[1:40:4, 1] + 1e-12 * rng.normal(size=(10, 7))
    J[3:40:4, 5] = J[3:40:4, 1] + 1e-4 * rng.normal(size=(10, 7))
    expected = numeric_rank_drop(J) > 0
    assert expected[::2].all() and not expected[3:40:4].any()
    np.testing.assert_array_equal(rank_deficient(J), expected)
    # tall matrices go through J^T J
    np.testing.assert_array_equal(rank_deficient(np.swapaxes(J, 1, 2)), expected)
