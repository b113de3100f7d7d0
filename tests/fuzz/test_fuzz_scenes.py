"""Fuzz: scene files mutated at random key paths (values a new user might write, deleted and
unknown keys, duplicated items, scaled numbers, lists where strings belong) and damaged at the
byte level (truncated, foreign bytes, BOM) must end in ``ibfem run --check`` exit 0 or 2, with
every error line naming the file, and never a traceback."""

from __future__ import annotations

import json
import tempfile
import time
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from _oracles import check_scene_file
from _values import mutate

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def _bases() -> list[dict]:
    out = []
    for path in sorted(EXAMPLES.rglob("*.toml")):
        data = tomllib.loads(path.read_text())
        if "bodies" not in data:  # a sweep file, not a scene
            continue
        for body in data.get("bodies", []):  # relative paths would change meaning in the temporary directory
            shape = body.get("shape", {})
            if isinstance(shape.get("path"), str):
                shape["path"] = str((path.parent / shape["path"]).resolve())
        data["output"] = {"vtk": False, "plots": False, **{k: v for k, v in data.get("output", {}).items()
                                                            if k in ("probes", "lines")}}
        out.append(data)
    return out


BASES = _bases()
SOURCES = sorted(p for p in EXAMPLES.rglob("*.toml") if "[[bodies]]" in p.read_text())
WORK = Path(tempfile.mkdtemp(prefix="ibfem-fuzz-scenes-"))
FAST = settings(max_examples=80, deadline=None, database=None, derandomize=True,
                suppress_health_check=list(HealthCheck))


def _mutated_scene(data) -> tuple[Path, str]:
    doc = data.draw(st.sampled_from(BASES))
    changes = []
    for _ in range(data.draw(st.sampled_from([1, 1, 1, 2, 3]))):
        doc, what = mutate(doc, data.draw)
        changes.append(what)
    path = WORK / "scene.json"
    try:
        text = json.dumps(doc, allow_nan=True)
    except (ValueError, RecursionError):
        text = "{}"
    path.write_text(text)
    return path, "; ".join(changes)


def _damaged_file(data) -> tuple[Path, str]:
    source = data.draw(st.sampled_from(SOURCES))
    raw = source.read_bytes()
    how = data.draw(st.sampled_from(["truncate", "insert", "bom", "latin1", "replace"]))
    at = data.draw(st.integers(0, len(raw)))
    if how == "truncate":
        raw = raw[:at]
    elif how == "insert":
        raw = raw[:at] + data.draw(st.binary(min_size=1, max_size=8)) + raw[at:]
    elif how == "bom":
        raw = b"\xef\xbb\xbf" + raw
    elif how == "latin1":
        raw = raw[:at] + "\u00e9".encode("latin-1") + raw[at:]
    else:
        raw = raw[:at] + data.draw(st.sampled_from([b"= =", b"[[", b"]]", b'"', b"\n[solver]\n", b"inf", b"nan"])) + raw[at:]
    path = WORK / source.parent.relative_to(EXAMPLES) / source.name if False else WORK / source.name
    path.write_bytes(raw)
    # the Onshape example's relative path points from examples/onshape: keep it valid
    if "onshape" in source.parts:
        path = source.parent / f".fuzz-{source.name}"
        path.write_bytes(raw)
    return path, f"{how} at byte {at} of {source.name}"


@FAST
@given(st.data())
def test_fuzz_scene_mutations_check_cleanly(data):
    path, what = _mutated_scene(data)
    problems = check_scene_file(path)
    assert not problems, (what, problems)


@settings(FAST, max_examples=30)
@given(st.data())
def test_fuzz_damaged_scene_files_check_cleanly(data):
    path, what = _damaged_file(data)
    try:
        problems = check_scene_file(path)
    finally:
        if path.name.startswith(".fuzz-"):
            path.unlink(missing_ok=True)
    assert not problems, (what, problems)


@pytest.mark.slow
@pytest.mark.fuzz_long
def test_fuzz_long_scenes(findings):
    stop = findings.budget("scenes")

    @settings(max_examples=20, deadline=None, database=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck))
    @given(st.data())
    def one(data):
        if data.draw(st.integers(0, 4)) == 0:
            path, what = _damaged_file(data)
        else:
            path, what = _mutated_scene(data)
        try:
            text = path.read_bytes()[:20000].decode("utf-8", "replace")
            findings.record("scenes", check_scene_file(path), {"change": what, "file": text})
        finally:
            if path.name.startswith(".fuzz-"):
                path.unlink(missing_ok=True)

    from _oracles import CHECK_CODES

    before = dict(CHECK_CODES)
    while time.monotonic() < stop:
        one()
    for code, n in CHECK_CODES.items():  # valid (0) and refused (2) scenes
        findings.tried[f"scenes-exit-{code}"] = n - before.get(code, 0)
    print(findings.summary("scenes"))
    assert not [f for f in findings.found if f["family"] == "scenes"], findings.summary("scenes")
