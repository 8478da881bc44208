"""Test helper: a report.html parsed into what a reader sees (ids, sections, cells, figures).

Shared by test/test_report_reader.py and test/test_report_browser.py.
"""
import base64
import shutil
import struct
from html.parser import HTMLParser
from pathlib import Path

import pytest
from hostile import run_motoflex

__all__ = ["ReportPage", "parse_report", "png_size", "example_report", "EXAMPLE"]

EXAMPLE = Path(__file__).resolve().parents[1] / "bags" / "example"


class ReportPage(HTMLParser):
    """ids (every id attribute, in order), cells (attrs + text of every td), figures {id: PNG
    bytes}, captions {id: text}, sections {id: text}, notes {id: text}, tables {id: rows of
    (attrs, text) cells}, css (the style element's text)."""

    def __init__(self):
        super().__init__()
        self.ids, self.cells, self.figures, self.captions = [], [], {}, {}
        self.sections, self.notes, self.tables, self.css = {}, {}, {}, ""
        self._stack, self._section = [], None
        self._figure = self._table = self._note = None
        self._cell = None

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if "id" in attrs:
            self.ids.append(attrs["id"])
        self._stack.append(tag)
        if tag == "section":
            self._section = attrs["id"]
            self.sections[self._section] = ""
        elif tag == "figure":
            self._figure = attrs["id"]
        elif tag == "img" and self._figure:
            self.figures[self._figure] = base64.b64decode(attrs["src"].split(",", 1)[1])
        elif tag == "table":
            self._table = attrs["id"]
            self.tables[self._table] = []
        elif tag == "tr" and self._table:
            self.tables[self._table].append([])
        elif tag == "td":
            self._cell = [attrs, ""]
        elif tag == "p" and "id" in attrs:
            self._note = attrs["id"]
            self.notes[self._note] = ""

    def handle_endtag(self, tag):
        if self._stack:
            self._stack.pop()
        if tag == "td" and self._cell is not None:
            self.cells.append(tuple(self._cell))
            if self._table and self.tables[self._table]:
                self.tables[self._table][-1].append(tuple(self._cell))
            self._cell = None
        elif tag == "table":
            self._table = None
        elif tag == "figure":
            self._figure = None
        elif tag == "p":
            self._note = None
        elif tag == "section":
            self._section = None

    def handle_data(self, data):
        top = self._stack[-1] if self._stack else None
        if top == "style":
            self.css += data
        if self._section:
            self.sections[self._section] += data
        if self._cell is not None:
            self._cell[1] += data
        if self._note:
            self.notes[self._note] += data
        if top == "figcaption" and self._figure:
            self.captions[self._figure] = self.captions.get(self._figure, "") + data


def parse_report(path):
    """The :class:`ReportPage` of the report.html at ``path``."""
    page = ReportPage()
    page.feed(path.read_text(encoding="utf-8"))
    return page


def png_size(png):
    """(width, height) [px] of PNG bytes, from the IHDR chunk."""
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", png[16:24])


def example_report(parent, prepare=None):
    """A copy of bags/example in ``parent`` (nothing in bags/ is written), ``prepare(folder)``
    applied to it, and its report built with ``motoflex report --no-compute``; the folder."""
    if not (EXAMPLE / "status.json").is_file():
        pytest.skip("bags/example is not in this checkout")
    folder = Path(parent) / "example"
    shutil.copytree(EXAMPLE, folder, ignore=shutil.ignore_patterns("report.html", "*.rrd"))
    if prepare is not None:
        prepare(folder)
    result = run_motoflex(["report", folder, "--no-compute", "--quiet"])
    assert result.returncode == 0, result.stderr
    return folder
