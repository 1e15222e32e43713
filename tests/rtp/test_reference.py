import numpy as np
import pytest

from wake.rtp.reference import ReferenceRTP
from wake.wavelets import filter_bank_taps

TAPS = filter_bank_taps("sym3", 4)
W = np.array([0.1, -0.2, 0.6, 0.5])


def textbook_kalman(x, taps, w, r, q, p0):
    """The paper's KF written plainly: state x = approximations, F = I, the
    filter bank increment as known input, scalar measurement through w."""
    J, N = taps.shape
    buf = np.full(N, x[0])
    a_prev = taps @ buf
    state = a_prev.copy()
    P = p0 * np.eye(J)
    out = []
    for k, m in enumerate(x):
        # r(k) = z(k) - w' x(k|k-1);  S = w' P w + R;  K = P w / S
        # (from the second sample on: the first one initialises the window and had no prediction before it)
        if k > 0:
            innov = m - w @ state
            S = w @ P @ w + r
            K = P @ w / S
            state = state + K * innov
            P = P - np.outer(K, w) @ P
        # x(k+1|k) = F x(k|k) + (a(k+1) - a(k)),  P(k+1|k) = F P F' + Q
        buf = np.append(buf[1:], m)
        a = taps @ buf
        state = state + (a - a_prev)
        a_prev = a
        P = P + q * np.eye(J)
        out.append(w @ state)
    return np.array(out)


@pytest.mark.parametrize("q,p0", [(0.0, 0.0), (1e-3, 0.0), (1e-2, 0.5)])
def test_matches_the_textbook_kalman_filter(q, p0, rng):
    x = np.cumsum(rng.normal(size=400)) * 0.1 + 0.3 * rng.normal(size=400)
    rtp = ReferenceRTP(TAPS, W, 0.2, q, p0)
    ours = np.array([rtp.step(v) for v in x])
    np.testing.assert_allclose(ours, textbook_kalman(x, TAPS, W, 0.2, q, p0), atol=1e-10)


def test_block_run_equals_steps_with_gaps_and_weight_changes(rng):
    x = rng.normal(size=600)
    x[50:60] = np.nan
    x[300] = np.nan
    a = ReferenceRTP(TAPS, W, 0.3, 1e-3, 0.1)
    b = ReferenceRTP(TAPS, W, 0.3, 1e-3, 0.1)
    y1 = np.array([a.step_missing() if np.isnan(v) else a.step(v) for v in x[:400]])
    y2 = b.run(x[:400])
    np.testing.assert_array_equal(y1, y2)
    a.set_weights(W[::-1], 0.5)
    b.set_weights(W[::-1], 0.5)
    np.testing.assert_array_equal([a.step(v) for v in x[400:]], b.run(x[400:]))


def test_weight_change_restarts_the_covariance_isotropic(rng):
    """docs/studies/design.md, "Covariance at a weight change": P = (w'Pw / w'w) I with the old w; d and the window stay."""
    rtp = ReferenceRTP(TAPS, W, 0.3, 1e-3, 0.5)
    rtp.run(rng.normal(size=300))
    P = rtp.covariance.reshape(4, 4).copy()
    assert np.ptp(np.diag(P)) > 1e-6                    # not isotropic before the change
    d, window = rtp.correction.copy(), rtp.buffer.copy()
    rtp.set_weights(W[::-1], 0.5)
    np.testing.assert_allclose(rtp.covariance.reshape(4, 4), (W @ P @ W) / (W @ W) * np.eye(4), rtol=1e-12)
    np.testing.assert_array_equal(rtp.correction, d)
    np.testing.assert_array_equal(rtp.buffer, window)
    # until the next change the gain stays along w: d moves only along the new weights
    d0 = rtp.correction.copy()
    rtp.run(rng.normal(size=50))
    step = rtp.correction - d0
    np.testing.assert_allclose(step - (step @ W[::-1]) / (W @ W) * W[::-1], 0.0, atol=1e-12)
    # w = 0 observes nothing: the restart keeps P's diagonal
    zero = ReferenceRTP(TAPS, np.zeros(4), 0.3, 1e-3, 0.5)
    zero.run(rng.normal(size=20))
    zero.set_weights(W, 0.3)
    np.testing.assert_allclose(zero.covariance.reshape(4, 4), (0.5 + 20e-3) * np.eye(4), rtol=1e-12)


def test_constant_input_is_predicted_exactly():
    rtp = ReferenceRTP(TAPS, np.array([0.0, 0.0, 0.0, 1.0]), 1.0, 1e-3, 1.0)
    assert np.allclose(rtp.run(np.full(100, 2.5)), 2.5)


def test_covariance_stays_symmetric_and_positive(rng):
    rtp = ReferenceRTP(TAPS, W, 0.05, 1e-4, 1.0)
    rtp.run(np.sign(np.sin(np.arange(5000) * 0.3)) + rng.normal(size=5000))
    P = rtp.covariance.reshape(4, 4)
    np.testing.assert_array_equal(P, P.T)
    assert np.linalg.eigvalsh(P).min() > 0


def test_missing_sample_policy():
    rtp = ReferenceRTP(TAPS, W, 1.0, 1e-3, 0.0)
    assert rtp.step_missing() == 0.0 and not rtp.primed  # nothing to predict from yet
    rtp.run(np.linspace(0, 1, 50))
    before = rtp.covariance.copy()
    y = rtp.last_output
    rtp.step_missing()
    # no measurement update: P only grows by Q, and the gap is filled with the prediction
    np.testing.assert_allclose(rtp.covariance - before, 1e-3 * np.eye(4).reshape(-1))
    assert rtp.buffer[(rtp.head - 1) % 16] == y


def test_bad_configuration():
    with pytest.raises(ValueError, match="weights must be 4 finite numbers"):
        ReferenceRTP(TAPS, [1.0, np.nan, 0, 0], 1.0)
    with pytest.raises(ValueError, match="measurement_noise R must be finite and > 0"):
        ReferenceRTP(TAPS, W, 0.0)
    with pytest.raises(ValueError, match="process_noise Q"):
        ReferenceRTP(TAPS, W, 1.0, -1.0)
    with pytest.raises(ValueError, match="taps must have shape"):
        ReferenceRTP(np.ones((3, 7)), W[:3], 1.0)
