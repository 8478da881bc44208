"""Every module is listed in its package's docstring (issue 25, point 4): a maintainer reads
what a package holds off its ``__init__.py``, and a new module cannot go unmentioned."""
import ast
import re
from pathlib import Path

import pytest

import motoflex_ros

ROOT = Path(motoflex_ros.__file__).parent
PACKAGES = sorted(p.parent for p in ROOT.rglob("__init__.py") if "config" not in p.parts)


def unlisted_modules(package):
    """The modules and subpackages of ``package`` whose names its docstring does not mention."""
    docstring = ast.get_docstring(ast.parse((package / "__init__.py").read_text())) or ""
    names = sorted({p.stem for p in package.glob("*.py") if p.stem != "__init__"}
                   | {p.parent.name for p in package.glob("*/__init__.py")})
    return [n for n in names if not re.search(rf"(?<![\w/]){re.escape(n)}(?![\w/])", docstring)]


def test_unlisted_modules_finds_a_missing_name(tmp_path):
    (tmp_path / "__init__.py").write_text('"""Holds :mod:`.beam` and ``assembly_tools``."""\n')
    for name in ("beam", "assembly", "assembly_tools", "clamped"):
        (tmp_path / f"{name}.py").write_text("")
    assert unlisted_modules(tmp_path) == ["assembly", "clamped"]


@pytest.mark.parametrize("package", PACKAGES, ids=lambda p: p.relative_to(ROOT.parent).as_posix())
def test_every_module_is_listed_in_its_package_docstring(package):
    assert unlisted_modules(package) == []
