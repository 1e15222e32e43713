"""Limits every layer shares: the highest decomposition level.

The lowest layer of the package (docs/reference/architecture.md), so that the filter
bank (:mod:`wake.wavelets`), the configuration (:mod:`wake.config`) and the
C core's formats (:mod:`wake.rtp.qformat`) read one number.
"""

__all__ = ["MAX_LEVEL"]

#: Highest decomposition level J, for the float reference and the C core alike
#: (the C struct is sized by ``WAKE_RTP_MAX_LEVEL``, which must equal it).
MAX_LEVEL = 6
