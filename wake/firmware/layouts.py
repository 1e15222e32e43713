"""Firmware project layouts for ``wake export-c DIR --layout ...``: how embedded build systems take a library.

Every layout holds the same C core (:data:`wake.firmware.folder.CORE_FILES`, copied unchanged) and
the generated configuration header; they differ in where the files go and which manifest describes
them:

``plain``
    The files side by side, with a README on adding them to a Makefile or CMake project.
``cmake``
    The same plus ``CMakeLists.txt`` and ``cmake/`` (the Cortex-M4 / M0+ toolchain files and the
    package configuration), copied from ``csrc/``: ``add_subdirectory(DIR)`` or an installable
    ``find_package(wake)`` package (docs/reference/packaging.md).
``platformio``
    ``library.json`` with the sources in ``src/`` (PlatformIO's default source folder).
``arduino``
    ``library.properties`` with the sources in ``src/`` (the Arduino 1.5 library format).
``zephyr``
    ``zephyr/module.yml`` with its CMake glue (``zephyr/CMakeLists.txt``) and ``zephyr/Kconfig``
    (``CONFIG_WAKE``), the sources at the module root.

The manifests are written by the functions here, the one place their fields are set; the
repository's own ``library.json`` and ``zephyr/`` (for a project that takes the git repository
itself) are the same functions' output for sources in ``csrc/`` (tests/firmware/test_layouts.py
checks they match).
"""

from __future__ import annotations

import json
from pathlib import Path

from wake import __version__
from wake.firmware.sources import HPA_SOURCES, RTP_SOURCES

__all__ = ["LAYOUTS", "layout_files", "library_json", "library_properties", "zephyr_files"]

#: The layouts ``wake export-c --layout`` writes.
LAYOUTS = ("plain", "cmake", "platformio", "arduino", "zephyr")

NAME = "wake"
VERSION = __version__  # the package metadata's, so a firmware folder says which release wrote it
SUMMARY = ("WAKE real-time tremor extraction: fixed-point wavelet predictor with adaptive Kalman "
           "filtering and a single-precision hyper-parameter adjustment, C99, no allocation")
#: The project's address in the manifests: the package's PyPI page (pyproject.toml names it wake-tremor).
HOMEPAGE = "https://pypi.org/project/wake-tremor/"
LICENSE = "MIT"
#: Compiler flag the HPA needs (a fixed evaluation order: docs/studies/hpa_c.md); harmless for the RTP.
HPA_FLAG = "-ffp-contract=off"
#: Files of csrc/ the cmake layout copies beside the core.
CMAKE_FILES = ("CMakeLists.txt", "cmake/arm-cortex-m4.cmake", "cmake/arm-cortex-m0plus.cmake",
               "cmake/arm-none-eabi.cmake", "cmake/wakeConfig.cmake.in")


def library_json(src_dir: str | None = None) -> str:
    """PlatformIO ``library.json``; ``src_dir`` is the sources' folder when it is not ``src/``."""
    build = {"flags": [HPA_FLAG]}
    if src_dir is not None:
        build.update(srcDir=src_dir, includeDir=src_dir,
                     srcFilter=["-<*>", *(f"+<{m}>" for m in RTP_SOURCES), *(f"+<{c}>" for c in HPA_SOURCES),
                                "+<wake_rate.c>"])
    manifest = {
        "name": NAME,
        "version": VERSION,
        "description": SUMMARY,
        "keywords": ["tremor", "kalman", "wavelet", "fixed-point", "dsp"],
        "homepage": HOMEPAGE,
        "license": LICENSE,
        "frameworks": "*",
        "platforms": "*",
        "headers": ["wake_rtp.h", "wake_hpa.h", "wake_rate.h"],
        "build": build,
    }
    return json.dumps(manifest, indent=2) + "\n"


def library_properties() -> str:
    """Arduino ``library.properties`` (the sources in ``src/``)."""
    fields = {
        "name": "WAKE tremor",
        "version": VERSION,
        "author": "WAKE authors",
        "maintainer": "WAKE authors",
        "sentence": "Real-time tremor extraction: wavelet predictor with adaptive Kalman filtering.",
        "paragraph": SUMMARY + ".",
        "category": "Signal Input/Output",
        "url": HOMEPAGE,
        "architectures": "*",
        "includes": "wake_rtp.h,wake_hpa.h,wake_rate.h",
    }
    return "".join(f"{k}={v}\n" for k, v in fields.items())


def zephyr_files(src_dir: str = ".") -> dict[str, str]:
    """``zephyr/module.yml``, ``zephyr/CMakeLists.txt`` and ``zephyr/Kconfig`` for sources in ``src_dir``."""
    base = "${ZEPHYR_CURRENT_MODULE_DIR}" + ("" if src_dir == "." else f"/{src_dir}")
    module = f"name: {NAME}\nbuild:\n  cmake: zephyr\n  kconfig: zephyr/Kconfig\n"
    cmake = f"""# Zephyr glue for the WAKE C core (module.yml: build.cmake). Enabled by CONFIG_WAKE.
if(CONFIG_WAKE)
  zephyr_library()
  zephyr_library_sources({" ".join(f"{base}/{m}" for m in RTP_SOURCES)} {base}/wake_rate.c)
  zephyr_library_sources({" ".join(f"{base}/{c}" for c in HPA_SOURCES)})
  zephyr_include_directories({base})
  # the HPA's fixed evaluation order (docs/studies/hpa_c.md)
  zephyr_library_compile_options({HPA_FLAG})
endif()
"""
    kconfig = """config WAKE
\tbool "WAKE real-time tremor extraction (fixed-point RTP, single-precision HPA)"
\thelp
\t  Builds the WAKE C core: wake_rtp.c (fixed-point predictor), wake_hpa*.c
\t  (hyper-parameter adjustment, single precision) and wake_rate.c (the
\t  front end for input rates above 150 Hz).
"""
    return {"zephyr/module.yml": module, "zephyr/CMakeLists.txt": cmake, "zephyr/Kconfig": kconfig}


def layout_files(layout: str, core: dict[str, str], src: Path) -> dict[str, str]:
    """Relative path -> text of every file of ``layout``, from the core files' texts ``core``
    (name -> text: the C core and the configuration header) and the sources' folder ``src``.

    Raises
    ------
    ValueError
        ``layout`` is not one of :data:`LAYOUTS`.
    FileNotFoundError
        The cmake layout's files are missing from ``src`` (sources older than the CMake project).

    Examples
    --------
    >>> sorted(layout_files("arduino", {"wake_rtp.c": "", "wake_rtp.h": ""}, Path(".")))
    ['library.properties', 'src/wake_rtp.c', 'src/wake_rtp.h']
    """
    if layout not in LAYOUTS:
        raise ValueError(f"unknown layout {layout!r}: choose one of {', '.join(LAYOUTS)}")
    if layout in ("platformio", "arduino"):
        files = {f"src/{n}": text for n, text in core.items()}
        files["library.json" if layout == "platformio" else "library.properties"] = (
            library_json() if layout == "platformio" else library_properties())
        return files
    files = dict(core)
    if layout == "cmake":
        missing = [n for n in CMAKE_FILES if not (src / n).is_file()]
        if missing:
            raise FileNotFoundError(f"{src} lacks {', '.join(missing)}: give --sources a csrc/ with the CMake "
                                    "project, or choose another layout")
        files.update({n: (src / n).read_text(encoding="utf-8") for n in CMAKE_FILES})
    elif layout == "zephyr":
        files.update(zephyr_files())
    return files
