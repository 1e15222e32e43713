"""help(WakeFilter) documents every parameter, with the same text as help(WakeConfig)."""

import dataclasses
import re

from wake import WakeConfig, WakeFilter
from wake._docs import parameters_doc


def _documented(doc):
    return set(re.findall(r"^    (\w+)(?:, \w+)* :", doc, re.M)) | {
        name for line in re.findall(r"^    ((?:\w+, )+\w+)$", doc, re.M) for name in line.split(", ")}


def test_every_setting_is_documented_in_help_wakefilter():
    settings = {f.name for f in dataclasses.fields(WakeConfig)}
    assert {"cutoff_rule", "hpa_backend", "shallow_max", "warmup_hpa_s", "initial_weights"} <= settings
    missing = settings - _documented(WakeFilter.__doc__)
    assert not missing, f"help(WakeFilter) does not document {sorted(missing)}"
    assert "config : WakeConfig" in WakeFilter.__doc__


def test_wakefilter_shows_wakeconfigs_own_text():
    assert parameters_doc(WakeConfig) in WakeFilter.__doc__


def test_the_automatic_full_scale_is_described_as_the_code_computes_it():
    doc = " ".join(WakeFilter.__doc__.split())
    assert "99th percentile" in doc and "headroom * max|x|" not in doc
