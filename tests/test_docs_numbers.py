"""The version numbers docs/formats.md quotes are the ones the code writes: the table of
formats, the section headings and the trace's ``version`` field, read from the page and
compared with the modules' constants (a raised version that the page misses fails here)."""

from __future__ import annotations

import re
from pathlib import Path

from epistemica.cli.json_output import VERSIONS
from epistemica.sim.study import store, trace

PAGE = (Path(__file__).resolve().parents[1] / "docs" / "formats.md").read_text(encoding="utf-8")


def _table() -> dict[str, str]:
    """Format tag -> the version column of the page's first table."""
    rows = re.findall(r"^\| [^|]+ \| `(epistemica-[\w-]+)` \| ([^|]+) \|", PAGE, re.M)
    return {tag: version.strip() for tag, version in rows}


def test_the_table_quotes_every_json_documents_version():
    table = _table()
    for kind, version in VERSIONS.items():
        assert table[f"epistemica-{kind}"] == str(version), kind
    assert len(table) >= len(VERSIONS) + 2


def test_the_results_files_schema_and_the_traces_version_are_the_codes():
    table = _table()
    assert table["epistemica-results"] == str(store.SCHEMA_VERSION)
    older = [str(v) for v in trace.READABLE if v != trace.VERSION]
    assert table["epistemica-trace"] == f"{trace.VERSION} ({', '.join(older)} read too)"
    assert f"(`epistemica-results`, schema {store.SCHEMA_VERSION})" in PAGE
    assert f"(`epistemica-trace`, version {trace.VERSION})" in PAGE
    assert f'`"epistemica-trace"`, `{trace.VERSION}`' in PAGE
    assert f"`version` = `{store.SCHEMA_VERSION}`" in PAGE
