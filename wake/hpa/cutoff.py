"""S2 of the HPA: the cut-off ``f_d`` at the valley between voluntary and tremor content."""

from __future__ import annotations

import numpy as np

from wake._validation import check_positive

__all__ = ["CUTOFF_FLAGS", "CUTOFF_RULES", "FALLBACK_FLAGS", "find_cutoff"]

#: How a cut-off was found: from the window's spectrum (``"valley"``, ``"floor_valley"``, ``"shallow_valley"``)
#: or the fallback ``default_cutoff`` (:data:`FALLBACK_FLAGS`).
CUTOFF_FLAGS = {
    "valley": "f_d at the PSD minimum between the voluntary content and the tremor peak",
    "no_tremor_peak": "no local PSD maximum inside tremor_band: default_cutoff used",
    "no_valley": "the PSD has no dip of min_depth_db below both sides: default_cutoff used",
    "silent": "the window has (near) zero variance: default_cutoff used, weights kept",
    "shallow_valley": ("rules 'shallow' and 'floor': a tremor peak but no 3 dB valley; f_d at the PSD minimum "
                       "below the peak and at or below shallow_max, above the lowest bin of the search"),
    "floor_valley": ("rule 'floor': a valley at the noise floor (less than floor_margin_db above it); f_d at the "
                     "low edge of the floor, where the PSD first comes within edge_db of the valley"),
}

#: The flags whose f_d is ``default_cutoff``, not taken from the window's spectrum.
FALLBACK_FLAGS = ("no_tremor_peak", "no_valley", "silent")

#: Cut-off rules (docs/design.md, "Cut-off on real wear").  "floor" is the default; "paper" is the paper's.
CUTOFF_RULES = ("paper", "shallow", "floor")

#: Highest f_d the "shallow" and "floor" rules take from a shallow dip, Hz: a shallow dip above it is not
#: where voluntary motion ends.
SHALLOW_MAX = 4.0

#: Rule "floor": a dip less than this far above the noise floor (the lowest PSD above the tremor band), dB,
#: is broadband noise between the two bands, not where they meet.
FLOOR_MARGIN_DB = 15.0

#: Rule "floor": the low edge of a valley at the noise floor is where the PSD comes within this of it, dB.
EDGE_DB = 3.0

#: Rule "floor": the noise floor is the lowest PSD over the last bin (fs/2) and every FLOOR_STRIDE-th bin
#: below it, above the tremor band.  An AR spectrum is smooth there; on the 512-bin grid of
#: :func:`~wake.hpa.spectrum.ar_psd` the stride keeps the C HPA's spectrum at about 200 bins instead of 512
#: (every stride from 1 to 8 gives the same flags on PADS and the synthetic set).
FLOOR_STRIDE = 8


def find_cutoff(freqs, psd, *, tremor_band=(2.5, 15.0), cutoff_range=(0.5, 6.0),
                default_cutoff=2.0, min_depth_db=3.0, rule="paper", shallow_max=SHALLOW_MAX,
                floor_margin_db=FLOOR_MARGIN_DB, edge_db=EDGE_DB):
    """Cut-off ``f_d`` at the valley between voluntary and tremor content.

    The tremor peak is the largest local maximum of the PSD inside
    ``tremor_band``.  The valley is the PSD minimum over ``cutoff_range``
    below that peak; it counts only if it lies at least ``min_depth_db``
    below both the tremor peak and the largest PSD value to its left
    (the voluntary content).  Otherwise the ``"paper"`` rule (the default)
    returns ``default_cutoff``, and the ``"shallow"`` rule the PSD minimum
    between ``cutoff_range[0]`` and ``min(shallow_max, peak)``.  The
    ``"floor"`` rule (:class:`wake.WakeConfig`'s default) compares both with
    the noise floor, the lowest PSD above ``tremor_band`` (over the last bin
    and every :data:`FLOOR_STRIDE`-th bin below it): a shallow dip counts
    only ``floor_margin_db`` or more above it, and a valley closer to
    it than that is a gap filled by noise, whose low edge is taken instead.

    Parameters
    ----------
    freqs, psd : array_like
        A spectrum from :func:`wake.hpa.spectrum.ar_psd`.
    tremor_band : (float, float)
        Where the tremor peak is searched, Hz.
    cutoff_range : (float, float)
        Where ``f_d`` may lie, Hz.  Every returned cut-off is inside it.
    default_cutoff : float
        The fallback, Hz; must lie in ``cutoff_range``.
    min_depth_db : float
        How deep a dip must be to count as a valley.
    rule : {"paper", "shallow", "floor"}
        ``"paper"`` (this function's default, the paper's rule): the valley
        or ``default_cutoff``.
        ``"shallow"``: where ``"paper"`` finds a tremor peak but no valley
        deep enough, take the PSD minimum between ``cutoff_range[0]`` and
        the lower of the peak and ``shallow_max`` (flag
        ``"shallow_valley"``) instead of the default, unless that minimum
        is the lowest bin of the search (the PSD rises from there into the
        peak: no dip, flag ``"no_valley"``).
        ``"floor"``: as ``"shallow"``, but a shallow dip less than
        ``floor_margin_db`` above the noise floor gives the default (flag
        ``"no_valley"``), and a valley less than ``floor_margin_db`` above
        it moves down to the floor's low edge: the lowest frequency, not
        below ``cutoff_range[0]``, from which the PSD stays within
        ``edge_db`` of the valley (flag ``"floor_valley"``).  Without PSD
        bins above ``tremor_band`` there is no floor and it acts as
        ``"shallow"``.  On the ten PADS recordings it leaves 33 % of HPA
        windows on the default instead of 82 %, and it lowers the error on
        PADS and on the paper's synthetic set (docs/design.md, "Cut-off on
        real wear" and "Rest tremor with little voluntary motion").
    shallow_max : float
        Highest cut-off the ``"shallow"`` and ``"floor"`` rules take from a
        shallow dip, Hz (default 4: the lower edge of pathological tremor;
        ``cutoff_range[1]`` caps it too).
    floor_margin_db : float
        Rule ``"floor"``: how far above the noise floor a dip must lie to
        be where voluntary and tremor content meet, dB (default 15).
    edge_db : float
        Rule ``"floor"``: the low edge of a valley at the noise floor is
        where the PSD comes within this of the valley, dB (default 3).

    Returns
    -------
    cutoff : float
    flag : str
        A key of :data:`CUTOFF_FLAGS`.

    Examples
    --------
    >>> import numpy as np
    >>> from wake.hpa import find_cutoff
    >>> f = np.linspace(0, 50, 501)
    >>> psd = np.exp(-f / 0.5) + np.exp(-((f - 8) ** 2) / 2)   # voluntary + tremor at 8 Hz
    >>> fd, flag = find_cutoff(f, psd)
    >>> flag, bool(2.0 < fd < 6.0)
    ('valley', True)
    """
    lo, hi = cutoff_range
    if not 0 < lo <= default_cutoff <= hi:
        raise ValueError(
            f"need 0 < cutoff_range[0] <= default_cutoff <= cutoff_range[1], got "
            f"cutoff_range={cutoff_range!r}, default_cutoff={default_cutoff!r}"
        )
    if rule not in CUTOFF_RULES:
        raise ValueError(f"unknown cut-off rule {rule!r}; valid choices: {', '.join(CUTOFF_RULES)}")
    if isinstance(shallow_max, bool) or not isinstance(shallow_max, (int, float, np.floating, np.integer)) \
            or not lo <= shallow_max < np.inf:
        raise ValueError(f"shallow_max must be a finite frequency at or above cutoff_range[0] = {lo:g} Hz, "
                         f"got {shallow_max!r}")
    floor_margin_db = check_positive("floor_margin_db", floor_margin_db)
    edge_db = check_positive("edge_db", edge_db)
    if not 0 < tremor_band[0] < tremor_band[1]:
        raise ValueError(f"tremor_band must be (low, high) with 0 < low < high, got {tremor_band!r}")
    freqs = np.asarray(freqs, dtype=float)
    psd = np.asarray(psd, dtype=float)
    if not np.isfinite(psd).all() or psd.max() <= 0:
        return float(default_cutoff), "silent"
    db = 10 * np.log10(np.maximum(psd, psd.max() * 1e-30))
    inner = np.flatnonzero((freqs >= tremor_band[0]) & (freqs <= tremor_band[1]))
    inner = inner[(inner > 0) & (inner < freqs.size - 1)]
    local_max = inner[(db[inner] >= db[inner - 1]) & (db[inner] >= db[inner + 1])]
    if local_max.size == 0:
        return float(default_cutoff), "no_tremor_peak"
    peak = local_max[np.argmax(db[local_max])]
    search = np.flatnonzero((freqs >= lo) & (freqs <= min(hi, freqs[peak])))
    if search.size < 3:
        return float(default_cutoff), "no_valley"
    valley = search[np.argmin(db[search])]
    left = db[: valley + 1].max()
    # the noise floor: the lowest PSD above the tremor band, over fs/2 and every FLOOR_STRIDE-th bin below it
    # (rule "floor"; none without bins there)
    above = np.flatnonzero(freqs > tremor_band[1])[::-1][::FLOOR_STRIDE]
    floor = db[above].min() if rule == "floor" and above.size else -np.inf
    if db[valley] > db[peak] - min_depth_db or db[valley] > left - min_depth_db:
        if rule in ("shallow", "floor"):
            # a dip shallower than min_depth_db: its minimum, but only where voluntary motion can end
            # and, rule "floor", only well above the noise floor
            low = np.flatnonzero((freqs >= lo) & (freqs <= min(hi, shallow_max, freqs[peak])))
            if low.size >= 3:
                dip = low[np.argmin(db[low])]
                # a minimum on the lowest bin is no dip: the PSD rises from there into the tremor peak
                # (rest tremor on slow drift; docs/design.md, "Rest tremor with little voluntary motion")
                if dip > low[0] and db[dip] >= floor + floor_margin_db:
                    return float(freqs[dip]), "shallow_valley"
        return float(default_cutoff), "no_valley"
    if db[valley] < floor + floor_margin_db:
        # a valley at the noise floor: where the minimum falls inside the gap is noise; the gap's low
        # edge is where the voluntary content ends
        edge = valley
        while edge > 0 and freqs[edge - 1] >= lo and db[edge - 1] <= db[valley] + edge_db:
            edge -= 1
        return float(freqs[edge]), "floor_valley"
    return float(freqs[valley]), "valley"
