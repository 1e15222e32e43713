"""S4 of the HPA: the weights that map wavelet approximations to voluntary motion."""

from __future__ import annotations

import numpy as np

from wake.ahead import identity
from wake.config import RIDGE_SCALES, WEIGHT_LIMIT
from wake.hpa.spectrum import row_mean
from wake.wavelets import default_weights  # noqa: F401  (re-exported: the weights before any fit)

__all__ = ["fit_weights", "fit_stacks", "ridge_scale_of", "default_weights"]


def ridge_scale_of(A, G, rule: str = "gram"):
    """The mean diagonal the weight fit's relative ridge multiplies (``WakeConfig.ridge_scale``).

    ``"gram"``: ``trace(A'A) / J``; ``"centred"``: the same of ``A`` with each column's mean taken out,
    ``(trace(A'A) - L |mean(A)|^2) / J``, which a constant offset in the signal (gravity) does not inflate,
    floored at ``1e-6`` of the first (an offset with little or no motion: the ridge still keeps the system
    solvable in float64).  ``A`` (L, J) with ``G = A'A`` gives a float; a stack ``A`` (W, L, J) with its
    ``G`` (W, J, J) gives one per window.

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[10.0, 11.0], [12.0, 9.0]])
    >>> ridge_scale_of(A, A.T @ A), ridge_scale_of(A, A.T @ A, "centred")
    (223.0, 2.0)
    """
    if rule not in RIDGE_SCALES:
        raise ValueError(f"unknown ridge_scale {rule!r}; valid choices: {', '.join(RIDGE_SCALES)}")
    A, G = np.asarray(A), np.asarray(G)
    if A.ndim == 2:
        return float(ridge_scale_of(A[None], G[None], rule)[0])
    J = A.shape[2]
    gram = np.trace(G, axis1=1, axis2=2) / J
    if rule == "gram":
        return gram
    mean = A.mean(axis=1)
    return np.maximum(gram - A.shape[1] * np.einsum("wj,wj->w", mean, mean) / J, 1e-6 * gram)


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
    A, y = _checked(approximations, target)
    if A.ndim == 3:
        return fit_stacks([A], [y], ridge, weight_limit, center=center, shrinks=[shrink], ridge_scale=ridge_scale)
    w, err, used = fit_stacks([A[None]], [y[None]], ridge, weight_limit, center=center, shrinks=[shrink],
                              ridge_scale=ridge_scale)
    return w[0], float(err[0]), float(used[0])


def fit_stacks(approximations, targets, ridge=1e-6, weight_limit=WEIGHT_LIMIT, *, center=None, shrinks=None,
               ridge_scale="gram"):
    """:func:`fit_weights` of every window of a list of stacks, ``(W_i, L_i, J)`` against ``(W_i, L_i)``, each
    stack with its own ``shrinks[i]`` (default 0): ``(weights (W, J), fit_error (W,), ridge (W,))`` over the
    windows of all stacks in order, each row bit for bit its window's own fit.

    The Gram matrices, ridge scales and fit errors are taken stack by stack (the stacks may differ in length: the
    warm-up windows of a block beside its full ones); one solve serves every window whose first ridge holds (the
    usual case), the ridge raised window by window where it does not (the batched matmul and solve run the same
    BLAS and LAPACK calls per window as a window alone).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(2)
    >>> A1, A2 = rng.normal(size=(2, 40, 3)), rng.normal(size=(1, 90, 3))
    >>> y1, y2 = A1 @ [1.0, -1.0, 0.5], A2 @ [0.5, 1.0, 2.0]
    >>> w, err, used = fit_stacks([A1, A2], [y1, y2], ridge=1e-9)
    >>> np.round(w, 4).tolist()[2], bool(np.array_equal(w[2], fit_weights(A2[0], y2[0], 1e-9)[0]))
    ([0.5, 1.0, 2.0], True)
    """
    pairs = [_checked(A, y, stack=True) for A, y in zip(approximations, targets)]
    if not pairs or len(pairs) != len(targets) or len({A.shape[2] for A, _ in pairs}) != 1:
        raise ValueError(f"need one or more stacks of approximations, each with its targets, all with one J; got "
                         f"{len(approximations)} stacks of approximations and {len(targets)} of targets")
    approximations, targets = [A for A, _ in pairs], [y for _, y in pairs]
    shrinks = [0.0] * len(pairs) if shrinks is None else shrinks
    ridge, J = float(ridge), approximations[0].shape[2]
    eye = identity(J)   # made once per J
    G, b, scale = [], [], []
    for A, y, shrink in zip(approximations, targets, shrinks):
        At = np.swapaxes(A, 1, 2)
        G.append(At @ A)
        b.append((At @ y[:, :, None])[:, :, 0])
        scale.append(ridge_scale_of(A, G[-1], ridge_scale))
        if center is not None and shrink > 0:
            # |A w - y|^2 + s |w - c|^2: the normal equations gain s I on the left and s c on the right
            G[-1] = G[-1] + (shrink * scale[-1])[:, None, None] * eye
            b[-1] = b[-1] + (shrink * scale[-1])[:, None] * np.asarray(center, dtype=float)
    G, b, scale = (parts[0] if len(parts) == 1 else np.concatenate(parts) for parts in (G, b, scale))
    sizes = [A.shape[0] for A in approximations]
    n = G.shape[0]
    used = np.full(n, ridge)
    powered = np.isfinite(scale) & (scale > 0)   # a window without power: w = 0 (its error below)
    # the first ridge solves a window when there is a ridge or a pull; else its fit is the plain least squares
    solvable = powered if ridge > 0 else powered & np.repeat(np.array(shrinks, dtype=float) > 0, sizes)
    every = bool(solvable.all())
    rows = np.arange(n) if every else np.flatnonzero(solvable)
    todo, w = np.flatnonzero(powered & ~solvable), np.zeros((n, J))
    if rows.size:
        Gp, bp, sp = (G, b, scale) if every else (G[rows], b[rows], scale[rows])
        try:
            first = np.linalg.solve(Gp + (ridge * sp)[:, None, None] * eye, bp[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:   # one singular window: each solved alone (and refused alone)
            first = None
            todo = np.flatnonzero(powered)
        if first is not None:
            ok = np.isfinite(first).all(axis=1) & (np.abs(first).max(axis=1) <= weight_limit)
            if every and ok.all():
                w = first
            else:
                w[rows[ok]] = first[ok]
                todo = np.union1d(todo, rows[~ok])
    starts = np.cumsum([0] + sizes)
    for i in todo:
        k = int(np.searchsorted(starts, i, side="right")) - 1
        A, y, j = approximations[k], targets[k], i - starts[k]
        w[i], used[i] = _raised(A[j], y[j], G[i], b[i], scale[i], eye, ridge, weight_limit, shrinks[k])
    err = np.empty(n)
    for A, y, lo, hi in zip(approximations, targets, starts[:-1], starts[1:]):
        live = powered[lo:hi]
        if live.all():   # row_mean: np.mean(..., axis=1)'s numbers
            err[lo:hi] = np.sqrt(row_mean(((A @ w[lo:hi, :, None])[:, :, 0] - y) ** 2))
        else:
            e = np.sqrt(row_mean(y**2))
            live = np.flatnonzero(live)
            e[live] = np.sqrt(row_mean(((A[live] @ w[lo + live, :, None])[:, :, 0] - y[live]) ** 2))
            err[lo:hi] = e
    return w, err, used


def _checked(approximations, target, stack=False):
    """``(A, y)`` as float arrays, checked: ``A`` (L, J) with ``y`` (L,), or (with ``stack``, only) a stack (W, L, J)
    with (W, L), at least J rows each."""
    A = np.asarray(approximations, dtype=float)
    y = np.asarray(target, dtype=float)
    if A.ndim not in ((3,) if stack else (2, 3)) or y.shape != A.shape[:-1]:
        raise ValueError(f"approximations must be (L, J) and target (L,) (or stacks of them, (W, L, J) and "
                         f"(W, L)), got {A.shape} and {y.shape}")
    if A.shape[-2] < A.shape[-1]:
        raise ValueError(f"need at least J = {A.shape[-1]} rows to fit J weights, got {A.shape[-2]}")
    return A, y


def _raised(A, y, G, b, scale, eye, ridge, weight_limit, shrink):
    """One window's fit, the ridge raised tenfold until every weight lies within ``weight_limit``."""
    factor = ridge
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
    return w, factor
