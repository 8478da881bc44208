"""Self-contained HTML of a report: inline CSS, figures as base64 PNG, number cells traceable.

Every number cell carries ``data-kind`` (json, paper, diff, absdiff), ``data-value`` (the full
float) and, for JSON values, ``data-json`` (file) and ``data-path`` (keys joined by '/'); a
cell showing its value in another unit than the JSON's says which (``data-shown-unit``, beta in
deg of rad), a flagged deviation has ``class="flag"``. Provenance cells have kind
``provenance`` (or ``missing``: not recorded), the field as path and the file as source.
Sections have the id ``section-<name>``, so no id is used twice. The page is
:data:`CONTENT_WIDTH_PX` wide: figures are made at most that wide, so none is shown shrunk.
"""
import base64
import html
from dataclasses import dataclass

__all__ = ["Figure", "Missing", "Section", "Note", "render", "CONTENT_WIDTH_PX", "section_id"]

CONTENT_WIDTH_PX = 1100
CSS = f"""
body {{ font-family: sans-serif; max-width: {CONTENT_WIDTH_PX}px; margin: 2em auto; color: #222; }}
table {{ border-collapse: collapse; margin: 0.5em 0 1.5em; font-size: 0.9em; }}
th, td {{ border: 1px solid #ccc; padding: 3px 8px; text-align: right; }}
th:first-child, td:first-child {{ text-align: left; }} td {{ white-space: nowrap; }}
td[data-kind=paper] {{ color: #555; }} td[data-kind=diff] {{ font-style: italic; }}
td.flag {{ background: #fdd; color: #a00; font-weight: bold; }}
td[data-kind=missing] {{ color: #a33; }} #provenance td {{ text-align: left; }}
.na {{ color: #a33; }} figure {{ margin: 1em 0; }} img {{ max-width: 100%; }}
.sources {{ font-size: 0.85em; color: #555; }} .note {{ font-size: 0.9em; }}
.warning {{ border: 2px solid #a33; background: #fee; padding: 0.5em 1em; font-weight: bold; }}
#section-summary {{ border: 1px solid #bbb; background: #f7f9fc; padding: 0 1em; }}
#summary-verdict {{ font-weight: bold; font-size: 1em; }}
nav {{ margin: 1em 0; font-size: 0.9em; line-height: 1.6; }}
#sources td {{ text-align: left; }}
"""


@dataclass(frozen=True)
class Figure:
    """A figure: id (fig5_frame, ...), caption and PNG bytes."""

    id: str
    caption: str
    png: bytes


@dataclass(frozen=True)
class Missing:
    """A part whose data does not exist (yet): what, and why."""

    what: str
    reason: str


@dataclass(frozen=True)
class Note:
    """A paragraph of text; ``id`` (optional) lets a test find it."""

    text: str
    id: str = None


@dataclass(frozen=True)
class Section:
    """A report section: id, title and parts (Table, Figure, Missing)."""

    id: str
    title: str
    parts: tuple


def _cell(cell, tag="td"):
    attrs = ""
    if cell.value is not None:
        attrs += f' data-value="{cell.value!r}"'
    if cell.kind:
        attrs += f' data-kind="{cell.kind}"'
    if cell.file:
        attrs += f' data-json="{html.escape(cell.file)}"'
    if cell.path:
        attrs += f' data-path="{html.escape(cell.path)}"'
    if cell.shown_unit:
        attrs += f' data-shown-unit="{cell.shown_unit}"'
    if cell.flagged:
        attrs += ' class="flag"'
    return f"<{tag}{attrs}>{html.escape(cell.text)}</{tag}>"


def _table(table):
    head = "".join(f"<th>{html.escape(h)}</th>" for h in table.header)
    body = "".join("<tr>" + "".join(_cell(c) for c in row) + "</tr>" for row in table.rows)
    note = f"<p>{html.escape(table.note)}</p>" if table.note else ""
    return (f'<h3>{html.escape(table.title)}</h3><table id="{table.id}"><thead><tr>{head}'
            f"</tr></thead><tbody>{body}</tbody></table>{note}")


def _figure(figure):
    data = base64.b64encode(figure.png).decode("ascii")
    return (f'<figure id="{figure.id}"><img alt="{html.escape(figure.caption)}" '
            f'src="data:image/png;base64,{data}"><figcaption>{html.escape(figure.caption)}'
            "</figcaption></figure>")


def _part(part):
    if isinstance(part, Figure):
        return _figure(part)
    if isinstance(part, Note):
        ident = f' id="{part.id}"' if part.id else ""
        return f'<p class="note"{ident}>{html.escape(part.text)}</p>'
    if isinstance(part, Missing):
        return (f'<p class="na" data-missing="{html.escape(part.what)}">{html.escape(part.what)}'
                f": not available ({html.escape(part.reason)})</p>")
    return _table(part)


def section_id(name):
    """The HTML id of section ``name`` (tables and figures use the bare names)."""
    return f"section-{name}"


def _contents(sections):
    """A one-line table of contents: links to every section after the first."""
    links = " \u00b7 ".join(f'<a href="#{section_id(s.id)}">{html.escape(s.title)}</a>'
                            for s in sections[1:])
    return f'<nav id="contents"><b>Contents:</b> {links}</nav>' if links else ""


def render(title, sections, warning=None):
    """The whole HTML document: ``warning`` (e.g. an incomplete run) right under the title,
    then the first section (the summary), a table of contents and the other sections."""
    def one(s):
        return (f'<section id="{section_id(s.id)}"><h2>{html.escape(s.title)}</h2>'
                + "".join(_part(p) for p in s.parts) + "</section>")
    notice = (f'<p class="warning" id="warning">{html.escape(warning)}</p>' if warning else "")
    body = "".join(one(s) for s in sections[:1]) + _contents(sections) + "".join(
        one(s) for s in sections[1:])
    return (f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>'
            f"{html.escape(title)}</title><style>{CSS}</style></head><body><h1>"
            f'{html.escape(title)}</h1>{notice}{body}'
            "</body></html>\n")
