"""The documentation: the site builds with warnings as errors, every internal link resolves,
every example of the getting-started page runs (the ROS ones in ``test_docs_ros.py``).

The strict build is mkdocs' own check (``validation`` in mkdocs.yml: missing pages and anchors
are warnings, and ``--strict`` makes them errors); the link test below resolves the links
itself, README.md included (GitHub renders it; mkdocs does not see it), against the files and
the ids of the built pages.
"""
import re
import shutil

import pytest
from doc_pages import (
    DOCS,
    GETTING_STARTED,
    ROOT,
    SHOWN_LANGUAGE,
    build_site,
    example_folder,
    examples,
    fenced_blocks,
    html_ids,
    internal_links,
    markdown_headings,
    run_example,
)

pytest.importorskip("mkdocs", reason="mkdocs is in the test extra of setup.py")
PAGES = sorted(DOCS.glob("*.md"))
LINKED = [*PAGES, ROOT / "README.md"]


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site built with --strict into a temporary folder."""
    site_dir = tmp_path_factory.mktemp("site")
    built = build_site(ROOT / "mkdocs.yml", site_dir)
    assert built.returncode == 0, built.stdout + built.stderr
    return site_dir


def test_site_builds_strict_with_a_page_per_markdown_file(site):
    for page in PAGES:
        assert (site / page.with_suffix(".html").name).is_file(), page.name


def test_strict_build_fails_on_a_missing_anchor(tmp_path):
    """The build is a check that can fail: one broken anchor aborts it, naming the link."""
    shutil.copytree(DOCS, tmp_path / "docs")
    shutil.copy(ROOT / "mkdocs.yml", tmp_path / "mkdocs.yml")
    page = tmp_path / "docs" / "index.md"
    page.write_text(page.read_text() + "\n[broken](references.md#no-such-entry)\n")
    built = build_site(tmp_path / "mkdocs.yml", tmp_path / "site")
    assert built.returncode != 0
    assert "no-such-entry" in built.stdout + built.stderr


def _resolve(source, target, site):
    """None if ``target`` (a relative link in ``source``) resolves, else the reason."""
    path, _, anchor = target.partition("#")
    file = (source.parent / path).resolve() if path else source
    if not file.exists():
        return f"{file.relative_to(ROOT) if file.is_relative_to(ROOT) else file} does not exist"
    if not anchor:
        return None
    if file.parent == DOCS and file.suffix == ".md":
        ids = html_ids(site / file.with_suffix(".html").name)
    elif file.suffix == ".md":
        ids = markdown_headings(file)
    else:
        return f"an anchor into {file.name}, which is no page"
    return None if anchor in ids else f"{file.name} has no anchor #{anchor}"


@pytest.mark.parametrize("source", LINKED, ids=lambda p: p.name)
def test_internal_links_resolve(source, site):
    broken = [f"{source.name}:{line}: {target}: {reason}"
              for line, target in internal_links(source)
              if (reason := _resolve(source, target, site))]
    assert not broken, "\n".join(broken)


def test_readme_test_command_is_test_sh():
    """.ci/run calls ./test.sh; the README names the same command."""
    assert "./test.sh" in (ROOT / "README.md").read_text()
    assert "./test.sh" in (ROOT / ".ci" / "run").read_text()


def test_getting_started_blocks_follow_the_stated_rule():
    """Every fenced block is either run (bash) or shown with its reason (console), and the page
    says so."""
    text = GETTING_STARTED.read_text()
    assert "block of this page is run by the test suite" in text
    blocks = fenced_blocks(GETTING_STARTED)
    assert {language for language, _, _ in blocks} == {"bash", SHOWN_LANGUAGE}
    for language, block, line in blocks:
        if language == SHOWN_LANGUAGE:
            commands = [c for c in block.splitlines() if c.strip()]
            assert all("#" in c for c in commands), f"line {line}: a shown block says why"
    assert examples() and examples(ros=True)


@pytest.mark.parametrize("example", examples(), ids=lambda e: f"line{e[1]}")
def test_getting_started_example_runs(example, tmp_path):
    text, line = example
    done = run_example(text, example_folder(tmp_path))
    assert done.returncode == 0, f"getting-started.md:{line}\n{text}\n{done.stderr[-2000:]}"


def test_code_cites_docs_references_only():
    """Citations in the code point at docs/references.md entries and docs pages that exist,
    and at no reference or design file outside the repository."""
    references = (DOCS / "references.md").read_text()
    anchors = set(re.findall(r'<a id="([^"]+)"></a>', references))
    sources = [p for folder in ("motoflex_ros", "test", "tools", "benchmarks", "launch")
               for p in (ROOT / folder).rglob("*") if p.suffix in (".py", ".yaml", ".sh")]
    cited, outside, pages = set(), [], set()
    for path in sources:
        text = path.read_text(encoding="utf-8", errors="replace")
        cited |= set(re.findall(r"docs/references\.md#([\w-]+)", text))
        outside += [f"{path.relative_to(ROOT)}: {m}"
                    for m in re.findall(r"(?<![\w/.])(?:reference/[\w-]+|design)\.md", text)]
        pages |= set(re.findall(r"docs/([\w-]+\.md)", text))
    assert cited and not cited - anchors, sorted(cited - anchors)
    assert not outside, outside
    missing = sorted(page for page in pages if not (DOCS / page).is_file())
    assert not missing, f"the code cites docs pages that do not exist: {missing}"
