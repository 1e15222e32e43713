"""S4 of the HPA: the weights that map wavelet approximations to voluntary motion."""

from __future__ import annotations

import numpy as np

from wake.ahead import identity
from wake.config import RIDGE_SCALES, WEIGHT_LIMIT
from wake.wavelets import default_weights  # noqa: F401  (re-exported: the weights before any fit)

__all__ = ["fit_weights", "ridge_scale_of", "default_weights"]


def ridge_scale_of(A, G, rule: str = "gram") -> float:
    """The mean diagonal the weight fit's relative ridge multiplies (``WakeConfig.ridge_scale``).

    ``"gram"``: ``trace(A'A) / J``; ``"centred"``: the same of ``A`` with each column's mean taken out,
    ``(trace(A'A) - L |mean(A)|^2) / J``, which a constant offset in the signal (gravity) does not inflate,
    floored at ``1e-6`` of the first (an offset with little or no motion: the ridge still keeps the system
    solvable in float64).

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[10.0, 11.0], [12.0, 9.0]])
    >>> ridge_scale_of(A, A.T @ A), ridge_scale_of(A, A.T @ A, "centred")
    (223.0, 2.0)
    """
    J = A.shape[1]
    gram = float(np.trace(G) / J)
    if rule == "gram":
        return gram
    if rule == "centred":
        mean = A.mean(axis=0)
        return max(gram - A.shape[0] * float(mean @ mean) / J, 1e-6 * gram)
    raise ValueError(f"unknown ridge_scale {rule!r}; valid choices: {', '.join(RIDGE_SCALES)}")


def fit_weights(approximations, target, ridge=1e-6, weight_limit=WEIGHT_LIMIT, *, center=None, shrink=0.0,
                ridge_scale="gram"):
    """Least-squares weights ``w`` minimising ``e_L = sqrt(|A w - y|^2 / L)``.

    With ``center`` and ``shrink > 0`` the fit minimises
    ``|A w - y|^2 + shrink * trace(A'A) / J * |w - center|^2`` instead: a
    warm-up window too short to pin ``w`` down is pulled towards the prior
    weights (docs/studies/design.md, "Warm-up").

    ``e_L`` is quadratic in ``w``, so its minimum (which the paper reaches
    with a quasi-Newton search) has the closed form of the normal equations.
    A ridge ``lambda = ridge * trace(A'A) / J`` keeps the nearly collinear
    approximations well-posed; it is raised tenfold until every weight lies
    within ``weight_limit``.  ``ridge_scale="centred"`` takes the trace of
    the centred Gram matrix instead (:func:`ridge_scale_of`).

    Returns
    -------
    weights : numpy.ndarray, shape (J,)
    fit_error : float
        ``e_L``.
    ridge : float
        The ridge factor used.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.hpa import fit_weights
    >>> A = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> w, e, r = fit_weights(A, A @ [2.0, -1.0], ridge=0.0)
    >>> np.round(w, 6).tolist(), round(e, 9)
    ([2.0, -1.0], 0.0)
    """
    A = np.asarray(approximations, dtype=float)
    y = np.asarray(target, dtype=float)
    if A.ndim != 2 or y.shape != (A.shape[0],):
        raise ValueError(f"approximations must be (L, J) and target (L,), got {A.shape} and {y.shape}")
    if A.shape[0] < A.shape[1]:
        raise ValueError(f"need at least J = {A.shape[1]} rows to fit J weights, got {A.shape[0]}")
    J = A.shape[1]
    G = A.T @ A
    b = A.T @ y
    scale = ridge_scale_of(A, G, ridge_scale)
    if not np.isfinite(scale) or scale <= 0:
        return np.zeros(J), float(np.sqrt(np.mean(y**2))), float(ridge)
    eye = identity(J)   # made once per J
    if center is not None and shrink > 0:
        # |A w - y|^2 + s |w - c|^2: the normal equations gain s I on the left and s c on the right
        G = G + shrink * scale * eye
        b = b + shrink * scale * np.asarray(center, dtype=float)
    factor = float(ridge)
    for _ in range(16):
        if factor > 0 or shrink > 0:
            w = np.linalg.solve(G + factor * scale * eye, b)
        else:
            w = np.linalg.lstsq(A, y, rcond=None)[0]
        if np.all(np.isfinite(w)) and np.max(np.abs(w)) <= weight_limit:
            break
        factor = max(factor * 10.0, 1e-9)
    else:  # pragma: no cover - a ridge of 1e7 * trace makes w tiny
        w = np.clip(w, -weight_limit, weight_limit)
    err = float(np.sqrt(np.mean((A @ w - y) ** 2)))
    return w, err, factor


