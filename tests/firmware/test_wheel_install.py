"""From a wheel in a fresh virtualenv, not the checkout: ``wake profile --quick`` and ``wake export-c`` work.

The firmware tools need the C sources, which the wheel ships as package data
(``wake._csrc``).  This test builds the wheel from a copy of the source tree,
installs it into a new virtualenv whose only other contents are the running
interpreter's third-party packages (numpy, scipy, ... through a ``.pth`` file,
so no network is needed for them), runs both commands from an empty folder
and compiles the exported folder for Cortex-M4 and for the host.
"""

import os
import shutil
import site
import subprocess
import sys
import sysconfig
import venv
from pathlib import Path

import pytest

from wake.firmware.sources import HPA_SOURCES, INTERNAL_HEADERS, RTP_HEADERS, RTP_SOURCES  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
ARM_CC = shutil.which("arm-none-eabi-gcc")
HOST_CC = shutil.which("cc") or shutil.which("gcc")

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(not (ROOT / "pyproject.toml").is_file(), reason="needs the source tree to build a wheel"),
]

_IGNORE = shutil.ignore_patterns(".git", ".ci-venv", ".ci-dist", "build", "dist", "*.egg-info", "__pycache__", "*.so", "*.o",
                                 ".pytest_cache", ".benchmarks", ".hypothesis")


def _clean_env():
    # no PYTHONPATH: it would put a checkout before the venv's site-packages
    return {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "PYTHONSTARTUP")}


def _run(cmd, env=None, **kw):
    res = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, env=env or _clean_env(), **kw)
    assert res.returncode == 0, f"{cmd} exited {res.returncode}\nstdout:\n{res.stdout}\nstderr:\n{res.stderr}"
    return res


def _build_wheel(tmp: Path, env=None) -> Path:
    src = tmp / "src"
    shutil.copytree(ROOT, src, ignore=_IGNORE)
    dist = tmp / "dist"
    # -v: setuptools' own warnings reach the log (test_the_wheel_builds_without_setuptools_warnings)
    res = _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-v", "-w", dist, src], **({"env": env} if env else {}))
    (tmp / "build.log").write_text(res.stdout + res.stderr)
    wheels = list(dist.glob("wake_tremor-*.whl"))
    assert len(wheels) == 1, wheels
    return wheels[0]


#: the wheel .ci/run built (pip wheel -v) and installed, beside its build log: the test with a compiler takes it
#: rather than building the same wheel again
CI_WHEEL = os.environ.get("WAKE_CI_WHEEL")


def _ci_wheel(tmp: Path) -> Path:
    wheel = Path(CI_WHEEL)
    dist = tmp / "dist"
    dist.mkdir()
    shutil.copy(wheel.parent / "build.log", tmp / "build.log")
    return Path(shutil.copy(wheel, dist / wheel.name))


def _install(tmp_path_factory, build_env=None):
    tmp = tmp_path_factory.mktemp("wheel")
    wheel = _ci_wheel(tmp) if CI_WHEEL and build_env is None else _build_wheel(tmp, build_env)
    env_dir = tmp / "venv"
    venv.EnvBuilder(with_pip=False).create(env_dir)
    py = env_dir / ("Scripts/python.exe" if os.name == "nt" else "bin/python")
    purelib = Path(_run([py, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"]).stdout.strip())
    # installed before the outer packages become visible, so pip cannot take an installed copy
    # (an editable checkout, say) for this one
    _run([sys.executable, "-m", "pip", "--python", py, "install", "--no-deps", "-q", wheel])
    # the running interpreter's packages (numpy, scipy, unicorn, ...) after the venv's own:
    # a .pth line only extends sys.path, so an editable hook of the checkout there stays inert
    outer = [p for p in {*site.getsitepackages(), sysconfig.get_paths()["purelib"]} if Path(p).is_dir()]
    (purelib / "outer_packages.pth").write_text("\n".join(outer) + "\n")
    work = tmp / "work"
    work.mkdir()
    return env_dir, py, work


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    return _install(tmp_path_factory)


@pytest.fixture(scope="module")
def installed_without_compiler(tmp_path_factory):
    # CC=false: every compiler call fails, as on a machine without one
    return _install(tmp_path_factory, {**_clean_env(), "CC": "false", "WAKE_REQUIRE_C": "0"})


def test_without_a_compiler_the_package_installs_and_runs_on_the_reference(installed_without_compiler):
    env_dir, py, work = installed_without_compiler
    assert not list(env_dir.rglob("_rtp*.so")) and not list(env_dir.rglob("_rtp*.pyd"))
    demo = _run([env_dir / "bin" / "wake", "demo"], cwd=work)
    assert "(backend reference," in demo.stdout and "NRMSE relative to the paper" in demo.stdout
    assert "CoreMissingWarning" in demo.stderr and "C compiler" in demo.stderr
    res = subprocess.run([str(py), "-c", "from wake import WakeFilter; WakeFilter(backend='c')"], cwd=work,
                         capture_output=True, text=True, env=_clean_env())
    assert res.returncode == 1 and "CoreUnavailable" in res.stderr and "pip install" in res.stderr


def test_with_a_compiler_the_demo_runs_on_the_c_core(installed):
    env_dir, py, work = installed
    demo = _run([env_dir / "bin" / "wake", "demo"], cwd=work)
    assert "(backend c," in demo.stdout and "CoreMissingWarning" not in demo.stderr


def test_the_package_comes_from_the_wheel_not_the_checkout(installed):
    env_dir, py, work = installed
    out = _run([py, "-c", "import wake, wake.firmware.sources as s; print(wake.__file__); print(s.csrc_dir())"],
               cwd=work).stdout.split("\n")
    assert Path(out[0]).resolve().is_relative_to(env_dir.resolve()), out
    assert Path(out[1]).resolve().is_relative_to(env_dir.resolve()), out


@pytest.mark.skipif(ARM_CC is None, reason="arm-none-eabi-gcc is not installed (the Arm GNU toolchain)")
def test_profile_quick_from_the_wheel(installed):
    pytest.importorskip("unicorn", reason="unicorn is not installed (pip install unicorn capstone)")
    pytest.importorskip("capstone", reason="capstone is not installed (pip install unicorn capstone)")
    env_dir, py, work = installed
    res = _run([env_dir / "bin" / "wake", "profile", "--quick"], cwd=work)
    assert "Cortex-M4, -O2" in res.stdout and "static bound" in res.stdout


@pytest.mark.skipif(ARM_CC is None or HOST_CC is None,
                    reason="needs arm-none-eabi-gcc and a host C compiler (cc or gcc) on PATH")
def test_export_c_from_the_wheel_compiles_for_cortex_m4_and_the_host(installed):
    env_dir, py, work = installed
    _run([env_dir / "bin" / "wake", "export-c", "fw", "--level", "5", "--wavelet", "sym3"], cwd=work)
    fw = work / "fw"
    assert sorted(p.relative_to(fw).as_posix() for p in fw.rglob("*") if p.is_file()) == sorted(
        ["README.md", "wake_config.h", "wake_fixed.h", *HPA_SOURCES, "wake_hpa.h", *INTERNAL_HEADERS,
         "wake_rate.c", "wake_rate.h", *RTP_HEADERS, *RTP_SOURCES])
    (fw / "use_config.c").write_text('#include "wake_hpa.h"\n#include "wake_config.h"\n'
                                     "int start(void) { static wake_rtp_t r; static wake_hpa_t h;\n"
                                     "  return wake_config_init(&r) + (int)wake_config_hpa_init(&h); }\n")
    for cc, extra in ((ARM_CC, ["-mcpu=cortex-m4", "-mthumb"]), (HOST_CC, [])):
        for src in (*RTP_SOURCES, *HPA_SOURCES, "use_config.c"):
            _run([cc, "-std=c99", "-Wall", "-Wextra", "-Werror", *extra, "-c", src, "-o", f"{src}.{Path(cc).name}.o"],
                 cwd=fw)


def test_the_wheel_builds_without_setuptools_package_warnings(installed):
    env_dir, py, work = installed
    log = (work.parent / "build.log").read_text()
    assert "running build_py" in log  # the verbose build log was captured
    # the C sources' folders are declared packages, not "importable but absent from packages"
    assert "absent from the `packages` configuration" not in log and "Package would be ignored" not in log
