"""The firmware cost profiler (wake/profile.py): the instruction counter and a real profile.

No timing assertions: only that the counter counts what the processor
issues, and that a profile of the real core is well formed.
"""

import math
import shutil

import numpy as np
import pytest

from wake.firmware import profile

unicorn = pytest.importorskip("unicorn", reason="unicorn is not installed (pip install unicorn capstone)")
pytest.importorskip("capstone", reason="capstone is not installed (pip install unicorn capstone)")

from support import CSRC

needs_gcc = pytest.mark.skipif(shutil.which("arm-none-eabi-gcc") is None,
                               reason="arm-none-eabi-gcc is not installed (the Arm GNU toolchain)")

# Thumb-2, assembled with arm-none-eabi-as:
#   0x00  2000  movs  r0, #0
#   0x02  2801  cmp   r0, #1
#   0x04  bf0c  ite   eq
#   0x06  2101  moveq r1, #1        condition fails
#   0x08  2102  movne r1, #2
#   0x0a  bf08  it    eq
#   0x0c  3105  addeq r1, #5        condition fails
#   0x0e  bf00  nop
#   0x10  1c0a  adds  r2, r1, #0
#   0x12  be00  bkpt  #0            stop address (not executed)
SNIPPET = bytes.fromhex("002001280cbf0121022108bf053100bf0a1c00be")
BASE, STOP = 0x1000, 0x1012
ISSUED = 9  # every instruction before the stop, the two condition-failed ones included


def _snippet_emulator():
    from unicorn import arm_const

    uc = unicorn.Uc(unicorn.UC_ARCH_ARM, unicorn.UC_MODE_THUMB | unicorn.UC_MODE_MCLASS)
    if hasattr(uc, "ctl_set_cpu_model") and hasattr(arm_const, "UC_CPU_ARM_CORTEX_M4"):
        uc.ctl_set_cpu_model(arm_const.UC_CPU_ARM_CORTEX_M4)
    uc.mem_map(0, 0x10000)
    uc.mem_write(BASE, SNIPPET)
    return uc


def test_block_counter_counts_condition_failed_it_instructions():
    from unicorn import arm_const

    uc = _snippet_emulator()
    counter = profile.BlockCounter(uc)
    per_insn = []
    uc.hook_add(unicorn.UC_HOOK_CODE, lambda _uc, addr, size, _u: per_insn.append(addr))
    uc.emu_start(BASE | 1, STOP)
    assert uc.reg_read(arm_const.UC_ARM_REG_PC) == STOP
    assert uc.reg_read(arm_const.UC_ARM_REG_R2) == 2  # movne ran, moveq/addeq did not
    assert counter.count == ISSUED
    # The per-instruction hook is what the block counter exists to avoid: it
    # never reports more than the processor issues (and, in the unicorn
    # versions this was written against, skips the failed IT instructions).
    assert len(per_insn) <= ISSUED


def test_block_counter_reset_and_repeat():
    uc = _snippet_emulator()
    counter = profile.BlockCounter(uc)
    for _ in range(3):
        counter.reset()
        uc.emu_start(BASE | 1, STOP)
        assert counter.count == ISSUED


def test_arithmetic_floor():
    # J 2^J + J^2 + J + J + J(J+1)/2 + J
    assert profile.arithmetic_floor(5) == 160 + 25 + 5 + 5 + 15 + 5
    assert profile.arithmetic_floor(3) == 24 + 9 + 3 + 3 + 6 + 3


def test_adversarial_inputs_are_int16_and_full_scale():
    x = profile.adversarial_inputs(4, 64, measurement=np.arange(100, dtype=np.int16))
    assert set(x) == set(profile.INPUT_KINDS)
    for v in x.values():
        assert v.dtype == np.int16 and v.shape == (64,)
    assert x["square_nyquist"].max() == 32767 and x["square_nyquist"].min() == -32768
    assert not x["silence"].any()


@pytest.fixture(scope="module")
def m4_emulator(tmp_path_factory):
    try:
        # the sources of this checkout, also when the package under test is an installed copy
        image = profile.build_image("m4-O2", build_dir=tmp_path_factory.mktemp("profile"), csrc=CSRC)
    except profile.ProfileUnavailable as exc:  # pragma: no cover - environment dependent
        pytest.skip(str(exc))
    return profile.Emulator(image)


@needs_gcc
def test_profile_of_the_real_core_level_3(m4_emulator):
    prof = profile.profile_configuration(m4_emulator, "sym3", 3, kalman=True, n=40)
    for value in (prof.max, prof.median, prof.min):
        assert math.isfinite(value) and value > 0
    assert prof.max >= prof.median >= prof.min
    assert prof.max >= prof.steady_max
    assert prof.set_weights > 0
    assert 0 < prof.stack_bytes < 4096


@needs_gcc
def test_footprint_and_static_stack(m4_emulator):
    fp = profile.footprint(m4_emulator.image, m4_emulator)
    assert fp["text"] > 0 and fp["state"] > 0
    depth, path, _ext = fp["stack_static"]
    assert path[0] == "wake_rtp_step" and depth > 0


def _image_against_host(emu, level, kind):
    """Predictions of ``emu`` and of the host build for the same parameters and input."""
    cb = pytest.importorskip("wake.rtp.fixed", reason="the C extension is not built")
    params = profile.fitted_parameters("sym3", level, kalman=True, formats=emu.formats)
    x = profile.adversarial_inputs(level, 3 * 2**level, measurement=params["measurement"])[kind]
    emu.write_config(params)
    emu.init()
    ours = [emu.step(int(s))[0] for s in x]
    fs = params["full_scale"]
    lsb = fs**2 / 2.0**emu.p_frac
    host = cb.FixedPointRTP(params["taps"] / 2.0**emu.tap_frac, params["weights"] / 2.0**emu.weight_frac,
                            params["r"] * lsb, params["q"] * lsb, params["p0"] * lsb, full_scale=fs)
    one = 2.0**emu.sample_frac
    theirs = np.round(host.run(x / one * fs) / fs * one).astype(int)
    return ours, list(theirs)


@needs_gcc
def test_prediction_matches_the_host_core(m4_emulator):
    """The image computes what the host build computes (same C, other compiler)."""
    ours, theirs = _image_against_host(m4_emulator, 3, "random")
    assert ours == theirs


@needs_gcc
@pytest.mark.parametrize("kind", ["random", "square_window"])
def test_cortex_m0plus_arithmetic_is_the_host_arithmetic(tmp_path, kind):
    """Without a 64-bit multiply the FIR sums split taps in 32 bits and products are
    built from 16-bit halves; the predictions are still the host's, bit for bit."""
    try:
        image = profile.build_image("m0plus-O2", build_dir=tmp_path, csrc=CSRC, defs=["-DWAKE_RTP_MAX_LEVEL=5"])
    except profile.ProfileUnavailable as exc:  # pragma: no cover - environment dependent
        pytest.skip(str(exc))
    ours, theirs = _image_against_host(profile.Emulator(image), 5, kind)
    assert len(ours) == 3 * 32 and ours == theirs


def _fake_profile(target, kalman, measured, bound, build=""):
    from types import SimpleNamespace

    from wake.firmware.wcet import Bound
    return SimpleNamespace(target=target, level=5, wavelet="sym3", kalman=kalman, max=measured, build=build,
                           max_cycles=measured, bound=Bound("wake_rtp_step", bound, bound, [], []))


def test_check_targets_separates_goals_from_regression_ceilings():
    from wake.firmware.profile.build import CEILING_LIMITS, LEAN_BUILD, TARGET_LIMITS
    from wake.firmware.profile.report import check_targets
    lean_name = LEAN_BUILD[0]
    foot = {"m4-O2": {"state": 464, "stack_static": (104, []), "code": 5720},
            "m4-Os": {"state": 464, "stack_static": (128, []), "code": 3724},
            "m4-O2-no-ahead": {"state": 376, "stack_static": (104, []), "code": 4912},
            "m4-Os-no-ahead": {"state": 376, "stack_static": (120, []), "code": 3060}}
    # the current core's figures: with the tremor ahead the M4 bound 599 <= 650 (issue 32), its state 88 B;
    # without it the cost issue's goals (493 / 348 within 1.4 % / 1.5 % of the measured worst, M0+ 1,429,
    # 3,060 B <= 3,072 B); ceilings held
    lean = [_fake_profile("m4-O2", True, 486, 493, lean_name), _fake_profile("m4-O2", False, 343, 348, lean_name),
            _fake_profile("m0plus-O2", True, 1362, 1429, lean_name)]
    full = [_fake_profile("m4-O2", True, 592, 599), _fake_profile("m4-O2", False, 448, 453),
            _fake_profile("m0plus-O2", True, 1958, 2031)]
    profiles = full + lean
    assert check_targets(profiles, foot, TARGET_LIMITS) == []
    assert check_targets(profiles, foot, CEILING_LIMITS) == []
    # the tremor ahead past the issue's goal, or its state past 256 B per channel, misses it
    slow = [_fake_profile("m4-O2", True, 660, 670)] + profiles[1:]
    assert any("static bound, Kalman active: 670 > 650" in f for f in check_targets(slow, foot, TARGET_LIMITS))
    big = dict(foot, **{"m4-O2": {"state": 640, "stack_static": (104, []), "code": 5720}})
    assert any("state of the tremor ahead 264 B > 256 B" in f for f in check_targets(profiles, big, TARGET_LIMITS))
    # the code of the previous core (3,652 B at -Os) missed the goal and is past today's ceiling
    fat = dict(foot, **{"m4-Os-no-ahead": {"state": 376, "stack_static": (108, []), "code": 3652}})
    assert any("WAKE_RTP_AHEAD=0) 3,652 B > 3,072 B" in f for f in check_targets(profiles, fat, TARGET_LIMITS))
    assert any("3,652 B > 3,200 B" in f for f in check_targets(profiles, fat, CEILING_LIMITS))
    # the core before the covariance restart (bound 683, 5,424 B) is past today's ceilings
    carried = full + [_fake_profile("m4-O2", True, 654, 683, lean_name)] + lean[1:]
    old_foot = dict(foot, **{"m4-Os-no-ahead": {"state": 496, "stack_static": (140, []), "code": 5424}})
    failures = check_targets(carried, old_foot, CEILING_LIMITS)
    assert any("683 > 520" in f for f in failures) and any("5,424 B > 3,200 B" in f for f in failures)
    # the figures before the bound was tightened (gap 8.6 %): a missed goal, and past the 7 % ceiling
    loose = full + [_fake_profile("m4-O2", True, 638, 693, lean_name)] + lean[1:]
    assert any("bound 693 is more than 5 % above the measured worst 638" in f
               for f in check_targets(loose, foot, TARGET_LIMITS))
    assert any("more than 7 %" in f for f in check_targets(loose, foot, CEILING_LIMITS))
    # a measured step above its static bound fails under either set: the bound would be wrong
    unsound = profiles + [_fake_profile("m4-Os", True, 1100, 1017)]
    for limits in (TARGET_LIMITS, CEILING_LIMITS):
        assert any("exceed the static bound" in f for f in check_targets(unsound, foot, limits))
    # a regression of the bound past its ceiling fails --check, in either build
    worse = [_fake_profile("m4-O2", True, 900, 950)] + profiles[1:]
    assert any("950 > 620" in f for f in check_targets(worse, foot, CEILING_LIMITS))
    # the code ceiling of the default build names the size of the build without the Kalman update beside it
    heavy = dict(foot, **{"m4-Os": {"state": 464, "stack_static": (128, []), "code": 4100},
                          "m4-Os-no-kalman": {"state": 464, "stack_static": (88, []), "code": 2340}})
    assert any("4,100 B > 3,850 B (2,340 B built with WAKE_RTP_KALMAN=0" in f
               for f in check_targets(profiles, heavy, CEILING_LIMITS))
    # and so does the Cortex-M0+ bound of the core before its FIR split the taps
    before = full + lean[:2] + [_fake_profile("m0plus-O2", True, 2568, 2824, lean_name)]
    assert any("2,824 > 1,500" in f for f in check_targets(before, foot, CEILING_LIMITS))


def test_loop_annotation_may_hold_any_bound_expression():
    """A `wcet-loop:` bound is read up to the comment's end, `*` included (the portable ring fill's `2 * N`)."""
    from wake.firmware.wcet import LOOP_ANNOTATION
    assert LOOP_ANNOTATION.search("for (i = 0; i < 2u * N; ++i) {   /* wcet-loop: 2 * N */").group(1) == "2 * N"
    assert LOOP_ANNOTATION.search("} while (h != end);  /* wcet-loop: N / 4 */ /* not this */").group(1) == "N / 4"
    assert LOOP_ANNOTATION.search("/* steps 1 and 2   wcet-loop: 2 */").group(1) == "2"
    assert LOOP_ANNOTATION.search("/* a loop without a bound */") is None


@needs_gcc
@pytest.mark.parametrize("kalman", [True, False], ids=["active", "inert"])
def test_static_bound_holds_and_is_tight_on_cortex_m4(tmp_path, kalman):
    """docs/studies/profiling.md: the bound is never below a measured step, and within 5 % of the worst one (J = 5).

    Two things keep it tight: a one-block loop that tests at its end counts B iterations, not B + 1
    (wake.firmware.wcet), and check_structure tests an inert instance's covariance without a branch on
    `inert`, so an inert and a live instance pay the same."""
    image = profile.build_image("m4-O2", build_dir=tmp_path, csrc=CSRC, defs=["-DWAKE_RTP_MAX_LEVEL=5"])
    prof = profile.profile_configuration(profile.Emulator(image), "sym3", 5, kalman=kalman)
    assert prof.max <= prof.bound.instructions <= 1.05 * prof.max, (prof.max, prof.bound.instructions)


@needs_gcc
def test_front_end_cost_at_1khz(tmp_path):
    """docs/studies/design.md, "In firmware": the front end's push beside the RTP step, from the static bounds."""
    from wake.firmware.rate_cost import rate_cost
    from wake.firmware.wcet import static_bound

    image = profile.build_image("m4-O2", build_dir=tmp_path, csrc=CSRC, defs=["-DWAKE_RTP_MAX_LEVEL=5"])
    push = static_bound(image, 5, function="wake_rate_push").instructions
    step = static_bound(image, 5).instructions
    fast, slow = rate_cost(1000.0, step, push), rate_cost(100.0, step, None)
    assert fast["per_sample"] == step + push and slow["per_sample"] == step
    assert push <= 0.2 * step, (push, step)  # 63 against 493 measured: UDIV, no 16-turn loop
    assert fast["per_second"] <= 10 * slow["per_second"]  # issue 33: at most 10x the work per second


@needs_gcc
@pytest.mark.parametrize("ahead", [True, False], ids=["ahead", "no-ahead"])
def test_split_step_keeps_1khz_within_the_100hz_bound(tmp_path, ahead):
    """Issue 33 (docs/studies/design.md, "In firmware"): built with WAKE_RTP_SPLIT 1, the worst input sample at
    1 kHz (the static bound of wake_rate_step) is no larger than wake_rtp_step's at 100 Hz on Cortex-M4
    -O2, like with like (the tremor ahead compiled in at both rates, or at neither); the default build,
    what a 100 Hz firmware links, has none of the split entries."""
    from wake.firmware.rate_cost import rate_cost
    from wake.firmware.wcet import static_bound

    defs = ["-DWAKE_RTP_MAX_LEVEL=5"] + ([] if ahead else ["-DWAKE_RTP_AHEAD=0"])
    plain = profile.build_image("m4-O2", build_dir=tmp_path / "plain", csrc=CSRC, defs=defs)
    split = profile.build_image("m4-O2", build_dir=tmp_path / "split", csrc=CSRC, defs=[*defs, "-DWAKE_RTP_SPLIT=1"])
    # what the firmware links (the core's footprint object, the image's front end): every module is compiled in
    # both builds (no feature switch in a .c), the split's entries are linked in the split build only
    linked = {b: set(profile.build._defined_functions(image.core_object)) for b, image in (("plain", plain),
                                                                                            ("split", split))}
    assert "wake_rtp_prepare" not in linked["plain"] and "wake_rate_step" not in plain.symbols
    assert "wake_rtp_prepare" in linked["split"] and "wake_rate_step" in split.symbols

    def bound(function):
        return static_bound(split, 5, function=function).instructions

    step = static_bound(plain, 5).instructions
    b = {"push": bound("wake_rate_push"), "prepare": bound("wake_rtp_prepare"),
         "finish": max(bound("wake_rtp_finish"), bound("wake_rtp_finish_missing")), "rate_step": bound("wake_rate_step")}
    fast = rate_cost(1000.0, step, b["push"], b)
    assert fast["per_sample"] == b["rate_step"] <= step, (b, step)
    # the entry is a push and one of prepare / finish, plus a dispatch of a few instructions
    assert max(b["prepare"], b["finish"]) < b["rate_step"] <= b["push"] + max(b["prepare"], b["finish"]) + 20, b
    assert rate_cost(1000.0, step, b["push"])["per_sample"] > step  # unsplit: push + step, over the 100 Hz bound
