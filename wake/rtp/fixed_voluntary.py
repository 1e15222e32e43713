"""The voluntary motion ahead of the fixed-point C core (``WAKE_RTP_VOLUNTARY_AHEAD``): the Python side of
:class:`~wake.rtp.fixed.FixedPointRTP`.

With ``horizon = h > 1`` the HPA fits a second weight vector ``w_h`` (``HPAUpdate.weights_ahead``) and the
RTP outputs ``v_h(n) = w_h' (a + d)``, the voluntary motion predicted for ``n + h`` from the state of the
one-step prediction (:class:`wake.rtp.reference.ReferenceRTP` is the float twin).  The C core runs it as a
second FIR ``B' w_h`` over the window plus one product, ``w_h' d = w_h' d_s + k (z - z_s)`` with
``k = w_h' w / |w|^2`` (docs/studies/design.md, "Voluntary motion at n + h"); the output is Q23 of the full scale.
Until a ``w_h`` is installed it is the one-step prediction held, as in the float reference.
"""

from __future__ import annotations

import numpy as np

from wake._rtp import ffi, lib
from wake.rtp.status import check_status as _check
from wake.rtp.qformat import STATE_FRAC, quantize_weights

__all__ = ["VoluntaryAheadMixin", "STRUCT_LAYOUT", "migrate_struct"]

#: The layout of the pickled struct (``"layout"`` in FixedPointRTP's pickled state): 2 since the voluntary motion
#: ahead is an instance (``wake_rtp_t::voluntary_ahead``, wake_voluntary_ahead.h); a state without the key is
#: layout 1, its fields in ``wake_rtp_t`` itself.
STRUCT_LAYOUT = 2
#: Where layout 1 put w_h: right after the tremor ahead, 4-byte aligned (``vol_weights``); layout 2 aligns the
#: instance to its int64 fields.  The fields after w_h sit where they sat (the int64 aligned them before too).
_W_H_BEFORE = ffi.offsetof("wake_rtp_t", "ahead") + ffi.sizeof("wake_ahead_t")
_W_H_BYTES = ffi.sizeof("wake_q24_t") * lib.WAKE_RTP_MAX_LEVEL
_REST_BEFORE = -(-(_W_H_BEFORE + _W_H_BYTES) // 8) * 8
_REST_NOW = ffi.offsetof("wake_rtp_t", "voluntary_ahead") + ffi.offsetof("wake_voluntary_ahead_t", "z_start")
#: The sizes of a layout-1 struct this core loads: whole, before the voluntary motion ahead, before the tremor
#: ahead (each part was appended to the struct, so an older struct is its prefix).
LAYOUT_1_SIZES = (_REST_BEFORE + ffi.sizeof("wake_rtp_t") - _REST_NOW, _W_H_BEFORE, ffi.offsetof("wake_rtp_t", "ahead"))


def migrate_struct(struct: bytes, layout: int = 1) -> bytes:
    """The bytes of a pickled ``wake_rtp_t`` in this core's layout (:data:`STRUCT_LAYOUT`).

    Parameters
    ----------
    struct : bytes
        The struct as pickled: the whole struct, or for layout 1 one of its prefixes (:data:`LAYOUT_1_SIZES`).
    layout : int
        The layout it was pickled in (1: no ``"layout"`` key in the state).

    Returns
    -------
    bytes
        The struct, or the same prefix of it, with w_h moved onto the instance's offset (layout 1); the
        bytes after the given prefix are the caller's to fill.

    Raises
    ------
    ValueError
        For a layout or a size this core does not know: re-create the filter instead of loading the state.

    Examples
    --------
    >>> from wake._rtp import ffi
    >>> size = ffi.sizeof("wake_rtp_t")
    >>> len(migrate_struct(bytes(LAYOUT_1_SIZES[0]))) == size
    True
    >>> migrate_struct(bytes(size), layout=3)
    Traceback (most recent call last):
    ...
    ValueError: this state was saved in struct layout 3 by another version of the C core (this one loads layouts 1 and 2); re-create the filter and run it again instead of loading the state
    """
    sizes = {1: LAYOUT_1_SIZES, STRUCT_LAYOUT: (ffi.sizeof("wake_rtp_t"),)}.get(layout)
    if sizes is None or not isinstance(struct, (bytes, bytearray)) or len(struct) not in sizes:
        what = (f"struct layout {layout!r}" if sizes is None else
                f"a struct of {len(struct) if isinstance(struct, (bytes, bytearray)) else type(struct).__name__}"
                f" bytes in layout {layout}")
        raise ValueError(f"this state was saved in {what} by another version of the C core (this one loads "
                         f"layouts 1 and {STRUCT_LAYOUT}); re-create the filter and run it again instead of "
                         "loading the state")
    if layout == STRUCT_LAYOUT or len(struct) <= _W_H_BEFORE:
        return bytes(struct)                   # today's layout, or a prefix that ends before w_h: nothing moved
    out = bytearray(ffi.sizeof("wake_rtp_t"))
    out[:_W_H_BEFORE] = struct[:_W_H_BEFORE]
    w_h = ffi.offsetof("wake_rtp_t", "voluntary_ahead")
    out[w_h:w_h + _W_H_BYTES] = struct[_W_H_BEFORE:_W_H_BEFORE + _W_H_BYTES]
    out[_REST_NOW:] = struct[_REST_BEFORE:]
    return bytes(out)


class VoluntaryAheadMixin:
    """``set_weights_ahead``, ``last_voluntary_ahead`` and ``run_outputs`` of the C core (issue 32).

    Needs the struct ``_state``, ``level``, ``full_scale`` and ``step`` / ``last_ahead`` of
    :class:`~wake.rtp.fixed.FixedPointRTP`.

    Examples
    --------
    >>> from wake.wavelets import filter_bank_taps
    >>> from wake.rtp.fixed import FixedPointRTP
    >>> rtp = FixedPointRTP(filter_bank_taps("sym3", 3), [0, 0, 1], 1e-3, full_scale=4.0)
    >>> rtp.set_weights_ahead([0, 0, 0.5])          # w_h: half of the approximation
    >>> _ = rtp.run(np.ones(20)); round(rtp.last_voluntary_ahead, 4)
    0.5
    >>> rtp.set_weights_ahead([0, 0, 99.0])
    Traceback (most recent call last):
    ...
    ValueError: weights must lie within ±64 in Q24 (int32); got max |w| 99
    """

    @property
    def has_weights_ahead(self) -> bool:
        """Whether a ``w_h`` is installed (until then :attr:`last_voluntary_ahead` is the one-step prediction)."""
        return bool(self._state.voluntary_ahead.set)

    @property
    def weights_ahead(self):
        """``w_h`` as the C core holds it (Q24, dequantised), or None while none is installed."""
        if not self._state.voluntary_ahead.set:
            return None
        return np.array([self._state.voluntary_ahead.weights[j] for j in range(self.level)]) / 2.0**24

    def set_weights_ahead(self, weights_ahead) -> None:
        """Install ``w_h`` (``level`` finite numbers within ±64) between two samples.

        The window, ``d``, ``P`` and every other output are untouched.  The C core has no way back to "no
        ``w_h``": None raises ValueError (the float reference's None keeps the one-step prediction).
        """
        if weights_ahead is None:
            raise ValueError("weights_ahead must be level finite numbers; the C core cannot uninstall w_h "
                             "(None is the float reference's 'hold the one-step prediction')")
        w_q = quantize_weights(weights_ahead, self.level)
        _check(lib.wake_rtp_set_voluntary_ahead(self._state, ffi.from_buffer("int32_t[]", w_q)),
               "wake_rtp_set_voluntary_ahead")

    @property
    def voluntary_ahead_saturations(self) -> int:
        """Narrowings of ``v_h`` that saturated (apart from :attr:`saturations`, which describe ``y``)."""
        return int(self._state.voluntary_ahead.saturations)

    @property
    def last_voluntary_ahead(self) -> float:
        """``w_h' (a + d)`` after the last sample (Q23 of the full scale); the one-step prediction ``y(n)``
        (Q23) while no ``w_h`` is installed."""
        return self._state.voluntary_ahead.output * (self.full_scale / 2.0**STATE_FRAC)

    def run_outputs(self, samples):
        """Step through a block (NaN = missing sample) in one call of the C core
        (``wake_rtp_run_outputs``): ``(voluntary, predicted, confidence, command, voluntary_ahead)`` arrays,
        as :meth:`ReferenceRTP.run_outputs` and bit for bit a loop of :meth:`step` reading :attr:`last_ahead`
        and :attr:`last_voluntary_ahead` after each sample; while no ``w_h`` is installed the last row is the
        returned one-step prediction (Q15), as before the C core had ``w_h``."""
        return tuple(self._run_block(samples, all_outputs=True))

    def _carry_from(self, other) -> None:
        """Take ``other``'s tremor ahead and fs (``AheadMixin._carry_ahead_from``) and its ``w_h`` when it has
        one (``other`` a FixedPointRTP or a ReferenceRTP)."""
        self._carry_ahead_from(other)
        w_h = getattr(other, "weights_ahead", None)
        if w_h is not None:
            self.set_weights_ahead(w_h)
