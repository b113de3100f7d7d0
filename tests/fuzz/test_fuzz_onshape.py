"""Fuzz: cached Onshape responses (copies of fixtures/onshape in a temporary directory) damaged
at a random JSON path or at the byte level must give a Part or an OnshapeFormatError naming the
file, ``ibfem verify --json`` exit 0/1/2 with strict JSON, and a scene on the damaged cache
``--check`` exit 0 or 2, never a traceback."""

from __future__ import annotations

import json
import shutil
import tempfile
import time
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from _oracles import check_part_directory, check_scene_file
from _values import mutate

ROOT = Path(__file__).resolve().parents[2]
FIXTURES = ROOT / "fixtures" / "onshape"
#: small caches (a full load under 0.2 s); the scene example uses half_cylinder_on_block
SMALL = ["cylinder_on_v_groove", "half_ellipse_on_block", "swept_spline", "freeform"]
FILES = ["tessellatedfaces.json", "bodydetails.json", "tessellatededges.json"]
WORK = Path(tempfile.mkdtemp(prefix="ibfem-fuzz-onshape-"))
PARSED = {(name, f): json.loads((FIXTURES / name / f).read_text()) for name in SMALL + ["half_cylinder_on_block"]
          for f in FILES if (FIXTURES / name / f).exists()}
SCENE = tomllib.loads((ROOT / "examples" / "onshape" / "half_cylinder_on_block.toml").read_text())


def _damaged_cache(data, names=SMALL) -> tuple[Path, str]:
    name = data.draw(st.sampled_from(names))
    target = WORK / "cache"
    shutil.rmtree(target, ignore_errors=True)
    shutil.copytree(FIXTURES / name, target)
    file = data.draw(st.sampled_from([f for f in FILES if (name, f) in PARSED]))
    if data.draw(st.integers(0, 5)) == 0:  # bytes
        raw = (target / file).read_bytes()
        at = data.draw(st.integers(0, len(raw)))
        how = data.draw(st.sampled_from(["truncate", "latin1", "garbage", "empty"]))
        raw = {"truncate": raw[:at], "latin1": raw[:at] + b"\xe9" + raw[at:], "empty": b"",
               "garbage": raw[:at] + data.draw(st.binary(min_size=1, max_size=6)) + raw[at:]}[how]
        (target / file).write_bytes(raw)
        return target, f"{name}/{file}: {how} at byte {at}"
    doc = PARSED[(name, file)]
    changes = []
    for _ in range(data.draw(st.integers(1, 2))):
        doc, what = mutate(doc, data.draw)
        changes.append(what)
    (target / file).write_text(json.dumps(doc, allow_nan=True))
    return target, f"{name}/{file}: " + "; ".join(changes)


def _scene_on(cache: Path) -> Path:
    scene = json.loads(json.dumps(SCENE))
    for body in scene["bodies"]:
        body["shape"]["path"] = str(cache)
    scene["output"] = {"vtk": False, "plots": False}
    path = WORK / "scene.json"
    path.write_text(json.dumps(scene))
    return path


FAST = settings(max_examples=40, deadline=None, database=None, derandomize=True,
                suppress_health_check=list(HealthCheck))


@FAST
@given(st.data())
def test_fuzz_damaged_caches_load_or_fail_cleanly(data):
    cache, what = _damaged_cache(data)
    problems = check_part_directory(cache, verify=data.draw(st.integers(0, 3)) == 0)
    assert not problems, (what, problems)


@settings(FAST, max_examples=6)
@given(st.data())
def test_fuzz_scenes_on_damaged_caches_check_cleanly(data):
    cache, what = _damaged_cache(data, ["half_cylinder_on_block"])
    problems = check_scene_file(_scene_on(cache))
    assert not problems, (what, problems)


@pytest.mark.slow
@pytest.mark.fuzz_long
def test_fuzz_long_onshape(findings):
    stop = findings.budget("onshape")

    @settings(max_examples=10, deadline=None, database=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck))
    @given(st.data())
    def one(data):
        scene = data.draw(st.integers(0, 4)) == 0
        cache, what = _damaged_cache(data, ["half_cylinder_on_block"] if scene else SMALL)
        problems = check_scene_file(_scene_on(cache)) if scene else check_part_directory(cache, verify=True)
        findings.record("onshape", problems, {"change": what})

    while time.monotonic() < stop:
        one()
    print(findings.summary("onshape"))
    assert not [f for f in findings.found if f["family"] == "onshape"], findings.summary("onshape")
