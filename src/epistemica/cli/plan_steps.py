"""Plans written on the command line (``--verify A,B,C``, ``--after A B``) as step names.

Kept apart from :mod:`epistemica.cli.coordination` (the planner's commands) so that
``check`` and ``show``, which read plans too, do not import the planner.
"""

from __future__ import annotations

from epistemica.del_.errors import InvalidArgumentError

__all__ = ["split_plan"]


def split_plan(text: str) -> list[str]:
    """The action names of a plan separated by commas or spaces; ``(...)`` is kept whole.

    Examples
    --------
    >>> split_plan("father nobody_knows, open(a, 2)")
    ['father', 'nobody_knows', 'open(a, 2)']

    Raises
    ------
    InvalidArgumentError
        An empty step (``a,,b``) or unbalanced parentheses.
    """
    steps = []
    pieces = _split_outside_parentheses(text, ",")
    for piece in pieces or [""]:
        words = [w for w in _split_outside_parentheses(piece, None) or [""] if w]
        if not words or pieces is None:
            raise InvalidArgumentError(
                f"cannot read the plan {text!r}",
                hint="list action names separated by commas or spaces, e.g. "
                "go_r1_g1,go_r2_g2 or 'go_r1_g1 go_r2_g2'",
            )
        steps.extend(words)
    # Arguments are canonical with one space after each comma, as in `open(a, 2)`.
    return [_canonical(" ".join(s.split()).replace("( ", "(").replace(" )", ")")) for s in steps]


def _split_outside_parentheses(text: str, separator: str | None) -> list[str] | None:
    """``text`` split at ``separator`` (None: whitespace) outside parentheses; None if
    the parentheses do not balance."""
    parts, depth, current = [], 0, []
    for char in text:
        if depth == 0 and (char == separator if separator else char.isspace()):
            parts.append("".join(current))
            current = []
            continue
        depth += {"(": 1, ")": -1}.get(char, 0)
        if depth < 0:
            return None
        current.append(char)
    parts.append("".join(current))
    return parts if depth == 0 else None


def _canonical(name: str) -> str:
    stem, paren, rest = name.partition("(")
    if not paren:
        return name
    args = rest[:-1].split(",") if rest.endswith(")") else [rest]
    return f"{stem.strip()}({', '.join(a.strip() for a in args)})"
