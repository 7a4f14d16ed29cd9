"""Guard the package layout: every module under the mapped folders reaches the install.

setuptools silently drops a subpackage missing from ``packages`` when it builds a wheel,
while an editable install still finds it; these tests catch that on either kind of install.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import pytest

import epistemica

from _modules import LAYERS, all_modules

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(
    not (ROOT / "pyproject.toml").exists(), reason="needs the source tree"
)


def _config() -> dict:
    if sys.version_info < (3, 11):
        pytest.skip("tomllib needs Python 3.11")
    import tomllib

    return tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]


def _source_packages() -> dict[str, Path]:
    """Every folder holding an __init__.py below each mapped root, by dotted name."""
    found = {}
    for dotted, folder in _config()["package-dir"].items():
        base = ROOT / folder
        for init in base.rglob("__init__.py"):
            rel = init.parent.relative_to(base)
            name = ".".join((dotted, *rel.parts)) if rel.parts else dotted
            found[name] = init.parent
    return found


def test_every_source_package_is_listed():
    listed = set(_config()["packages"])
    missing = sorted(set(_source_packages()) - listed)
    assert not missing, f"add {missing} to [tool.setuptools] packages in pyproject.toml"


_DATA = {".lark", ".epi", ".js", ".css", ".html"}


def _data_files(folder: Path) -> list[Path]:
    """The data files of a package: in its folder and in subfolders that are no package."""
    files = [p for p in folder.iterdir() if p.suffix in _DATA]
    for sub in folder.iterdir():
        if sub.is_dir() and not (sub / "__init__.py").exists():
            files += [p for p in sub.rglob("*") if p.suffix in _DATA]
    return files


def test_every_data_file_is_declared():
    data = _config().get("package-data", {})
    for dotted, folder in _source_packages().items():
        patterns = data.get(dotted, [])
        for path in _data_files(folder):
            assert any(path.match(p) for p in patterns), f"{path} not in package-data"


def _installed_record() -> set[str] | None:
    """Files listed in the RECORD next to the imported package; None for editable installs.

    Looked up from the imported package's location rather than by distribution name: run
    from the source tree, the name would find the build's stray ``*.egg-info`` first.
    """
    site = Path(epistemica.__file__).resolve().parents[1]
    records = list(site.glob("epistemica-*.dist-info/RECORD"))
    if not records:
        return None
    lines = records[0].read_text().splitlines()
    return {line.split(",")[0].replace("\\", "/") for line in lines}


def test_installed_files_cover_the_sources():
    """On a regular (non-editable) install, the RECORD lists every module and grammar."""
    files = _installed_record()
    if files is None or not any(f.startswith("epistemica/del_/") for f in files):
        pytest.skip("editable install: the modules are not copied, nothing to compare")
    for dotted, folder in _source_packages().items():
        prefix = dotted.replace(".", "/")
        for path in [*folder.glob("*.py"), *_data_files(folder)]:
            name = path.relative_to(folder).as_posix()
            assert f"{prefix}/{name}" in files, f"{prefix}/{name} not installed"


def test_every_module_imports():
    names = all_modules()
    assert set(LAYERS) <= set(names)
    for name in names:
        importlib.import_module(name)
