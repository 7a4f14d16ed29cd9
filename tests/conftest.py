"""Shared test configuration: hypothesis profiles that do not flake on a shared machine, and
the headless browser the page tests drive."""

from __future__ import annotations

import os

import pytest
from _browser import CHROMIUM, Browser
from hypothesis import HealthCheck, settings

settings.register_profile(
    "default", deadline=None, suppress_health_check=[HealthCheck.too_slow], print_blob=True
)
settings.register_profile("ci", parent=settings.get_profile("default"), derandomize=True)
settings.load_profile("ci" if os.environ.get("CI") else "default")


@pytest.fixture(scope="module")
def browser():
    """Headless Chromium with one page (tests/_browser.py), one per test module; a test that
    asks for it is skipped without a Chromium executable."""
    if CHROMIUM is None:
        pytest.skip("no Chromium executable on PATH (Debian: apt-get install chromium)")
    b = Browser()
    yield b
    b.close()
