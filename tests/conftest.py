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


@pytest.fixture
def few_frames(monkeypatch):
    """Animations of at most 3 frames (the first, middle and last steps), each drawn and
    written by the real code: for tests of a command that writes a GIF, not of what its
    frames show (those: test_gif_frames_follow_the_trial and
    test_the_animation_has_one_frame_a_step_up_to_sixty, at the full 60)."""
    monkeypatch.setattr("epistemica.sim.study.figure_parts._MAX_FRAMES", 3)
