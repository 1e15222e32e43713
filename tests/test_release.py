"""The release in one place: the version of the package metadata (pyproject.toml) is the one that
``wake.__version__``, the C core's CMake package, the firmware manifests, CITATION.cff and CHANGELOG.md say."""

import json
import re
from pathlib import Path

import pytest

import wake

ROOT = Path(__file__).resolve().parents[1]


def pyproject_version():
    text = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    found = re.findall(r'^version = "([^"]+)"$', text, re.M)
    assert len(found) == 1, f"pyproject.toml sets the version {len(found)} times, not once"
    return found[0]


def test_the_version_is_set_once_and_read_from_the_metadata():
    version = pyproject_version()
    assert re.fullmatch(r"\d+\.\d+\.\d+", version), version
    assert wake.__version__ == version
    # wake/__init__.py holds no version literal of its own: it reads the metadata
    assert version not in (ROOT / "wake" / "__init__.py").read_text(encoding="utf-8")


def test_the_c_core_and_the_firmware_manifests_carry_the_same_version():
    version = pyproject_version()
    cmake = (ROOT / "csrc" / "CMakeLists.txt").read_text(encoding="utf-8")
    assert re.search(r"^project\(wake VERSION (\S+) ", cmake, re.M)[1] == version
    assert json.loads((ROOT / "library.json").read_text(encoding="utf-8"))["version"] == version
    from wake.firmware.layouts import library_json

    assert json.loads(library_json())["version"] == version


def test_changelog_and_citation_name_this_release():
    version = pyproject_version()
    changelog = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    releases = re.findall(r"^## \[(\d+\.\d+\.\d+)\] - (\d{4}-\d{2}-\d{2})$", changelog, re.M)
    assert "## [Unreleased]" in changelog
    assert releases and releases[0][0] == version, f"CHANGELOG.md's newest release is not {version}"
    assert [r[1] for r in releases] == sorted((r[1] for r in releases), reverse=True), "releases out of order"
    cff = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    assert re.search(r"^version: (\S+)$", cff, re.M)[1] == version
    assert re.search(r'^date-released: "([\d-]+)"$', cff, re.M)[1] == releases[0][1]
    # the method's paper, with its four authors, is the reference
    for author in ("Shahtalebi", "Atashzar", "Patel", "Mohammadi"):
        assert f"family-names: {author}" in cff


def test_citation_file_is_valid_cff():
    yaml = pytest.importorskip("yaml", reason="PyYAML is needed to parse CITATION.cff")
    data = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    for key in ("cff-version", "message", "title", "authors", "version", "date-released", "license"):
        assert key in data, f"CITATION.cff lacks the required or expected key {key!r}"
    assert data["cff-version"] == "1.2.0"
    paper = data["references"][0]
    assert paper["type"] == "article" and paper["title"].startswith("WAKE: Wavelet Decomposition")
