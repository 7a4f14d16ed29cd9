"""The exception family of epistemica.

Every error that epistemica raises on purpose derives from :class:`EpistemicaError`.
The family lives in the lowest layer (``epistemica.del_``) so that every layer above
can raise it without importing upward; the package root re-exports it.

Errors about text a user wrote (a formula, a spec file) carry a location and render as
``FILE:LINE:COL: error: message``, then the offending line with a caret under the
column, then a hint. The command-line interface prints exactly that and exits with 2.
"""

from __future__ import annotations

__all__ = [
    "EpistemicaError",
    "InvalidArgumentError",
    "ModelError",
    "ParseError",
    "SourceError",
    "SpecError",
]


class EpistemicaError(Exception):
    """Base class of every error raised by epistemica.

    Parameters
    ----------
    message : str
        What went wrong, in one sentence.
    hint : str, optional
        What to do about it.
    """

    def __init__(self, message: str, *, hint: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.hint = hint

    def __str__(self) -> str:
        if self.hint:
            return f"{self.message}\nhint: {self.hint}"
        return self.message


class InvalidArgumentError(EpistemicaError, ValueError):
    """An argument passed to a public function is malformed (wrong shape, NaN, unknown name)."""


class ModelError(InvalidArgumentError):
    """A Kripke model or action model is ill-formed (dangling world, unknown agent, ...)."""


class SourceError(EpistemicaError):
    """An error located in text the user wrote.

    Parameters
    ----------
    message : str
        What went wrong.
    line, column : int, optional
        1-based position of the offending character.
    source : str, optional
        The whole text, used to show the offending line with a caret.
    filename : str, optional
        Where the text came from; ``"<formula>"`` or ``"<string>"`` when it did not come
        from a file.
    hint : str, optional
        What to do about it.

    Examples
    --------
    >>> err = SourceError("unknown agent 'r9'", line=1, column=3, source="K[r9] p",
    ...                   filename="<formula>", hint="declared agents: r1, r2")
    >>> print(err)
    <formula>:1:3: error: unknown agent 'r9'
        K[r9] p
          ^
    hint: declared agents: r1, r2
    """

    def __init__(
        self,
        message: str,
        *,
        line: int | None = None,
        column: int | None = None,
        source: str | None = None,
        filename: str | None = None,
        hint: str | None = None,
    ) -> None:
        super().__init__(message, hint=hint)
        self.line = line
        self.column = column
        self.source = source
        self.filename = filename or "<string>"

    def __str__(self) -> str:
        where = self.filename
        if self.line is not None:
            where += f":{self.line}"
            if self.column is not None:
                where += f":{self.column}"
        parts = [f"{where}: error: {self.message}"]
        excerpt = self._excerpt()
        if excerpt:
            parts.append(excerpt)
        if self.hint:
            parts.append(f"hint: {self.hint}")
        return "\n".join(parts)

    def _excerpt(self) -> str:
        if self.source is None or self.line is None:
            return ""
        lines = self.source.splitlines()
        if not 1 <= self.line <= len(lines):
            return ""
        text = lines[self.line - 1].expandtabs(1)
        caret = ""
        if self.column is not None:
            caret = "\n    " + " " * max(self.column - 1, 0) + "^"
        return f"    {text}{caret}"


class ParseError(SourceError):
    """Text does not follow the grammar of formulas or specs."""


class SpecError(SourceError):
    """A spec parses but is not meaningful: unknown agent or atom, impossible constraint."""
