"""Scenario options shared by ``simulate`` and ``sweep``: declared once, read once."""

from __future__ import annotations

import argparse

__all__ = ["add_scenario_options", "scenario_options"]

# (flag, Scenario field, type, help)
_OPTIONS = (
    ("--observation", "observation", str, "paper (default) or honest"),
    ("--sensing-range", "sensing_range", float, "metres (default: unlimited)"),
    ("--position-noise", "position_noise", float, "observation noise variance, m² (default 0.5)"),
    ("--max-steps", "max_steps", int, "step limit (default: the protocol's)"),
)


def add_scenario_options(parser: argparse.ArgumentParser) -> None:
    """Add the flags that set :class:`epistemica.sim.Scenario` fields."""
    for flag, field, kind, text in _OPTIONS:
        parser.add_argument(flag, dest=field, type=kind, default=None, help=text)


def scenario_options(args: argparse.Namespace) -> dict:
    """The Scenario fields the user set, by name.

    Examples
    --------
    >>> scenario_options(argparse.Namespace(observation="honest", sensing_range=None,
    ...                                     position_noise=None, max_steps=20))
    {'observation': 'honest', 'max_steps': 20}
    """
    chosen = {field: getattr(args, field, None) for _, field, _, _ in _OPTIONS}
    return {k: v for k, v in chosen.items() if v is not None}
