"""Helpers shared by the test modules (importable: pytest puts tests/ on sys.path)."""

import os
import shutil
from pathlib import Path

import numpy as np

#: The C sources of this checkout: tests build them rather than a possibly
#: older copy installed with the package.
CSRC = Path(__file__).resolve().parents[1] / "csrc"


def pads_dir():
    """The PADS subset next to the checkout (or $WAKE_PADS_DIR), if present."""
    env = os.environ.get("WAKE_PADS_DIR")
    path = Path(env) if env else Path(__file__).resolve().parents[1].parent / "shared" / "data" / "pads"
    return path if path.is_dir() and any(path.glob("*.txt")) else None


def pdkit_dir():
    """pdkit's smartphone tremor-task recordings next to the checkout (or $WAKE_PDKIT_DIR), if present."""
    env = os.environ.get("WAKE_PDKIT_DIR")
    path = Path(env) if env else Path(__file__).resolve().parents[1].parent / "shared" / "data" / "pdkit"
    return path if path.is_dir() and any(path.glob("T_-_*.csv")) else None


def has_c_backend():
    from wake.rtp import c_backend_available

    return c_backend_available()


NO_PADS = "PADS recordings not found next to the checkout (../shared/data/pads) or in $WAKE_PADS_DIR"
NO_CORE = "the compiled C core wake._rtp is not built"
NO_PDKIT = "pdkit recordings not found next to the checkout (../shared/data/pdkit) or in $WAKE_PDKIT_DIR"


def missing_tools(*names):
    """A skip reason naming exactly the tools of ``names`` that are not on PATH, or None when all are."""
    missing = [n for n in names if shutil.which(n) is None]
    if not missing:
        return None
    return f"{' and '.join(missing)} {'is' if len(missing) == 1 else 'are'} not installed (on PATH)"


#: the environment variable in which .ci/run lists the steps that have passed before pytest ("make-test",
#: "standalone-check"): a test that would only run one of them again skips, or checks that step's outputs
CI_PASSED = "WAKE_CI_PASSED"


def ci_passed(step):
    """Whether CI already ran ``step`` and it passed (.ci/run lists it in $WAKE_CI_PASSED); never outside CI."""
    return step in os.environ.get(CI_PASSED, "").split()


def ci_skip_reason(target):
    """The skip reason of a test that would only run ``make -C csrc target`` again after CI's own step did."""
    return (f"CI already ran `make -C csrc {target}` and it passed (.ci/run lists it in ${CI_PASSED}); "
            "a plain pytest runs it")


def prove_script(name):
    """The module of one of csrc/tests/prove's scripts (eva_check, wp_check, assigns_check), loaded from its file."""
    import importlib.util
    path = Path(__file__).resolve().parents[1] / "csrc" / "tests" / "prove" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


# -- the readers of wake.io.formats (tests/io/test_formats*.py) ---------------------------------------------

TREMOR_HZ = 6.0
NO_PARADIGMA = ("the ParaDigMa example files are not next to the checkout (../shared/data/paradigma) nor in "
                "$WAKE_PARADIGMA_DIR")


def paradigma_dir():
    """The folder of the two ParaDigMa files (CWA, TSDF) next to the checkout (or $WAKE_PARADIGMA_DIR), if present."""
    env = os.environ.get("WAKE_PARADIGMA_DIR")
    path = Path(env) if env else Path(__file__).resolve().parents[1].parent / "shared" / "data" / "paradigma"
    return path if (path / "axivity").is_dir() and (path / "tsdf_imu").is_dir() else None


def motion(fs, kind, seconds=20.0, seed=0):
    """Three axes of wrist motion at ``fs``: ``(x, tremor)``, each (n, 3).

    ``kind`` "gyro": rad/s, slow voluntary rotation and a 6 Hz tremor;
    "acc": m/s^2 with gravity (9.81 on z, tilting slowly) under the same.
    """
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(seconds * fs))) / fs
    phases = rng.uniform(0, 2 * np.pi, 3)
    voluntary = np.column_stack([np.sin(2 * np.pi * 0.4 * t + p) for p in phases])
    tremor = 0.3 * np.column_stack([np.sin(2 * np.pi * TREMOR_HZ * t + 2 * p) for p in phases])
    if kind == "acc":
        voluntary = 2.0 * voluntary + np.array([0.0, 0.0, 9.81]) * np.cos(0.2 * np.sin(2 * np.pi * 0.1 * t))[:, None]
    x = voluntary + tremor + 0.01 * rng.standard_normal(voluntary.shape)
    return x, tremor


UNITS = {"gyro": "rad/s", "acc": "m/s^2"}


def tremor_captured(estimate, truth, fs, skip_s=8.0):
    """Correlation of the filter's tremor with the true tremor after the warm-up (NaN rows left out)."""
    k = int(skip_s * fs)
    e, t = np.asarray(estimate)[k:], np.asarray(truth)[k:]
    ok = np.isfinite(e)
    return float(np.corrcoef(e[ok], t[ok])[0, 1])


def load_build_ffi():
    """The checkout's build_ffi.py as a module, loaded by its path: under CI the package is installed from its
    wheel and the checkout's top is not on sys.path."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("build_ffi", Path(__file__).resolve().parents[1] / "build_ffi.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


#: every per-sample output of WakeFilter.run that a bit-for-bit comparison of two paths covers
RUN_OUTPUTS = ("prediction", "voluntary", "tremor", "tremor_ahead", "confidence", "command", "full_scale", "clipped",
               "saturations", "full_scale_changes")


def assert_same_history(a, b):
    """Two HPA histories (per channel, a list of HPAUpdate) equal field by field, arrays bit for bit."""
    assert len(a) == len(b)
    for ups_a, ups_b in zip(a, b):
        assert len(ups_a) == len(ups_b) > 0
        for u, v in zip(ups_a, ups_b):
            assert u.__dict__.keys() == v.__dict__.keys()
            for name, value in u.__dict__.items():
                other = v.__dict__[name]
                if isinstance(value, np.ndarray) or isinstance(other, np.ndarray):
                    assert np.array_equal(value, other), (u.index, name)
                else:
                    assert value == other, (u.index, name, value, other)


def assert_same_results(res, ref):
    """Two WakeFilter.run results equal bit for bit: every output in RUN_OUTPUTS and the HPA history."""
    for name in RUN_OUTPUTS:
        assert np.array_equal(getattr(res, name), getattr(ref, name), equal_nan=True), name
    assert_same_history(res.hpa, ref.hpa)
