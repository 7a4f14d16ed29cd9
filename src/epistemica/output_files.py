"""Writing a command's output file: never over an input, never over a file unasked.

The rules every command that writes a file follows (``view -o``, ``show --html``/``--dot``,
``report --png``/``--pdf``/``--svg``, ``export -o``, ``simulate --png``/``--gif``):

- an output that is one of the command's own inputs (the same file, by any path or link)
  is refused, with or without ``--force``;
- an existing output is refused unless ``--force`` is given;
- a symbolic link at the output path is never written through: a dangling one is refused,
  and with ``--force`` a link is replaced by the new file (its target is left alone);
- a missing folder is named plainly (``export``'s output folder is created instead);
- the file is written to a temporary file in the target folder and renamed over the
  target, so that an interrupted or failed write leaves the old file (or none), never half
  of one. A device or a pipe (``/dev/stdout``, ``/dev/null``) is written to directly, as
  no file of the user's is replaced there.

:func:`check_output` runs before any work (a study may take minutes);
:func:`write_output` writes.
"""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Callable, Iterable
from pathlib import Path

from epistemica.del_.errors import InvalidArgumentError

__all__ = ["check_output", "write_output"]


def check_output(
    path: str | Path,
    inputs: Iterable[str | Path | None] = (),
    force: bool = False,
    flag: str = "",
    create_folder: bool = False,
) -> Path:
    """The output path ``path``, checked against the rules above before any work.

    ``inputs``: the files the command reads (``None`` entries are skipped); ``flag``: the
    option naming the output, for the message; ``create_folder``: create a missing folder
    rather than refuse.

    Raises
    ------
    InvalidArgumentError
        The output is an input, exists (without ``force``), is a dangling link or a
        folder, or its folder cannot be created or written.
    """
    out = Path(path)
    named = f"{flag} {out}".strip()
    for source in inputs:
        if source is not None and _same_file(out, Path(source)):
            raise InvalidArgumentError(
                f"{named}: that is the command's input {source}; it would be overwritten",
                hint="choose another output file",
            )
    if out.is_symlink() and not out.exists():
        raise InvalidArgumentError(
            f"{named}: a dangling symbolic link (to {os.readlink(out)}); nothing is written "
            "through it",
            hint="remove the link or choose another output file",
        )
    if out.is_dir():
        raise InvalidArgumentError(f"{named}: is a folder", hint="name a file in it")
    if _device(out):
        return out
    if (out.exists() or out.is_symlink()) and not force:
        raise InvalidArgumentError(
            f"{named}: the file exists", hint="add --force to replace it, or choose another name"
        )
    folder = out.parent
    if not folder.is_dir() and not create_folder:
        raise InvalidArgumentError(
            f"{named}: the folder {folder} does not exist (No such file or directory)",
            hint=f"create it first (mkdir -p {folder}) or choose another folder",
        )
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InvalidArgumentError(
            f"{named}: cannot create the folder {folder}: {exc.strerror or exc}",
            hint="choose a path in a writable folder",
        ) from None
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InvalidArgumentError(
            f"{named}: the folder {folder} is not writable", hint="choose another folder"
        )
    return out


def _device(out: Path) -> bool:
    """Whether ``out`` exists and is neither a regular file nor a folder (a device, a pipe)."""
    try:
        mode = out.stat().st_mode
    except OSError:
        return False
    return not stat.S_ISREG(mode) and not stat.S_ISDIR(mode)


def _same_file(out: Path, source: Path) -> bool:
    try:
        if out.exists() and source.exists():
            return os.path.samefile(out, source)
        return out.resolve() == source.resolve()
    except OSError:
        return False


def write_output(path: str | Path, content: str | bytes | Callable[[Path], object]) -> None:
    """Write ``content`` to ``path`` through a temporary file in its folder, then rename.

    ``content``: text (written as UTF-8), bytes, or a function that writes to the path it
    is given (a figure's ``savefig``); that path ends with ``path``'s own suffix, so a
    writer that picks its format from the name picks the same one.

    Raises
    ------
    InvalidArgumentError
        The folder is not writable or the disk is full (the target is left as it was).
    """
    out = Path(path)
    if _device(out):
        _write_directly(out, content)
        return
    try:
        handle, name = tempfile.mkstemp(prefix=f".{out.name}.", suffix=out.suffix, dir=out.parent)
    except OSError as exc:
        raise _unwritable(out, exc) from None
    temporary = Path(name)
    try:
        with os.fdopen(handle, "wb") as stream:
            if isinstance(content, str):
                stream.write(content.encode("utf-8"))
            elif isinstance(content, bytes):
                stream.write(content)
        if callable(content):
            content(temporary)
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp's 0600 is for the temporary only
        os.replace(temporary, out)  # replaces a link itself, never its target
    except OSError as exc:
        temporary.unlink(missing_ok=True)
        raise _unwritable(out, exc) from None
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def _write_directly(out: Path, content) -> None:
    try:
        if callable(content):
            content(out)
        else:
            with open(out, "wb") as stream:
                stream.write(content.encode("utf-8") if isinstance(content, str) else content)
    except OSError as exc:
        raise _unwritable(out, exc) from None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _unwritable(out: Path, exc: OSError) -> InvalidArgumentError:
    return InvalidArgumentError(
        f"cannot write {out}: {exc.strerror or exc}",
        hint="check the folder is writable and the disk has room",
    )
