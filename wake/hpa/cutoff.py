"""S2 of the HPA: the cut-off ``f_d`` at the valley between voluntary and tremor content."""

from __future__ import annotations

import functools
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np

from wake._validation import check_positive
from wake.registry import get_cutoff_rule, register_cutoff_rule

__all__ = ["CUTOFF_FLAGS", "FALLBACK_FLAGS", "Spectrum", "find_cutoff"]

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

#: How deep a dip must be to count as a valley, dB (the paper's 3 dB).
MIN_DEPTH_DB = 3.0

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
                default_cutoff=2.0, min_depth_db=MIN_DEPTH_DB, rule="paper", shallow_max=SHALLOW_MAX,
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
        A spectrum from :func:`wake.hpa.spectrum.ar_psd`; ``psd`` may be a stack of spectra on that grid,
        shape (W, n), each row's answer its own (a list of them).
    tremor_band : (float, float)
        Where the tremor peak is searched, Hz.
    cutoff_range : (float, float)
        Where ``f_d`` may lie, Hz.  Every returned cut-off is inside it.
    default_cutoff : float
        The fallback, Hz; must lie in ``cutoff_range``.
    min_depth_db : float
        How deep a dip must be to count as a valley.
    rule : {"paper", "shallow", "floor"} or another registered rule
        A name in :mod:`wake.registry` (the built-in rules below are
        :func:`paper_rule`, :func:`shallow_rule` and :func:`floor_rule`).
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
        PADS and on the paper's synthetic set (docs/studies/design.md, "Cut-off on
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
        A key of :data:`CUTOFF_FLAGS`.  A stack of spectra gives a list of ``(cutoff, flag)``, one per row.

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
    args = (tremor_band, cutoff_range, default_cutoff, min_depth_db, shallow_max, floor_margin_db, edge_db)
    try:
        settings = _settings(*args)
    except TypeError:   # something unhashable (a list): checked, and refused by name, without the cache
        settings = _settings.__wrapped__(*args)
    decide = get_cutoff_rule(rule).function
    psd = np.asarray(psd, dtype=float)
    found = [decide(s) for s in _analyse_rows(np.asarray(freqs, dtype=float), psd.reshape(-1, psd.shape[-1]),
                                               settings)]
    return found[0] if psd.ndim == 1 else found


@functools.lru_cache(maxsize=64, typed=True)   # typed: True is not 1 (check_positive refuses a bool)
def _settings(tremor_band, cutoff_range, default_cutoff, min_depth_db, shallow_max, floor_margin_db, edge_db):
    """:func:`find_cutoff`'s settings checked, as the keywords of :class:`Spectrum` (the same for every window
    of a stream: checked once), read-only."""
    lo, hi = cutoff_range
    if not 0 < lo <= default_cutoff <= hi:
        raise ValueError(
            f"need 0 < cutoff_range[0] <= default_cutoff <= cutoff_range[1], got "
            f"cutoff_range={cutoff_range!r}, default_cutoff={default_cutoff!r}"
        )
    if isinstance(shallow_max, bool) or not isinstance(shallow_max, (int, float, np.floating, np.integer)) \
            or not lo <= shallow_max < np.inf:
        raise ValueError(f"shallow_max must be a finite frequency at or above cutoff_range[0] = {lo:g} Hz, "
                         f"got {shallow_max!r}")
    floor_margin_db = check_positive("floor_margin_db", floor_margin_db)
    edge_db = check_positive("edge_db", edge_db)
    if not 0 < tremor_band[0] < tremor_band[1]:
        raise ValueError(f"tremor_band must be (low, high) with 0 < low < high, got {tremor_band!r}")
    return MappingProxyType(dict(cutoff_range=(lo, hi), tremor_band=tremor_band, default_cutoff=default_cutoff,
                                 min_depth_db=min_depth_db, shallow_max=shallow_max,
                                 floor_margin_db=floor_margin_db, edge_db=edge_db))


def _analyse_rows(freqs, P, settings) -> list:
    """:func:`_analyse` of each row of ``P`` (W, n), one :class:`Spectrum` each: on a rising grid the dB spectra,
    local maxima, peaks, valleys and their left maxima of every row at once (the same elementwise operations,
    first-occurrence argmax and argmin over the same bins, so each row's numbers are its own), else row by row."""
    inner, above, ascending = _bins(freqs, settings["tremor_band"])
    if not ascending or not inner.size or P.shape[0] == 1:   # one row: its own calls cost less than the stack's
        return [_analyse(freqs, row, settings) for row in P]
    lo, hi = settings["cutoff_range"]
    top, bottom = P.max(axis=1), P.min(axis=1)   # both finite exactly when every bin is (a NaN propagates into max)
    live = np.isfinite(top) & np.isfinite(bottom) & (top > 0)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        db = 10 * np.log10(np.maximum(P, top[:, None] * 1e-30))
    middle = db[:, inner]
    peaked = (middle >= db[:, inner - 1]) & (middle >= db[:, inner + 1])
    masked = np.where(peaked, middle, -np.inf)
    peaks = inner[np.argmax(masked, axis=1)]
    first = int(np.searchsorted(freqs, lo, side="left"))
    stops = np.searchsorted(freqs, np.minimum(hi, freqs[peaks]), side="right")
    span = np.arange(first, freqs.size)
    valleys = first + np.argmin(np.where(span < stops[:, None], db[:, first:], np.inf), axis=1)
    left = np.maximum.accumulate(db, axis=1)[np.arange(P.shape[0]), valleys]
    floors = db[:, above].min(axis=1) if above.size else [None] * P.shape[0]   # each row's noise floor
    out = []
    # the tests of each row, made for every row at once (the same comparisons and first-occurrence maxima)
    for i, (alive, any_peak, top_peak, narrow) in enumerate(zip(live.tolist(), peaked.any(axis=1).tolist(),
                                                                masked.max(axis=1).tolist(),
                                                                (stops - first < 3).tolist())):
        if not alive:
            out.append(Spectrum(freqs, None, None, None, None, fallback="silent", **settings))
        elif not any_peak:
            out.append(Spectrum(freqs, db[i], None, None, None, fallback="no_tremor_peak", **settings))
        elif top_peak == -np.inf:   # every local maximum at -inf dB (an underflowed floor): as one row
            out.append(_analyse(freqs, P[i], settings))
        elif narrow:
            out.append(Spectrum(freqs, db[i], peaks[i], None, None, fallback="no_valley", floor=floors[i], **settings))
        else:
            out.append(Spectrum(freqs, db[i], peaks[i], valleys[i], left[i], floor=floors[i], **settings))
    return out


def _analyse(freqs, psd, settings) -> "Spectrum":
    """The tremor peak and the valley below it, or the fallback flag that says why there is none (one row, any
    grid: what :func:`_analyse_rows` computes for a stack on a rising grid)."""
    lo, hi = settings["cutoff_range"]
    inner, _, ascending = _bins(freqs, settings["tremor_band"])
    top, bottom = psd.max(), psd.min()   # both finite exactly when every bin is (a NaN propagates into max)
    if not (np.isfinite(top) and np.isfinite(bottom)) or top <= 0:
        return Spectrum(freqs, None, None, None, None, fallback="silent", **settings)
    db = 10 * np.log10(np.maximum(psd, top * 1e-30))
    local_max = inner[(db[inner] >= db[inner - 1]) & (db[inner] >= db[inner + 1])]
    if local_max.size == 0:
        return Spectrum(freqs, db, None, None, None, fallback="no_tremor_peak", **settings)
    peak = local_max[np.argmax(db[local_max])]
    top_search = min(hi, freqs[peak])
    if ascending:   # the bins in [lo, top_search]: one run of them, found by bisection
        first = int(np.searchsorted(freqs, lo, side="left"))
        search = np.arange(first, max(first, int(np.searchsorted(freqs, top_search, side="right"))))
    else:
        search = np.flatnonzero((freqs >= lo) & (freqs <= top_search))
    if search.size < 3:
        return Spectrum(freqs, db, peak, None, None, fallback="no_valley", **settings)
    valley = search[np.argmin(db[search])]
    return Spectrum(freqs, db, peak, valley, db[: valley + 1].max(), **settings)


#: :func:`_bins` of the grids seen last (a stream's windows share one grid: ar_psd's), by their bytes
_BINS: dict = {}


def _bins(freqs, tremor_band) -> tuple:
    """``(inner, above, ascending)`` of a frequency grid: the bins inside ``tremor_band`` that have a neighbour on
    both sides (where a tremor peak may lie), the noise floor's bins (:meth:`Spectrum.noise_floor`) and whether
    the grid rises strictly (then a band of it is one run of bins).  Made once per grid and band."""
    key = (freqs.tobytes(), tuple(tremor_band))
    found = _BINS.get(key)
    if found is None:
        inner = np.flatnonzero((freqs >= tremor_band[0]) & (freqs <= tremor_band[1]))
        inner = inner[(inner > 0) & (inner < freqs.size - 1)]
        above = np.flatnonzero(freqs > tremor_band[1])[::-1][::FLOOR_STRIDE]
        ascending = bool(freqs.size and np.isfinite(freqs).all() and (np.diff(freqs) > 0).all())
        for part in (inner, above):
            part.flags.writeable = False
        if len(_BINS) >= 16:
            _BINS.clear()
        found = _BINS[key] = (inner, above, ascending)
    return found


@dataclass(frozen=True)
class Spectrum:
    """What a cut-off rule reads: a window's spectrum in dB, its tremor peak and its valley below it.

    When there is no valley to judge, ``fallback`` says why (``"silent"``, ``"no_tremor_peak"``,
    ``"no_valley"``: a key of :data:`FALLBACK_FLAGS`) and the fields it leaves unknown are None; a rule
    then usually answers ``(default_cutoff, fallback)``.
    """

    freqs: np.ndarray
    db: np.ndarray | None
    peak: int | None      #: bin of the tremor peak (the largest local maximum inside tremor_band)
    valley: int | None    #: bin of the PSD minimum over cutoff_range below the peak
    left: float | None    #: the largest PSD value at or below the valley (the voluntary content), dB
    cutoff_range: tuple
    tremor_band: tuple
    default_cutoff: float
    min_depth_db: float
    shallow_max: float
    floor_margin_db: float
    edge_db: float
    fallback: str | None = None
    floor: float | None = None   #: the noise floor when the analysis has it (:meth:`noise_floor`), dB

    @property
    def deep(self) -> bool:
        """Whether the valley lies at least ``min_depth_db`` below both the tremor peak and ``left``."""
        db, v = self.db, self.valley
        return not (db[v] > db[self.peak] - self.min_depth_db or db[v] > self.left - self.min_depth_db)

    def noise_floor(self) -> float:
        """The lowest PSD above the tremor band, over fs/2 and every FLOOR_STRIDE-th bin below it (dB;
        -inf without bins there)."""
        if self.floor is not None:
            return self.floor
        above = _bins(self.freqs, self.tremor_band)[1]
        return self.db[above].min() if above.size else -np.inf


@register_cutoff_rule("paper", c_name="WAKE_HPA_RULE_PAPER",
                      description="the paper's: a 3 dB valley, else default_cutoff")
def paper_rule(s: Spectrum):
    """The valley when it is deep, else ``default_cutoff``."""
    return _valley_or_dip(s, shallow=False, floor=-np.inf)


@register_cutoff_rule("shallow", c_name="WAKE_HPA_RULE_SHALLOW",
                      description="also a shallower dip below a tremor peak, at or below shallow_max")
def shallow_rule(s: Spectrum):
    """As ``"paper"``, and a shallower dip below a tremor peak at or below ``shallow_max``."""
    return _valley_or_dip(s, shallow=True, floor=-np.inf)


@register_cutoff_rule("floor", c_name="WAKE_HPA_RULE_FLOOR",
                      description=("as 'shallow', with both compared to the noise floor above the tremor band "
                                   "(on PADS 33 % instead of 82 % of windows on 2 Hz)"))
def floor_rule(s: Spectrum):
    """As ``"shallow"``, with the dip and the valley compared to the noise floor (:meth:`Spectrum.noise_floor`)."""
    return _valley_or_dip(s, shallow=True, floor=s.noise_floor() if s.fallback is None else -np.inf)


def _valley_or_dip(s: Spectrum, *, shallow: bool, floor: float):
    if s.fallback is not None:
        return float(s.default_cutoff), s.fallback
    freqs, db, valley = s.freqs, s.db, s.valley
    lo, hi = s.cutoff_range
    if not s.deep:
        if shallow:
            # a dip shallower than min_depth_db: its minimum, but only where voluntary motion can end
            # and, rule "floor", only well above the noise floor
            low = np.flatnonzero((freqs >= lo) & (freqs <= min(hi, s.shallow_max, freqs[s.peak])))
            if low.size >= 3:
                dip = low[np.argmin(db[low])]
                # a minimum on the lowest bin is no dip: the PSD rises from there into the tremor peak
                # (rest tremor on slow drift; docs/studies/design.md, "Rest tremor with little voluntary motion")
                if dip > low[0] and db[dip] >= floor + s.floor_margin_db:
                    return float(freqs[dip]), "shallow_valley"
        return float(s.default_cutoff), "no_valley"
    if db[valley] < floor + s.floor_margin_db:
        # a valley at the noise floor: where the minimum falls inside the gap is noise; the gap's low
        # edge is where the voluntary content ends
        # walking down from the valley while the bin below is at or above lo and within edge_db of it: the
        # edge is one above the highest bin below the valley where that fails (bin 0 when none does)
        stop = np.flatnonzero(~((freqs[:valley] >= lo) & (db[:valley] <= db[valley] + s.edge_db)))
        edge = int(stop[-1]) + 1 if stop.size else 0
        return float(freqs[edge]), "floor_valley"
    return float(freqs[valley]), "valley"
