"""The image metrics on arrays whose values are known by hand."""

import numpy as np
import pytest

import lancer


def test_metrics_of_a_uniform_difference():
    ref = np.ones((4, 6, 3))
    img = np.full((4, 6, 3), 2.0)
    assert lancer.rmse(img, ref) == pytest.approx(1.0)
    assert lancer.nrmse(img, ref) == pytest.approx(1.0)
    # (2 - 1)^2 / (1^2 + (0.1 * 1)^2)
    assert lancer.relmse(img, ref) == pytest.approx(1 / 1.01)
    assert lancer.mean_rel_error(img, ref) == pytest.approx(1.0)
    assert lancer.rmse(ref, ref) == 0.0 and lancer.relmse(ref, ref) == 0.0


def test_mean_rel_error_takes_the_worst_channel_and_any_size():
    ref = np.ones((2, 2, 3)) * [1.0, 2.0, 4.0]
    img = np.ones((8, 3, 3)) * [1.1, 2.0, 3.0]  # +10 %, 0 %, -25 %
    assert lancer.mean_rel_error(img, ref) == pytest.approx(0.25)
    with pytest.raises(ValueError, match="differ in shape"):
        lancer.rmse(img, ref)


def test_relmse_weights_errors_by_the_reference():
    ref = np.zeros((1, 2, 3))
    ref[0, 1] = 10.0  # mean 5: the floor is (0.1 * 5)^2 = 0.25
    img = ref + 1.0
    # pixel 0: 1 / 0.25 = 4; pixel 1: 1 / (100 + 0.25)
    assert lancer.relmse(img, ref) == pytest.approx((4 + 1 / 100.25) / 2)
    assert lancer.rmse(img, ref) == pytest.approx(1.0)
    assert lancer.nrmse(img, ref) == pytest.approx(0.2)
