"""Helpers shared by the test modules (importable: pytest puts tests/ on sys.path)."""

import os
import shutil
from pathlib import Path

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
