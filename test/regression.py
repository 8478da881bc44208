"""Numbers the suite pins that our own code produced, with no independent reference (no closed
form, published table or second formulation): regression values. They live in
test/regression_values.json, each with its tolerance, the commit that produced it and the
command or function that gives it; the tests that read them carry the ``regression`` marker,
and tools/regenerate_regression_values.py recomputes them (prints old against new; --write
rewrites the file with the current commit). A change of one of them is a change of behaviour
to explain, not a failure to silence.
"""
import json
from pathlib import Path

import pytest

FILE = Path(__file__).with_name("regression_values.json")


def entries():
    """The entries of test/regression_values.json: key -> {value, rel or abs, commit, source}."""
    return json.loads(FILE.read_text(encoding="utf-8"))


def expected(key):
    """``pytest.approx`` of the regression value ``key`` with its tolerance."""
    entry = entries()[key]
    return pytest.approx(entry["value"], rel=entry.get("rel"), abs=entry.get("abs"))
