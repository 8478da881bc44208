"""Every expected failure of the suite is a known deviation (test/deviations.py): strict, raises
AssertionError, a one-line reason linking to a section of docs/known-deviations.md that exists.

Read from the test files' syntax trees, so every mark is seen, parametrized or not, and whatever
part of the suite a run selects: the only ``xfail`` call under test/ is known_deviation's, no
test calls ``pytest.xfail`` (not strict), and each known_deviation call names an anchor of the
page and a one-line summary as literals.
"""
import ast
import re
from pathlib import Path

import pytest
from deviations import PAGE, known_deviation

HERE = Path(__file__).parent
ROOT = HERE.parent


def _calls(name, folder=HERE):
    """(file, line, call) of every call in ``folder`` of a function or attribute ``name``."""
    found = []
    for path in sorted(folder.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and name in (getattr(node.func, "attr", None),
                                                       getattr(node.func, "id", None)):
                found.append((path.name, node.lineno, node))
    return found


def _anchors():
    return set(re.findall(r"\{#([a-z0-9-]+)\}", (ROOT / PAGE).read_text(encoding="utf-8")))


def test_every_xfail_is_a_known_deviation():
    assert [f for f, _, _ in _calls("xfail")] == ["deviations.py"]
    mark = known_deviation("an-anchor", "a summary").mark
    assert mark.kwargs == {"strict": True, "raises": AssertionError,
                           "reason": f"a summary ({PAGE}#an-anchor)"}


def test_each_known_deviation_links_to_its_section():
    calls = [c for c in _calls("known_deviation") if c[0] != Path(__file__).name]
    assert len(calls) >= 16, calls
    anchors = _anchors()
    for file, line, call in calls:
        anchor, summary = (getattr(arg, "value", None) for arg in call.args)
        assert anchor in anchors, f"{file}:{line}: no section {{#{anchor}}} in {PAGE}"
        assert isinstance(summary, str) and "\n" not in summary and len(summary) <= 90, \
            f"{file}:{line}: the summary is one short line; the numbers go to {PAGE}"


def test_page_is_in_the_site_nav():
    assert "known-deviations.md" in (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    assert {"cb-truncation", "low-speed-wobble-sign"} <= _anchors()


@pytest.mark.parametrize("text", ['pytest.mark.xfail(reason="x")\n', 'pytest.xfail("x")\n'])
def test_the_scan_sees_a_plain_xfail(tmp_path, text):
    """The scan is not blind: a plain xfail in a test file is found."""
    (tmp_path / "test_x.py").write_text(text)
    assert [(f, line) for f, line, _ in _calls("xfail", tmp_path)] == [("test_x.py", 1)]
