"""The C core's status codes in words: the one check every wrapper of ``wake._rtp`` calls.

Examples
--------
>>> from wake._rtp import lib
>>> from wake.rtp.status import check_status
>>> check_status(lib.WAKE_RTP_OK, "wake_rtp_reset")
"""

from __future__ import annotations

from wake._rtp import lib

__all__ = ["check_status"]

_STATUS_TEXT = {
    int(lib.WAKE_RTP_E_NULL): "null pointer",
    int(lib.WAKE_RTP_E_LEVEL): "level out of range",
    int(lib.WAKE_RTP_E_TAPS): "taps out of range",
    int(lib.WAKE_RTP_E_WEIGHTS): "weights out of range (w and w_h lie within ±64)",
    int(lib.WAKE_RTP_E_NOISE): "bad noise values",
    int(lib.WAKE_RTP_E_UNINIT): "uninitialised state",
    int(lib.WAKE_RTP_E_CORRUPT): "corrupted state",
    int(lib.WAKE_RTP_E_STATE): "bad state values",
    int(lib.WAKE_RTP_E_NO_KALMAN): "a Kalman setting in a core built without the Kalman update (WAKE_RTP_KALMAN 0)",
    int(lib.WAKE_RTP_E_AHEAD): "a tremor-ahead value out of range",
    int(lib.WAKE_RTP_E_UNPREPARED): "a finish without a prepare since the last step",
    int(lib.WAKE_RTP_E_FEATURE): "an entry of a feature this core is built without (WAKE_RTP_AHEAD, WAKE_RTP_SPLIT or "
                                 "WAKE_RTP_VOLUNTARY_AHEAD 0)",
}
_OK = int(lib.WAKE_RTP_OK)


def check_status(status, what: str) -> None:
    """Raise ``RuntimeError`` naming the C call ``what`` and its status in words unless ``status`` is OK."""
    status = int(status)
    if status != _OK:
        raise RuntimeError(f"{what} failed: {_STATUS_TEXT.get(status, 'unknown error')} (status {status})")
