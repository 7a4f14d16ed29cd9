"""Which code produced a result: the package version plus the git commit, or a content hash.

:func:`code_version` is stamped on every row of a results file (its ``version`` column), so
that a row can be traced to the code that computed it. From a git work tree it is
``VERSION+gCOMMIT`` (12 hex digits), with ``.dirty.HASH`` when files differ from the commit;
from an installed wheel (no git) it is ``VERSION+sha.HASH``, HASH being the first 12 hex
digits of a SHA-256 over the package's own files (``.py``, ``.lark``, ``.epi``), so two
installs of the same code agree and any edit changes it.

Examples
--------
>>> code_version().startswith(package_version())
True
>>> "+g" in code_version() or "+sha." in code_version()
True
"""

from __future__ import annotations

import functools
import hashlib
import os
import subprocess
from pathlib import Path

__all__ = ["code_version", "package_version", "source_hash"]

_PACKAGES = ("epistemica", "epistemica.del_", "epistemica.aif", "epistemica.sim")
_SUFFIXES = (".py", ".lark", ".epi")


def package_version() -> str:
    """The installed distribution's version (``0+unknown`` in a never-installed tree)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("epistemica")
    except PackageNotFoundError:
        return "0+unknown"


def _package_dirs() -> list[Path]:
    import importlib.util

    dirs = []
    for name in _PACKAGES:
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.submodule_search_locations:
            dirs.extend(Path(p) for p in spec.submodule_search_locations)
    return sorted(set(dirs))


@functools.lru_cache(maxsize=1)
def source_hash() -> str:
    """12 hex digits of SHA-256 over the package's files (paths and contents, sorted)."""
    digest = hashlib.sha256()
    for folder in _package_dirs():
        for path in sorted(folder.rglob("*")):
            if path.suffix in _SUFFIXES and "__pycache__" not in path.parts:
                digest.update(f"{folder.name}/{path.relative_to(folder)}\0".encode())
                digest.update(path.read_bytes())
    return digest.hexdigest()[:12]


def _git(folder: Path, *args: str) -> str | None:
    try:
        done = subprocess.run(
            ["git", "-C", os.fspath(folder), *args],
            capture_output=True,
            text=True,
            timeout=5,
            check=False,
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """``VERSION+gCOMMIT`` (``.dirty.HASH`` if the tree differs), else ``VERSION+sha.HASH``."""
    version = package_version()
    dirs = _package_dirs()
    paths = [os.fspath(d) for d in dirs]
    # a git commit only if git tracks these very files (not a venv inside some other repo)
    tracked = _git(dirs[0], "ls-files", "--", *paths) if dirs else None
    commit = _git(dirs[0], "rev-parse", "--short=12", "HEAD") if tracked else None
    if commit is None:
        return f"{version}+sha.{source_hash()}"
    changed = _git(dirs[0], "status", "--porcelain", "--untracked-files=no", "--", *paths)
    if changed:
        return f"{version}+g{commit}.dirty.{source_hash()}"
    return f"{version}+g{commit}"
