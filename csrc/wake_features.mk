# Generated from wake.firmware.sources.FEATURE_ENTRIES by `python -m wake.firmware.sources --write-make`:
# do not edit (tests/firmware/test_c_layout.py checks that they agree).  The entry points of each
# feature: a firmware built without the feature links none of them.

WAKE_ENTRIES_WAKE_RTP_AHEAD := wake_rtp_set_ahead wake_rtp_set_ahead_ramp wake_rtp_ahead_output wake_rtp_load_ahead_state wake_rtp_get_ahead_state
WAKE_ENTRIES_WAKE_RTP_SPLIT := wake_rtp_prepare wake_rtp_finish wake_rtp_finish_missing wake_rate_step
WAKE_ENTRIES_WAKE_RTP_VOLUNTARY_AHEAD := wake_rtp_set_voluntary_ahead wake_rtp_voluntary_ahead_output wake_rtp_run_outputs

# $(call wake_entries_off,FLAGS): the entries of the features a build with FLAGS leaves off
wake_entries_off = $(if $(filter -DWAKE_RTP_AHEAD=0,$(1)),$(WAKE_ENTRIES_WAKE_RTP_AHEAD)) $(if $(filter -DWAKE_RTP_SPLIT -DWAKE_RTP_SPLIT=1,$(1)),,$(WAKE_ENTRIES_WAKE_RTP_SPLIT)) $(if $(filter -DWAKE_RTP_VOLUNTARY_AHEAD -DWAKE_RTP_VOLUNTARY_AHEAD=1,$(1)),,$(WAKE_ENTRIES_WAKE_RTP_VOLUNTARY_AHEAD))
