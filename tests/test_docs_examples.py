"""Every command and code example of the README and the documentation pages runs on the shipped
scenes and does what the text says.

In each document, in order and in one working directory (holding links to ``examples/`` and
``fixtures/``): a ``sh`` block's lines are ``ibfem`` commands, run in this process and required to
exit with 0; a ``python`` block is executed in a separate interpreter, one per document (its
blocks share their names, so a later block reads what an earlier one computed); a block after
``<!-- file: NAME -->`` is written to NAME. A block after ``<!-- slow -->`` runs only in the slow
variant (``make validate``-sized runs); one after ``<!-- not run: REASON -->`` never runs
(installs, network access, a cluster) and must give its reason. Blocks without a language and
``text`` blocks are command synopses (with placeholders such as SCENE.toml) and printed output;
``toml`` blocks without a file marker are fragments.
Where a ``text`` block follows a command, the output it shows must be what the command
prints now: every ``key = number`` pair (half_width, normal_force, semi_axes, ...) to the printed
digits, timings excepted.
"""

from __future__ import annotations

import contextlib
import io
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCUMENTS = ["README.md"] + sorted(
    str(p.relative_to(ROOT)) for p in (ROOT / "docs").rglob("*.md") if "hooks" not in p.parts
)
MARKER = re.compile(r"^<!-- (slow|not run: .+|file: \S+) -->$")
FENCE = re.compile(r"^```(\w*)\s*$")
#: printed values that depend on the machine, not on the result
VOLATILE = ("s",)


@dataclass
class Block:
    language: str
    text: str
    marker: str | None
    line: int
    output: str | None = None  # the text block that follows, if any


def blocks(path: Path) -> list[Block]:
    lines = path.read_text().splitlines()
    found: list[Block] = []
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        end = next(j for j in range(i + 1, len(lines)) if lines[j].startswith("```"))
        marker = MARKER.match(lines[i - 1]) if i > 0 else None
        block = Block(m.group(1), "\n".join(lines[i + 1:end]) + "\n", marker and marker.group(1), i + 1)
        if block.language == "text" and found and found[-1].language == "sh" and end - i > 1:
            found[-1].output = block.text
        found.append(block)
        i = end + 1
    return found


def _pairs(text: str) -> dict[str, list[float]]:
    """``key = 1.5`` and ``key = [1, 2]`` pairs of a run's printed lines."""
    out = {}
    for key, value in re.findall(r"(\w+) = (\[[^\]]*\]|[-+]?[0-9][0-9.e+-]*)", " ".join(text.split())):
        out[key] = [float(v) for v in re.findall(r"[-+]?[0-9][0-9.e+-]*", value)]
    return out


def _run_command(line: str, where: str) -> str:
    from ibfem.solver import cli

    argv = shlex.split(line, comments=True)
    if not argv:
        return ""
    assert argv[0] == "ibfem", f"{where}: only ibfem commands run in examples, got {line!r}"
    stdout = io.StringIO()
    with contextlib.redirect_stdout(stdout):
        try:
            code = cli.main(argv[1:])
        except SystemExit as exc:  # --version and --help exit through argparse
            code = exc.code or 0
    assert code == 0, f"{where}: {line!r} exited with {code}\n{stdout.getvalue()}"
    return stdout.getvalue()


def _check_output(shown: str, printed: str, where: str) -> None:
    expected, got = _pairs(shown), _pairs(printed)
    for key, values in expected.items():
        if key in VOLATILE:
            continue
        assert key in got, f"{where}: the shown output has {key}, the command printed no such value:\n{printed}"
        for v, g in zip(values, got[key], strict=True):
            assert g == pytest.approx(v, rel=1e-5, abs=1e-12), f"{where}: {key} shown {v}, printed now {g}"


#: a fresh interpreter that runs a document's Python blocks in one namespace, as a reader's Python
#: session would: each request is a line with the code's length in characters, the code, and a
#: line naming the block; the answer is the length of the status ("ok" or the traceback) and the
#: status. What the blocks print goes to stderr.
PYTHON_SESSION = r"""
import contextlib, sys, traceback
namespace = {"__name__": "__docs__"}
answer = sys.stdout
for line in sys.stdin:
    code = sys.stdin.read(int(line))
    where = sys.stdin.readline().strip()
    try:
        with contextlib.redirect_stdout(sys.stderr):
            exec(compile(code, where, "exec"), namespace)
        status = "ok"
    except BaseException:
        status = traceback.format_exc()
    answer.write(f"{len(status)}\n{status}")
    answer.flush()
"""


class PythonSession:
    """The reader's Python: blocks run in another process, so what the in-process ``ibfem``
    commands imported does not leak into them (a reader runs those in a shell)."""

    def __init__(self, cwd: Path):
        self.log = open(cwd / "python_session.log", "w")
        self.process = subprocess.Popen([sys.executable, "-c", PYTHON_SESSION], cwd=cwd, text=True,
                                        stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self.log)

    def run(self, code: str, where: str) -> None:
        self.process.stdin.write(f"{len(code)}\n{code}{where}\n")
        self.process.stdin.flush()
        size = self.process.stdout.readline()
        assert size, f"{where}: the Python session ended (see {self.log.name})"
        status = self.process.stdout.read(int(size))
        assert status == "ok", f"{where}: {status}"

    def close(self) -> None:
        self.process.stdin.close()
        self.process.wait(timeout=60)
        self.log.close()


def run_document(document: str, tmp_path: Path, with_slow: bool) -> None:
    path = ROOT / document
    for name in ("examples", "fixtures"):
        (tmp_path / name).symlink_to(ROOT / name)
    session = None
    try:
        for block in blocks(path):
            where = f"{document}:{block.line}"
            marker = block.marker or ""
            if marker.startswith("not run:"):
                assert len(marker) > len("not run: "), f"{where}: a block that is not run must say why"
                continue
            if marker == "slow" and not with_slow:
                continue
            if marker.startswith("file: "):
                (tmp_path / marker[len("file: "):]).write_text(block.text)
            elif block.language == "sh":
                printed = "".join(_run_command(line, where) for line in block.text.splitlines())
                if block.output is not None and " converged in " in block.output:
                    _check_output(block.output, printed, where)
            elif block.language == "python":
                session = session or PythonSession(tmp_path)
                session.run(block.text, where)
    finally:
        if session is not None:
            session.close()


def _has_slow(document: str) -> bool:
    return any(b.marker == "slow" for b in blocks(ROOT / document))


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    return tmp_path


@pytest.mark.parametrize("document", DOCUMENTS)
def test_examples_run(document, workdir):
    run_document(document, workdir, with_slow=False)


@pytest.mark.slow
@pytest.mark.parametrize("document", [d for d in DOCUMENTS if _has_slow(d)])
def test_examples_run_with_slow_ones(document, workdir):
    run_document(document, workdir, with_slow=True)


def test_every_example_block_is_run_or_says_why():
    """Shell and Python examples run unless marked; a marker stands right before its block."""
    for document in DOCUMENTS:
        text = (ROOT / document).read_text().splitlines()
        for k, line in enumerate(text):
            if line.startswith("<!--") and ("slow" in line or "not run" in line or "file:" in line):
                assert MARKER.match(line), f"{document}:{k + 1}: malformed marker {line!r}"
                assert k + 1 < len(text) and FENCE.match(text[k + 1]), f"{document}:{k + 1}: marker not before a block"
