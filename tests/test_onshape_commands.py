"""``ibfem verify`` and ``ibfem info`` on the fixtures (in-process through the CLI)."""

from __future__ import annotations

import json
from collections import Counter

import pytest

from ibfem.solver.cli import main
from test_onshape_support import FIXTURES, copy_studio, edit_json

SPEC_FACE_KEYS = {"id", "type", "vertices", "max_error", "max_normal_error"}


def test_verify_json_follows_the_spec(capsys):
    assert main(["verify", str(FIXTURES / "freeform"), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert set(report) >= {"faces", "max_error"} and isinstance(report["max_error"], float)
    details = json.loads((FIXTURES / "freeform" / "bodydetails.json").read_text())
    ids = [f["id"] for b in details["bodies"] for f in b["faces"]]
    assert sorted(f["id"] for f in report["faces"]) == sorted(ids)
    for f in report["faces"]:
        assert SPEC_FACE_KEYS <= set(f) <= SPEC_FACE_KEYS | {"exact"}
        if f["type"] in ("BSURFACE", "SPUN"):
            assert f["exact"] is False and f["max_error"] is None
        else:
            assert f["exact"] is True and f["max_error"] <= 1e-12 and f["max_normal_error"] <= 1e-9
    assert report["max_error"] <= 1e-12


def test_verify_text_report(capsys):
    assert main(["verify", str(FIXTURES / "block_hole_fillet")]) == 0
    out = capsys.readouterr().out
    for word in ("TORUS", "CYLINDER", "PLANE", "OK"):
        assert word in out


def test_verify_fails_when_the_surface_is_not_the_tessellated_one(tmp_path, capsys):
    d = copy_studio("half_cylinder_on_block", tmp_path)

    def grow(data):
        for f in data["bodies"][0]["faces"]:
            if f["surface"]["type"] == "CYLINDER":
                f["surface"]["radius"] *= 1 + 1e-9  # 50 nm on 0.05 m: far above 1e-12 m

    edit_json(d / "bodydetails.json", grow)
    assert main(["verify", str(d), "--json"]) == 1
    report = json.loads(capsys.readouterr().out)
    assert report["max_error"] == pytest.approx(0.05e-9, rel=1e-3)


def test_info_counts_match_the_body_details(capsys):
    studio = "block_hole_fillet"
    assert main(["info", str(FIXTURES / studio)]) == 0
    out = capsys.readouterr().out
    details = json.loads((FIXTURES / studio / "bodydetails.json").read_text())
    faces = Counter(f["surface"]["type"] for b in details["bodies"] for f in b["faces"])
    edges = Counter(e["curve"]["type"] for b in details["bodies"] for e in b["edges"])
    lines = out.splitlines()
    for kind, n in list(faces.items()) + list(edges.items()):
        assert any(line.split()[:2] == [kind, str(n)] for line in lines), (kind, n)
    assert "Block with hole" in out
