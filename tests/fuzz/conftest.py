"""The fuzz campaign. ``make test`` runs the bounded tests (a fixed number of
hypothesis examples per family, under 60 s together); ``make fuzz`` adds the long ones (marked
``fuzz_long`` and ``slow``), which share IBFEM_FUZZ_MINUTES between the families, keep going
after a defect and write every defect found, with its input, to out/fuzz/findings.jsonl."""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the _helpers beside the tests

ROOT = Path(__file__).resolve().parents[2]
#: share of the long run per family
SHARES = {"scenes": 0.3, "solves": 0.45, "onshape": 0.15, "geometry": 0.1}


def fuzz_minutes() -> float:
    try:
        return max(float(os.environ.get("IBFEM_FUZZ_MINUTES", "10")), 0.0)
    except ValueError:
        return 10.0


class Findings:
    """Defects of the long run: counted per family, each written with its input."""

    def __init__(self, path: Path):
        self.path = path
        self.tried: dict[str, int] = {}
        self.found: list[dict] = []

    def budget(self, family: str) -> float:
        return time.monotonic() + SHARES[family] * fuzz_minutes() * 60.0

    def record(self, family: str, problems: list[str], case: dict) -> None:
        self.tried[family] = self.tried.get(family, 0) + 1
        for p in problems:
            entry = {"family": family, "problem": p, "case": case}
            self.found.append(entry)
            self.path.parent.mkdir(parents=True, exist_ok=True)
            with self.path.open("a") as f:
                f.write(json.dumps(entry, default=str) + "\n")

    def summary(self, family: str) -> str:
        mine = [f for f in self.found if f["family"] == family]
        return f"{family}: {self.tried.get(family, 0)} cases, {len(mine)} defects"


    def write_summary(self) -> None:
        """out/fuzz/summary.json: cases and defects per family, the minutes asked for."""
        families = sorted(set(self.tried) | {f["family"] for f in self.found})
        doc = {"minutes": fuzz_minutes(), "families": {
            fam: {"cases": self.tried.get(fam, 0), "defects": sum(f["family"] == fam for f in self.found)}
            for fam in families}}
        self.path.parent.mkdir(parents=True, exist_ok=True)
        (self.path.parent / "summary.json").write_text(json.dumps(doc, indent=1) + "\n")


@pytest.fixture(scope="session")
def findings():
    path = ROOT / "out" / "fuzz" / "findings.jsonl"
    if path.exists():
        path.unlink()
    found = Findings(path)
    yield found
    if found.tried:
        found.write_summary()
