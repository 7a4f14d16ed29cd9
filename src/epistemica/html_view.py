"""Self-contained HTML pages: a trial's replay and a Kripke model with a formula box.

Each page is one file with its script, style and data inline (the data as JSON in a
``<script type="application/json">`` element): it opens offline, from disk, with no server
and no network. The assets are in ``src/epistemica/pages/`` (``page.html``, ``view.css``,
``trial_parts.js``, ``trial_panels.js``, ``trial_view.js``, ``model_view.js``), shipped as
package data. This module imports no
simulator code, so that ``show --html`` starts as fast as ``show``.

- :func:`epistemica.view.trial_page`: a trace (:mod:`epistemica.sim.study.trace`) replayed with
  the panels of its mission kind, as the animation draws them
  (:mod:`epistemica.sim.study.figures`); a slider scrubs, a button plays and pauses.
- :func:`model_page`: a model as ``epistemica show --json`` writes it (worlds, relations per
  agent, designated worlds), the spec's claims with their truth sets computed by
  epistemica, and a box that evaluates static formulas (propositional, ``K``, ``B``,
  ``Kw``, ``M``, ``E``, ``C``, ``D``, ``EB``, ``CB``) in the page.

Examples
--------
>>> html = model_page({"format": "epistemica-kripke-1", "agents": ["a"], "atoms": ["p"],
...                    "worlds": [{"name": "w0", "atoms": ["p"]}], "designated": ["w0"],
...                    "relations": {"a": {"belief": {"blocks": [["w0"]]}}}}, "one world")
>>> html.startswith("<!DOCTYPE html>"), "<link" in html or " src=" in html
(True, False)
"""

from __future__ import annotations

import json
import math
import os
from importlib import resources
from pathlib import Path
from typing import Any

from epistemica.del_.errors import InvalidArgumentError
from epistemica.output_files import write_output

__all__ = ["check_writable", "model_page", "page", "write_page"]


def _asset(name: str) -> str:
    return (resources.files("epistemica") / "pages" / name).read_text(encoding="utf-8")


def _json(data: Any) -> str:
    """``data`` as JSON that is safe inside a ``<script>`` element and parses in a browser.

    Non-finite numbers become ``null`` (JSON has no NaN or Infinity), by value, so a
    string holding "NaN" is left alone. Every ``<``, ``>`` and ``&`` is written as its
    ``\\u`` escape, the same JSON string: the HTML parser then never sees ``</script>``
    nor ``<!--<script>`` (which would swallow the rest of the page) in the data.
    """
    text = json.dumps(_finite(data), separators=(",", ":"), allow_nan=False)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def _finite(value: Any) -> Any:
    """``value`` with every non-finite float (NaN, ±Infinity) replaced by None."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {key: _finite(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(item) for item in value]
    return value


def page(title: str, script: str | tuple[str, ...], data: dict[str, Any]) -> str:
    """The page titled ``title`` running the asset ``script`` (several: in that order, in
    one script element) over ``data`` (embedded JSON)."""
    escaped = title.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    names = (script,) if isinstance(script, str) else script
    code = "\n".join(_asset(name) for name in names)
    parts = {"title": escaped, "style": _asset("view.css"), "script": code}
    parts["data"] = _json(data)
    # Split on the markers once, so that no inserted text is searched for markers again.
    pieces = _asset("page.html").split("@@")
    return "".join(parts[p] if i % 2 else p for i, p in enumerate(pieces))


def model_page(
    model: dict[str, Any],
    title: str,
    claims: list[dict[str, Any]] = (),
    example: str = "",
) -> str:
    """The page of a model object (``epistemica-kripke-1``, from
    :func:`epistemica.model_json.model_to_json`) as HTML text.

    ``claims``: ``{"name", "formula", "expected", "holds", "worlds"}`` each, the truth sets
    as epistemica computed them; ``example``: a formula put in the box and evaluated when
    the page opens.
    """
    if not isinstance(model, dict) or not str(model.get("format", "")).startswith(
        "epistemica-kripke"
    ):
        raise InvalidArgumentError("not a model object", hint="write one with 'show --json'")
    data = {
        "model": model,
        "claims": list(claims),
        "example": example,
    }
    return page(title, "model_view.js", data)


def write_page(path, text: str) -> None:
    """Write a page's text to ``path`` (through a temporary file renamed over it, see
    :mod:`epistemica.output_files`); a clear error (not a traceback) when its folder is not
    writable."""
    write_output(path, text)


def check_writable(path) -> None:
    """Fail now, before any work, if a page could not be written at ``path``."""
    folder = Path(path).resolve().parent
    if not folder.is_dir() or not os.access(folder, os.W_OK):
        raise InvalidArgumentError(
            f"cannot write {path}: no writable folder {folder}",
            hint="choose a path in an existing folder",
        )
