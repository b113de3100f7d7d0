"""A sweep's results on disk: ``results.jsonl`` (one record per finished case, appended and
flushed as it finishes: what a rerun resumes from), ``results.csv`` (rebuilt from it, one row
per case of the sweep in case order) and ``cases/<hash>/`` (each case's result directory)."""

from __future__ import annotations

import csv
import json
import math
import os
import sys
import time
from pathlib import Path
from typing import Any

from .paths import PathError, get_path

#: statuses a rerun runs again with --retry-failed (the others are results)
FAILED = ("error", "timeout", "killed")


def output_values(summary: dict | None, columns: list[str]) -> dict[str, Any]:
    """The output columns from a case's summary (None where the path leads nowhere)."""
    values: dict[str, Any] = {}
    for column in columns:
        try:
            values[column] = get_path(summary, column) if summary is not None else None
        except PathError:
            values[column] = None
    return values


class Records:
    """The record file of one output directory."""

    def __init__(self, out: Path, digest: str):
        self.out = Path(out)
        self.digest = digest
        self.jsonl = self.out / "results.jsonl"
        self.csv = self.out / "results.csv"
        self.latest: dict[str, dict] = {}
        self.ignored = 0

    def load(self) -> "Records":
        """Read earlier records; those of another base scene, and a line cut short by an
        interruption, are ignored (counted in ``ignored``)."""
        if not self.jsonl.is_file():
            return self
        for line in self.jsonl.read_text(encoding="utf-8").splitlines():
            if not line.strip():
                continue
            try:
                rec = json.loads(line)
                key = rec["hash"]
            except (ValueError, KeyError, TypeError):
                self.ignored += 1
                continue
            if rec.get("scene_digest") == self.digest:
                self.latest[key] = rec
            else:
                self.ignored += 1
        return self

    def to_run(self, hashes: list[str], retry_failed: bool) -> set[str]:
        """The cases without a record (and, with ``retry_failed``, the failed ones)."""
        return {h for h in hashes if h not in self.latest
                or (retry_failed and self.latest[h].get("status") in FAILED)}

    def append(self, record: dict) -> None:
        self.out.mkdir(parents=True, exist_ok=True)
        record = {**record, "scene_digest": self.digest, "finished": time.strftime("%Y-%m-%dT%H:%M:%S")}
        with open(self.jsonl, "a", encoding="utf-8") as f:
            f.write(json.dumps(record, default=_plain) + "\n")
            f.flush()
            os.fsync(f.fileno())
        self.latest[record["hash"]] = record

    def write_case_dir(self, case_hash: str, scene: dict, files: dict[str, bytes]) -> Path:
        d = self.out / "cases" / case_hash
        d.mkdir(parents=True, exist_ok=True)
        (d / "scene.json").write_text(json.dumps(scene, indent=1) + "\n")
        for rel, data in files.items():
            p = d / rel
            p.parent.mkdir(parents=True, exist_ok=True)
            p.write_bytes(data)
        return d

    def write_csv(self, cases: list, columns: list[str]) -> None:
        params = list(dict.fromkeys(k for c in cases for k in c.params))
        header = ["case", "hash", *params, *columns, "status", "message", "wall_s", "peak_memory_mb", "worker"]
        self.out.mkdir(parents=True, exist_ok=True)
        tmp = self.csv.with_suffix(".csv.tmp")
        with open(tmp, "w", newline="", encoding="utf-8") as f:
            w = csv.writer(f)
            w.writerow(header)
            for c in cases:
                rec = self.latest.get(c.hash, {})
                outputs = rec.get("outputs", {})
                row = [c.index, c.hash, *(_cell(c.params.get(k)) for k in params),
                       *(_cell(outputs.get(col)) for col in columns),
                       rec.get("status", "pending"), rec.get("message", ""), _cell(rec.get("wall_s")),
                       _cell(rec.get("peak_memory_mb")), rec.get("worker", "")]
                w.writerow(row)
        os.replace(tmp, self.csv)


def _plain(value: Any) -> Any:
    try:
        return float(value)
    except (TypeError, ValueError):
        return str(value)


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else str(value)
    if isinstance(value, (int, str)):
        return str(value)
    return json.dumps(value, default=_plain)


def warn(text: str) -> None:
    print(f"ibfem sweep: {text}", file=sys.stderr)
