"""``wake export-c --layout``: every layout's files, and its manifest against the format's documented schema.

The schema rules are written from each format's specification; each check names its source:

- PlatformIO ``library.json``: https://docs.platformio.org/en/latest/manifests/library-json/
  (fields ``name``, ``version``, ``description``, ``keywords``, ``homepage``, ``license``,
  ``frameworks``, ``platforms``, ``headers``, ``build`` with ``flags``, ``srcDir``, ``includeDir``,
  ``srcFilter``).
- Arduino ``library.properties``: the Arduino library specification, 1.5 format
  (https://arduino.github.io/arduino-cli/latest/library-specification/).
- Zephyr ``zephyr/module.yml``: https://docs.zephyrproject.org/latest/develop/modules.html
  ("Module yaml file description", "Build settings").
"""

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from wake.firmware.folder import CORE_FILES, export_folder
from wake.firmware.layouts import LAYOUTS, library_json, zephyr_files

ROOT = Path(__file__).resolve().parents[2]
CONFIG = dict(wavelet="sym3", level=5, measurement_noise=1e-3, full_scale=4.0)
SEMVER = re.compile(r"^(0|[1-9]\d*)\.(0|[1-9]\d*)\.(0|[1-9]\d*)(?:-[0-9A-Za-z.-]+)?(?:\+[0-9A-Za-z.-]+)?$")


def check_library_json(manifest: dict, root: Path) -> list[str]:
    """Problems of a PlatformIO library.json (empty: valid)."""
    problems = []
    # library-json: "name" and "version" are required
    for key in ("name", "version"):
        if not isinstance(manifest.get(key), str) or not manifest[key]:
            problems.append(f"{key} missing")
    # library-json/fields/name: max 50 characters
    if len(manifest.get("name", "")) > 50:
        problems.append("name longer than 50 characters")
    # library-json/fields/version: semantic versioning (semver.org)
    if not SEMVER.match(manifest.get("version", "")):
        problems.append("version is not semver")
    # library-json/fields/description: max 255 characters
    if len(manifest.get("description", "")) > 255:
        problems.append("description longer than 255 characters")
    # library-json/fields/keywords: a list (or comma-separated string) of keywords, each max 50
    # characters, lower case letters, digits, and the characters "-", "+", ".", " "
    for kw in manifest.get("keywords", []):
        if len(kw) > 50 or not re.fullmatch(r"[a-z0-9+. -]+", kw):
            problems.append(f"keyword {kw!r}")
    # library-json/fields/frameworks, platforms: "*" or a list of names
    for key in ("frameworks", "platforms"):
        value = manifest.get(key, "*")
        if value != "*" and not (isinstance(value, list) and all(isinstance(v, str) for v in value)):
            problems.append(f"{key} is neither '*' nor a list")
    # library-json/fields/build: srcDir / includeDir are paths relative to the library root
    build = manifest.get("build", {})
    src = root / build.get("srcDir", "src")
    if not src.is_dir():
        problems.append(f"srcDir {src} does not exist")
    include = root / build.get("includeDir", "include")
    if "includeDir" in build and not include.is_dir():
        problems.append(f"includeDir {include} does not exist")
    # library-json/fields/headers: the headers a user includes, found in the include or source folder
    for h in manifest.get("headers", []):
        if not ((src / h).is_file() or (include / h).is_file()):
            problems.append(f"header {h} not found")
    # library-json/fields/build/flags: a list of strings (or one string)
    if not isinstance(build.get("flags", []), (list, str)):
        problems.append("build.flags")
    known = {"name", "version", "description", "keywords", "homepage", "repository", "authors", "license",
             "frameworks", "platforms", "headers", "build", "export", "examples", "dependencies"}
    problems += [f"unknown field {k}" for k in manifest if k not in known]
    return problems


ARDUINO_REQUIRED = ("name", "version", "author", "maintainer", "sentence", "paragraph", "category", "url")
# library-specification: "category" must be one of these (else "Uncategorized", with a warning)
ARDUINO_CATEGORIES = {"Display", "Communication", "Signal Input/Output", "Sensors", "Device Control",
                      "Timing", "Data Storage", "Data Processing", "Other"}


def check_library_properties(text: str, root: Path) -> list[str]:
    """Problems of an Arduino library.properties (empty: valid)."""
    problems, fields = [], {}
    for line in text.splitlines():
        if not line or line.startswith("#"):
            continue
        key, sep, value = line.partition("=")       # specification: key=value lines, UTF-8
        if not sep:
            problems.append(f"line without '=': {line!r}")
        fields[key] = value
    problems += [f"{k} missing" for k in ARDUINO_REQUIRED if not fields.get(k)]
    # specification, "name": starts with a letter or number; letters, numbers, spaces, underscores,
    # dots and dashes; no leading/trailing space; at most 63 characters
    name = fields.get("name", "")
    if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9 _.-]*", name) or name != name.strip() or len(name) > 63:
        problems.append(f"name {name!r}")
    # specification, "version": semver-compliant
    if not SEMVER.match(fields.get("version", "")):
        problems.append("version is not semver")
    if fields.get("category") not in ARDUINO_CATEGORIES:
        problems.append(f"category {fields.get('category')!r}")
    # specification, "url": the library's web page
    if not re.match(r"https?://", fields.get("url", "")):
        problems.append("url is not an http(s) address")
    # specification, 1.5 format: the sources in src/ at the library root
    if not (root / "src").is_dir():
        problems.append("no src/ folder")
    # specification, "includes": comma-separated headers, present in src/
    for h in filter(None, fields.get("includes", "").split(",")):
        if not (root / "src" / h).is_file():
            problems.append(f"include {h} not in src/")
    return problems


def check_zephyr_module(root: Path) -> list[str]:
    """Problems of a Zephyr module (zephyr/module.yml and what it points at)."""
    problems, doc, section = [], {}, None
    # module.yml is YAML; this one uses only "key: value" and one nested mapping (build), parsed here
    # without a YAML dependency
    for line in (root / "zephyr" / "module.yml").read_text().splitlines():
        m = re.match(r"^( *)([\w-]+):\s*(.*)$", line)
        if not m:
            problems.append(f"unparsed line {line!r}")
            continue
        indent, key, value = m.groups()
        if not indent:
            section = key
            doc[key] = value or {}
        else:
            doc[section][key] = value
    # modules.html: "name" names the module; letters, digits, "-" and "_" (it becomes a CMake variable)
    if not re.fullmatch(r"[A-Za-z0-9_-]+", str(doc.get("name", ""))):
        problems.append("name")
    build = doc.get("build", {})
    # modules.html, Build settings: build.cmake is the folder (relative to the module root) with the
    # CMakeLists.txt; build.kconfig the Kconfig file
    if not (root / build.get("cmake", "") / "CMakeLists.txt").is_file():
        problems.append("build.cmake has no CMakeLists.txt")
    if not (root / build.get("kconfig", "")).is_file():
        problems.append("build.kconfig missing")
    known = {"cmake", "kconfig", "cmake-ext", "kconfig-ext", "depends", "settings"}
    problems += [f"unknown build key {k}" for k in build if k not in known]
    glue = (root / build.get("cmake", "") / "CMakeLists.txt").read_text()
    for c in ("wake_rtp.c", "wake_hpa.c"):
        m = re.search(r"\$\{ZEPHYR_CURRENT_MODULE_DIR\}(/[\w/]+)?/" + re.escape(c), glue)
        if not m or not (root / (m.group(1) or "/").lstrip("/") / c).is_file():
            problems.append(f"the glue does not compile an existing {c}")
    return problems



@pytest.mark.parametrize("layout", LAYOUTS)
def test_every_layout_holds_the_unchanged_core(layout, tmp_path):
    files = export_folder(tmp_path, layout=layout, **CONFIG)
    prefix = "src/" if layout in ("platformio", "arduino") else ""
    for n in CORE_FILES:
        assert (tmp_path / prefix / n).read_bytes() == (ROOT / "csrc" / n).read_bytes()
    assert (tmp_path / prefix / "wake_config.h").is_file()
    assert all(f.is_file() for f in files) and (tmp_path / "README.md") in files


def test_platformio_layout_validates(tmp_path):
    export_folder(tmp_path, layout="platformio", **CONFIG)
    assert check_library_json(json.loads((tmp_path / "library.json").read_text()), tmp_path) == []


def test_arduino_layout_validates(tmp_path):
    export_folder(tmp_path, layout="arduino", **CONFIG)
    assert check_library_properties((tmp_path / "library.properties").read_text(), tmp_path) == []


def test_zephyr_layout_validates(tmp_path):
    export_folder(tmp_path, layout="zephyr", **CONFIG)
    assert check_zephyr_module(tmp_path) == []


def test_schema_checks_reject_bad_manifests(tmp_path):
    export_folder(tmp_path, layout="arduino", **CONFIG)
    text = (tmp_path / "library.properties").read_text()
    assert any("category" in p for p in check_library_properties(text.replace("Signal Input/Output", "DSP"), tmp_path))
    assert any("url missing" in p for p in check_library_properties(re.sub(r"url=.*\n", "", text), tmp_path))
    bad = json.loads(library_json())
    bad["version"], bad["keywords"] = "v1", ["Tremor!"]
    problems = check_library_json(bad, tmp_path)
    assert "version is not semver" in problems and any("keyword" in p for p in problems)


def test_repository_manifests_are_the_generators_output():
    """The repository's library.json and zephyr/ (sources in csrc/) come from wake.firmware.layouts."""
    assert (ROOT / "library.json").read_text() == library_json(src_dir="csrc")
    for name, text in zephyr_files(src_dir="csrc").items():
        assert (ROOT / name).read_text() == text
    assert check_library_json(json.loads((ROOT / "library.json").read_text()), ROOT) == []
    assert check_zephyr_module(ROOT) == []


@pytest.mark.slow
def test_cmake_layout_builds_with_cmake(tmp_path):
    cmake = __import__("shutil").which("cmake")
    if cmake is None:
        pytest.skip("cmake not found")
    export_folder(tmp_path / "wake", layout="cmake", **CONFIG)
    build = tmp_path / "build"
    subprocess.run([cmake, "-S", str(tmp_path / "wake"), "-B", str(build)], check=True, capture_output=True)
    subprocess.run([cmake, "--build", str(build)], check=True, capture_output=True)
    assert list(build.glob("libwake_rtp.*")) and list(build.glob("libwake_hpa.*"))


def test_cli_writes_the_chosen_layout(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "wake", "export-c", str(tmp_path), "--layout", "zephyr"],
                          cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "zephyr" / "module.yml").is_file()
    bad = subprocess.run([sys.executable, "-m", "wake", "export-c", str(tmp_path / "x"), "--layout", "keil"],
                         cwd=ROOT, capture_output=True, text=True)
    assert bad.returncode != 0 and "invalid choice: 'keil'" in bad.stderr
