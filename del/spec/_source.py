"""Reading a source file (spec or mission) from a path: bounded, once, as UTF-8 text.

The file is read once, so that a pipe (``epistemica check <(cat FILE)``) works, and never
past :data:`MAX_SOURCE_BYTES`. Binary input is refused from its first block (a NUL byte,
or bytes that are not UTF-8), so ``/dev/zero`` and ``/dev/urandom`` are refused at once;
a UTF-8 byte-order mark is dropped; an encoding error names the line, the column and the
byte.
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

from epistemica.del_.errors import SpecError

__all__ = [
    "MAX_CLAIMS",
    "MAX_SOURCE_BYTES",
    "MAX_TOKENS",
    "check_claim_count",
    "check_token_count",
    "decode_source",
    "read_source",
]

#: Larger files are refused (the largest shipped spec is 1.1 MB); within it,
#: :data:`MAX_TOKENS` bounds what a file costs.
MAX_SOURCE_BYTES = 64 << 20
#: More claims in one file are refused before parsing: each costs about 10 kB while the
#: file is compiled (50,000 claims of one line each peaked at 519 MB), so the limit keeps
#: a file's memory bounded (the shipped specs hold at most 12).
MAX_CLAIMS = 10_000
#: More tokens (names, numbers, symbols and line ends) in one text are refused before
#: parsing: reading and compiling cost up to about 0.9 kB a token (a spec of 200,000
#: ``observes`` lines, a million tokens, peaked at 867 MB), so this bounds the memory of
#: any spec, SMCDEL, EPDDL or policy file under the byte limit near 1 GB (the largest
#: shipped spec, the drinking logicians, holds 332,000).
MAX_TOKENS = 1_000_000
_TOKEN = re.compile(r"\w+|\S|\n")
_CLAIM = re.compile(r"^[ \t]*(check)\b", re.MULTILINE)
_BLOCK = 1 << 16
_BOM = b"\xef\xbb\xbf"


def read_source(path: str | Path, what: str = "spec file", limit: int = MAX_SOURCE_BYTES) -> str:
    """The text of the file at ``path``, read once and at most ``limit`` bytes.

    Raises
    ------
    SpecError
        The file cannot be opened, is larger than ``limit``, is binary, or is not UTF-8;
        the message says which (and where, for an encoding error).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "bom.epi"
    >>> _ = p.write_bytes(b"\\xef\\xbb\\xbfagents a\\n")
    >>> read_source(p)
    'agents a\\n'
    >>> try:
    ...     read_source("/dev/zero")
    ... except SpecError as err:
    ...     print(err.message)
    the spec file is binary, not text (a NUL byte at offset 0)
    """
    name = str(path)
    # The example names no file kind: the same hint serves EPDDL, SMCDEL, traces, ...
    hint = f"give the {what} as UTF-8 text (a text editor's ordinary save)"
    try:
        handle = open(path, "rb")  # closed by the `with` below
    except OSError as exc:
        raise SpecError(
            f"cannot read the {what}: {exc.strerror or exc}",
            filename=name,
            hint="check the path" if isinstance(exc, FileNotFoundError) else hint,
        ) from None
    blocks: list[bytes] = []
    size = 0
    try:
        with handle:
            while True:
                block = handle.read(_BLOCK)
                if not block:
                    break
                if not blocks:
                    _refuse_binary(block, name, what, hint)
                blocks.append(block)
                size += len(block)
                if size > limit:
                    raise SpecError(
                        f"the {what} is larger than the limit of {limit:,} bytes",
                        filename=name,
                        hint="split it, or generate a smaller one",
                    )
    except IsADirectoryError:
        raise SpecError(f"cannot read the {what}: it is a directory", filename=name) from None
    except OSError as exc:
        raise SpecError(f"cannot read the {what}: {exc.strerror or exc}", filename=name) from None
    return decode_source(b"".join(blocks), name, what)


def decode_source(data: bytes, filename: str = "<string>", what: str = "spec file") -> str:
    """``data`` as UTF-8 text without a byte-order mark; an error names line and column."""
    if data.startswith(_BOM):
        data = data[len(_BOM) :]
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        before = data[: exc.start]
        line = before.count(b"\n") + 1
        start = before.rfind(b"\n") + 1
        column = len(before[start:].decode("utf-8", errors="replace")) + 1
        text = data.decode("utf-8", errors="replace")
        raise SpecError(
            f"the {what} is not UTF-8 text: byte 0x{data[exc.start]:02x} cannot start or "
            "continue a character",
            line=line,
            column=column,
            source=text,
            filename=filename,
            hint="save the file as UTF-8 (most editors: 'Save with encoding')",
        ) from None


def _refuse_binary(block: bytes, name: str, what: str, hint: str) -> None:
    zero = block.find(b"\x00")
    if zero >= 0:
        raise SpecError(
            f"the {what} is binary, not text (a NUL byte at offset {zero})",
            filename=name,
            hint=hint,
        )
    # Most bytes of random data are not UTF-8 text: refuse before reading any further.
    try:
        block.decode("utf-8")
    except UnicodeDecodeError as exc:
        if exc.start < len(block) - 3:  # not merely a character cut at the block's end
            decode_source(block, name, what)


def check_claim_count(
    text: str, filename: str = "<string>", limit: int = MAX_CLAIMS, claim: re.Pattern = _CLAIM
) -> None:
    """Refuse a text with more than ``limit`` claims, at the first one too many; a claim
    is a match of ``claim`` (its group 1 is where it starts): a spec's ``check`` at the
    start of a line by default, SMCDEL's ``TRUE?``, ``VALID?`` and ``WHERE?`` jobs too.

    Examples
    --------
    >>> text = "agents a\\natoms p\\n" + 'check "p": p\\n' * 3
    >>> check_claim_count(text, limit=3)
    >>> try:
    ...     check_claim_count(text, "many.epi", limit=2)
    ... except SpecError as err:
    ...     print(err.line, err.column, err.message)
    5 1 more than 2 claims in one file
    """
    found = next(itertools.islice(claim.finditer(text), limit, None), None)
    if found is None:
        return
    start = found.start(1)
    raise SpecError(
        f"more than {limit} claims in one file",
        line=text.count("\n", 0, start) + 1,
        column=start - text.rfind("\n", 0, start),
        source=text,
        filename=filename,
        hint=f"split the claims over several files of at most {limit} each",
    )


def check_token_count(
    text: str, filename: str = "<string>", what: str = "spec file", limit: int | None = None
) -> None:
    """Refuse a text of more than ``limit`` tokens (default :data:`MAX_TOKENS`), at the
    first one too many.

    A token is a word (``\\w+``), any other visible character, or a line end: at least
    what the parsers make a node or a position of. Counting stops at the limit, so a
    hostile file costs no more than a legitimate one of the limit's size.

    Examples
    --------
    >>> check_token_count("agents a\\natoms p\\n", limit=6)  # 6 tokens
    >>> try:
    ...     check_token_count("agents a\\natoms p\\n", "x.epi", limit=5)
    ... except SpecError as err:
    ...     print(err.line, err.column, err.message)
    2 8 more than 5 tokens (words, symbols and line ends) in one spec file
    """
    limit = MAX_TOKENS if limit is None else limit
    found = next(itertools.islice(_TOKEN.finditer(text), limit, None), None)
    if found is None:
        return
    start = found.start()
    line = text.count("\n", 0, start) + 1
    raise SpecError(
        f"more than {limit:,} tokens (words, symbols and line ends) in one {what}",
        line=line,
        column=start - text.rfind("\n", 0, start),
        source=text,
        filename=filename,
        hint="the limit bounds the memory of reading a file (up to about 0.7 kB a token); "
        "split it, or build a larger model through the Python API",
    )
