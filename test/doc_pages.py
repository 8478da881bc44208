"""What the documentation tests read from the pages: fenced blocks, links, anchors.

The rule the getting-started page states: a ```` ```bash ```` block is an example the suite runs
(``test_docs.py``; one that starts ROS 2 nodes in ``test_docs_ros.py``, with the other ROS graph
tests); a ```` ```console ```` block is shown, not run, with its reason written beside it.
"""
import html.parser
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
GETTING_STARTED = DOCS / "getting-started.md"
RUN_LANGUAGE, SHOWN_LANGUAGE = "bash", "console"
STARTS_ROS = re.compile(r"\bmotoflex\s+(replay|campaign)\b|\bros2\s+(run|launch)\b")
FENCE = re.compile(r"^(\s*)```(\S*)")
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")
INLINE_CODE = re.compile(r"`[^`]*`")
EXTERNAL = ("http://", "https://", "mailto:")


def fenced_blocks(path):
    """[(language, text, first line number)] of the fenced code blocks of a markdown file."""
    blocks, current = [], None
    for number, line in enumerate(Path(path).read_text(encoding="utf-8").splitlines(), 1):
        match = FENCE.match(line)
        if current is None and match:
            current = (match.group(2), [], number)
        elif current is not None and match and not match.group(2):
            blocks.append((current[0], "\n".join(current[1]), current[2]))
            current = None
        elif current is not None:
            current[1].append(line)
    return blocks


def examples(path=GETTING_STARTED, ros=False):
    """The ``bash`` blocks of ``path`` that start ROS nodes (``ros``) or the others."""
    return [(text, line) for language, text, line in fenced_blocks(path)
            if language == RUN_LANGUAGE and bool(STARTS_ROS.search(text)) == ros]


def internal_links(path):
    """[(line number, target)] of the relative links of a markdown file, outside code."""
    links, fenced = [], False
    for number, line in enumerate(Path(path).read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if fenced:
            continue
        for target in LINK.findall(INLINE_CODE.sub("", line)):
            if not target.startswith(EXTERNAL):
                links.append((number, target))
    return links


class _Ids(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids = set()

    def handle_starttag(self, tag, attrs):
        self.ids |= {value for name, value in attrs if name == "id" and value}


def html_ids(path):
    """Every ``id`` of an HTML file (headings, explicit anchors)."""
    parser = _Ids()
    parser.feed(Path(path).read_text(encoding="utf-8"))
    return parser.ids


def github_slug(heading):
    """The anchor GitHub gives a markdown heading (README.md is read there, not built)."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def markdown_headings(path):
    """Slugs of a markdown file's headings, outside code blocks (GitHub's rule)."""
    slugs, fenced = set(), False
    for line in Path(path).read_text(encoding="utf-8").splitlines():
        if FENCE.match(line):
            fenced = not fenced
        elif not fenced and line.startswith("#"):
            slugs.add(github_slug(line.lstrip("#")))
    return slugs


def build_site(config, site_dir):
    """``mkdocs build --strict`` of ``config`` into ``site_dir``: the finished process."""
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")   # mkdocs-material's banner, not a warning
    return subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--config-file",
                           str(config), "--site-dir", str(site_dir)],
                          capture_output=True, text=True, env=env, timeout=300)


def run_example(text, cwd, env=None, timeout=300):
    """Run one example block with bash (errexit, pipefail) in ``cwd``, the venv's scripts
    first on the PATH: the finished process."""
    scripts = str(Path(sys.executable).parent)
    env = dict(os.environ if env is None else env)
    env["PATH"] = scripts + os.pathsep + env.get("PATH", "")
    return subprocess.run(["bash", "-e", "-o", "pipefail", "-c", text], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)


def section_blocks(path, heading, language):
    """The ``language`` blocks of ``path`` in the section whose heading line is ``heading``."""
    lines = Path(path).read_text(encoding="utf-8").splitlines()
    first = lines.index(heading) + 1   # the heading's line number
    last = next((n for n, line in enumerate(lines[first:], first + 1)
                 if line.startswith(heading.split()[0] + " ")), len(lines))
    return [text for kind, text, line in fenced_blocks(path)
            if kind == language and first < line < last]


def commands(block):
    """The commands of a shell block: continuation lines joined, comments dropped."""
    joined = block.replace("\\\n", " ")
    return [line.split("  #")[0].strip() for line in joined.splitlines()
            if line.strip() and not line.lstrip().startswith("#")]


def example_folder(tmp_path):
    """A working folder for the examples: the repository's bags/ and config/ linked in, so
    what an example writes lands in the temporary folder, not in the repository."""
    for name in ("bags", "config"):
        (tmp_path / name).symlink_to(ROOT / name, target_is_directory=True)
    return tmp_path
