"""csrc/tests/prove/wp_check.py reads every goal of a WP log and passes it only when every goal is proved, the loop
variant's two among them (docs/studies/verification.md, "Termination").  The logs below follow the shapes of Frama-C 25's
messages; no Frama-C is needed."""

from support import prove_script


def _check():
    return prove_script("wp_check")


PROVED = """[wp] 3 goals scheduled
[wp] [Qed] Goal typed_run_pieces_loop_variant_positive : Valid (420ms)
[wp] [Qed] Goal typed_run_pieces_loop_variant_decrease : Valid (381ms)
[wp] [CVC4 1.8] Goal typed_run_pieces_assert_rte_signed_overflow_2 : Valid (Qed:59ms) (40ms) (15009)
[wp] Proved goals:    3 / 3
  Qed:             2  (3ms-89ms-425ms)
  CVC4 1.8:        1  (40ms-80ms) (17236)
"""
DETECT = """[wp] Prover       CVC4 1.8    [cvc4|CVC4:1.8]
[wp] Prover       CVC4 1.8    [cvc4-ce|CVC4:1.8:counterexamples]
"""


def test_a_log_with_every_goal_proved_passes():
    check = _check()
    result = check.parse(PROVED)
    assert (result["proved"], result["total"]) == (3, 3)
    assert result["goals"]["typed_run_pieces_assert_rte_signed_overflow_2"] == ("Valid", "CVC4 1.8")
    assert check.verdict(result) == []
    assert [m["name"] for m in check.DETECTED.finditer(DETECT)] == ["cvc4", "cvc4-ce"]


def test_an_unproved_goal_a_short_summary_or_a_missing_variant_fails():
    check = _check()
    timeout = PROVED.replace("decrease : Valid (381ms)", "decrease : Timeout (Qed:4ms) (30s)").replace("3 / 3", "2 / 3")
    problems = check.verdict(check.parse(timeout))
    assert any("Timeout" in p for p in problems) and any("proved 2 of 3" in p for p in problems)
    assert any("loop_variant_decrease" in p for p in problems)
    no_variant = "\n".join(line for line in PROVED.splitlines() if "variant" not in line).replace("3 / 3", "1 / 1")
    assert len(check.verdict(check.parse(no_variant))) == 2          # both variant goals missing
    assert check.verdict(check.parse("[kernel] user error: syntax error")) == ["proved 0 of 0 goals"] + [
        f"no proved goal {name} (the loop variant is gone?)" for name in check.REQUIRED]
