"""What a user reads is self-contained: the README, the documentation pages, the examples' comments,
every ``--help`` text and the sources' and tests' docstrings name no internal contract document,
issue number or path outside the repository; the README stays a front page (about 150 lines,
none over 110 characters)."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: a contract document, an issue number, a path outside the repository, a work log
FORBIDDEN = re.compile(r"\bSPEC\b|\.\./shared|/shared/|/work/|\b[Ii]ssues? [0-9]|\bhelper-[0-9]|work log")
USER_TEXT = (
    [ROOT / "README.md", ROOT / "CHANGELOG.md"]
    + sorted((ROOT / "docs").rglob("*.md"))
    + sorted((ROOT / "examples").rglob("*.md"))
    + sorted((ROOT / "examples").rglob("*.toml"))
    + sorted((ROOT / "examples").rglob("*.py"))
    # docstrings and help texts of the benchmarks and the packages
    + sorted((ROOT / "benchmarks").glob("*.py"))
    + sorted((ROOT / "benchmarks" / "scenes").glob("*.toml"))
    + [p for folder in ("geometry", "importers", "solver", "ibfem") for p in sorted((ROOT / folder).rglob("*.py"))]
    # the tests' docstrings and comments, and their scenes (this file names the patterns themselves)
    + [p for p in sorted((ROOT / "tests").rglob("*.py")) if p.name != "test_docs_text.py"]
    + sorted((ROOT / "tests").rglob("*.toml"))
)


@pytest.mark.parametrize("path", USER_TEXT, ids=lambda p: str(p.relative_to(ROOT)))
def test_user_text_is_self_contained(path):
    hits = [f"{k}: {line.strip()}" for k, line in enumerate(path.read_text().splitlines(), 1)
            if FORBIDDEN.search(line)]
    assert not hits, f"{path.relative_to(ROOT)}:\n" + "\n".join(hits)


def _help_texts() -> dict[str, str]:
    from ibfem.solver import cli

    parser = cli.build_parser()
    texts = {"ibfem": parser.format_help()}
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    for name, command in sub.choices.items():
        texts[f"ibfem {name}"] = command.format_help()
    return texts


def test_help_texts_are_self_contained():
    texts = _help_texts()
    assert {"ibfem run", "ibfem sweep", "ibfem import", "ibfem verify", "ibfem info"} <= set(texts)
    hits = {name: FORBIDDEN.findall(text) + re.findall(r"thesis \d+\.\d+", text) for name, text in texts.items()}
    assert not any(hits.values()), hits


def test_readme_is_a_front_page():
    lines = (ROOT / "README.md").read_text().splitlines()
    assert len(lines) <= 160, f"README.md has {len(lines)} lines"
    long = [k for k, line in enumerate(lines, 1) if len(line) > 110]
    assert not long, f"README.md lines over 110 characters: {long}"
    assert "make test" in (ROOT / "README.md").read_text()  # the test command CI runs


def test_version_is_the_installed_distribution_s():
    from importlib.metadata import version

    import ibfem
    from ibfem.solver import cli

    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
        cli.main(["--version"])
    assert out.getvalue().strip() == f"ibfem {version('ibfem')}" == f"ibfem {ibfem.__version__}"
