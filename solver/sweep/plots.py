"""Plots of a sweep (PNG, headless): every numeric output column against each parameter that
takes more than one value, one line per combination of the other parameters' values."""

from __future__ import annotations

import json
import re
from collections import defaultdict
from pathlib import Path
from typing import Any

from .records import warn


def _number(value: Any) -> float | None:
    if isinstance(value, (bool, int, float)):
        return float(value)
    return None


def _show(value: Any) -> str:
    return f"{value:.6g}" if isinstance(value, float) else json.dumps(value)


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_-]+", "_", text).strip("_") or "value"


def _series(outcome, column: str, param: str) -> dict[str, list[tuple[Any, float]]]:
    """Label of the other parameters' values -> [(parameter value, output)], in case order."""
    lines: dict[str, list[tuple[Any, float]]] = defaultdict(list)
    for case in outcome.cases:
        rec = outcome.record(case)
        y = _number((rec.get("outputs") or {}).get(column))
        if rec.get("status") not in ("ok", "not_converged") or y is None:
            continue
        others = ", ".join(f"{k} = {_show(v)}" for k, v in case.params.items() if k != param)
        lines[others].append((case.params.get(param), y))
    return lines


def _plot_one(plt, outcome, column: str, param: str, path: Path) -> bool:
    lines = _series(outcome, column, param)
    if not lines:
        return False
    xs_all = [x for pts in lines.values() for x, _ in pts]
    numeric = all(_number(x) is not None for x in xs_all)
    categories = list(dict.fromkeys(json.dumps(x) for x in xs_all))
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for label, pts in lines.items():
        pts = sorted(pts, key=lambda p: _number(p[0])) if numeric else pts
        xs = [_number(x) for x, _ in pts] if numeric else [categories.index(json.dumps(x)) for x, _ in pts]
        ax.plot(xs, [y for _, y in pts], "o-", label=label or None)
    if not numeric:
        ax.set_xticks(range(len(categories)), categories, rotation=30, fontsize=7)
    ax.set_xlabel(param)
    ax.set_ylabel(column)
    ax.set_title(f"{outcome.records.out.name}: {column}", fontsize=9)
    ax.grid(True, alpha=0.3)
    if 1 < len(lines) <= 12:
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def write_plots(outcome) -> list[Path]:
    """``<out>/plots/<column>_vs_<parameter>.png``; nothing (and a note) without matplotlib."""
    params = [k for k in dict.fromkeys(k for c in outcome.cases for k in c.params)
              if len({json.dumps(c.params.get(k)) for c in outcome.cases}) > 1]
    columns = list(dict.fromkeys(k for c in outcome.cases for k in (outcome.record(c).get("outputs") or {})))
    if not params or not columns:
        return []
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        warn("no plots: matplotlib is not installed (pip install 'ibfem[pictures]')")
        return []
    d = outcome.out / "plots"
    d.mkdir(parents=True, exist_ok=True)
    written = []
    for column in columns:
        for param in params:
            path = d / f"{_slug(column)}_vs_{_slug(param)}.png"
            if _plot_one(plt, outcome, column, param, path):
                written.append(path)
    return written
