"""The package as installed: one abi3 wheel for every CPython >= 3.9 (issue 36, item 4).

Always (an installed distribution): its WHEEL tags are `cp39-abi3-<platform>` and the extension
module is the stable-ABI build (`_beadchain.abi3.so`), i.e. PyO3's `abi3-py39` feature is what
was built. With `BEADCHAIN_WHEEL=<path of the .whl>` (as `.ci/run` sets it): the package imported
is the one installed from that wheel, not the source tree (the extension's bytes hash to the
wheel's RECORD entry), and neither cargo nor rustc is on PATH (a wheel handed around installs and
runs without Rust).
"""

import base64
import hashlib
import importlib.metadata
import os
import pathlib
import shutil
import sys
import zipfile

import pytest

import beadchain
import beadchain._beadchain as ext

ROOT = pathlib.Path(__file__).resolve().parents[2]
WHEEL = os.environ.get("BEADCHAIN_WHEEL")


def installed_tags():
    """The `Tag:` lines of the installed distribution's WHEEL file."""
    try:
        dist = importlib.metadata.distribution("beadchain")
    except importlib.metadata.PackageNotFoundError:
        pytest.skip("beadchain is not installed as a distribution (imported from a path)")
    text = dist.read_text("WHEEL")
    assert text is not None, "the installed beadchain has no WHEEL file"
    return [l.split(":", 1)[1].strip() for l in text.splitlines() if l.startswith("Tag:")]


def record_hash(data):
    """A RECORD-style hash: sha256=<urlsafe base64 without padding>."""
    digest = hashlib.sha256(data).digest()
    return "sha256=" + base64.urlsafe_b64encode(digest).rstrip(b"=").decode()


def test_installed_distribution_is_abi3():
    tags = installed_tags()
    assert tags, "the installed WHEEL file names no tag"
    for tag in tags:
        assert tag.startswith("cp39-abi3-"), f"wheel tag {tag}: not one wheel for CPython >= 3.9"


@pytest.mark.skipif(sys.platform == "win32", reason="Windows extensions carry no abi3 suffix")
def test_extension_is_stable_abi_build():
    name = pathlib.Path(ext.__file__).name
    assert name == "_beadchain.abi3.so", f"extension module {name}: not the stable-ABI build"


@pytest.mark.skipif(not WHEEL, reason="BEADCHAIN_WHEEL is not set (only CI's wheel install)")
def test_imported_package_is_the_wheel():
    name = pathlib.Path(WHEEL).name
    assert "-cp39-abi3-" in name, f"{name}: not an abi3 wheel"
    pkg = pathlib.Path(beadchain.__file__).resolve()
    assert ROOT / "python" not in pkg.parents, f"beadchain imported from the source tree: {pkg}"
    with zipfile.ZipFile(WHEEL) as z:
        record = next(n for n in z.namelist() if n.endswith(".dist-info/RECORD"))
        wheel_tag = next(
            l.split(":", 1)[1].strip()
            for l in z.read(record.replace("RECORD", "WHEEL")).decode().splitlines()
            if l.startswith("Tag:")
        )
        rows = dict(l.split(",")[:2] for l in z.read(record).decode().splitlines() if l)
    assert wheel_tag in installed_tags()
    so = pathlib.Path(ext.__file__)
    key = f"beadchain/{so.name}"
    assert key in rows, f"{key} is not in {name}"
    assert record_hash(so.read_bytes()) == rows[key], f"{so} is not the extension of {name}"


@pytest.mark.skipif(not WHEEL, reason="BEADCHAIN_WHEEL is not set (only CI's wheel install)")
def test_no_rust_toolchain_on_path():
    for tool in ("cargo", "rustc"):
        assert shutil.which(tool) is None, f"{tool} is on PATH: {shutil.which(tool)}"
