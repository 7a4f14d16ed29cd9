"""Run the examples in every docstring of the installed package."""

from __future__ import annotations

import doctest
import importlib

import pytest

from _modules import all_modules


@pytest.mark.parametrize("name", all_modules())
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0
