"""wake.rtp.status: every status the C core can return is put in words."""

import re

import pytest
from support import CSRC

from wake.rtp import c_backend_available

pytestmark = pytest.mark.skipif(not c_backend_available(), reason="the compiled C core (wake._rtp) is not built")


def statuses():
    """The error statuses wake_rtp_types.h declares, by name."""
    text = (CSRC / "wake_rtp_types.h").read_text()
    return re.findall(r"\b(WAKE_RTP_E_\w+) = -\d+", text)


def test_every_status_of_the_core_has_its_words():
    from wake._rtp import lib
    from wake.rtp.status import _STATUS_TEXT

    names = statuses()
    assert "WAKE_RTP_E_FEATURE" in names and len(names) >= 12
    assert {int(getattr(lib, n)) for n in names} == set(_STATUS_TEXT)


def test_a_refusal_names_the_call_and_the_reason():
    from wake._rtp import lib
    from wake.rtp.status import check_status

    check_status(lib.WAKE_RTP_OK, "wake_rtp_step")
    with pytest.raises(RuntimeError, match=r"wake_rtp_prepare failed: an entry of a feature .* \(status -12\)"):
        check_status(lib.WAKE_RTP_E_FEATURE, "wake_rtp_prepare")
    with pytest.raises(RuntimeError, match=r"unknown error \(status -99\)"):
        check_status(-99, "wake_rtp_step")
