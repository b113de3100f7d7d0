"""The friction sweep of example 4 against Cattaneo-Mindlin: c/a computed for each friction
coefficient beside sqrt(1 - |Q| / (mu N)) for the forces each case computed, and the theory's
curve for the mean Q/N. Reads the sweep's results.csv, prints a table, writes a PNG.

    ibfem sweep examples/sweeps/friction.toml --out out/sweeps/friction
    python examples/sweeps/friction_vs_cattaneo_mindlin.py out/sweeps/friction
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np

from ibfem.solver.reference.theory import cattaneo_mindlin_stick_ratio


def read(out: Path) -> list[dict]:
    with open(out / "results.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "ok"]
    if not rows:
        raise SystemExit(f"{out / 'results.csv'}: no finished case")
    return rows


def main(argv: list[str]) -> int:
    out = Path(argv[0] if argv else "out/sweeps/friction")
    rows = read(out)
    mu = np.array([float(r["contacts.0.friction"]) for r in rows])
    N = np.array([float(r["contacts.0.normal_force"]) for r in rows])
    Q = np.array([float(r["contacts.0.tangential_force"]) for r in rows])
    ca = np.array([float(r["contacts.0.stick_half_width"]) / float(r["contacts.0.half_width"]) for r in rows])
    theory = np.array([cattaneo_mindlin_stick_ratio(q, n, m, allow_gross_slip=True) for q, n, m in zip(Q, N, mu)])
    print("| mu | Q/N | c/a | c/a Cattaneo-Mindlin | difference |")
    print("|---|---|---|---|---|")
    for m, q, n, c, t in zip(mu, Q, N, ca, theory):
        print(f"| {m:.3g} | {q / n:.4f} | {c:.4f} | {t:.4f} | {c - t:+.4f} |")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    grid = np.linspace(min(mu.min(), 0.1), mu.max(), 200)
    ratio = float(np.mean(np.abs(Q / N)))
    ax.plot(grid, np.sqrt(np.clip(1 - ratio / grid, 0, None)), "-", label=f"Cattaneo-Mindlin, |Q|/N = {ratio:.3f}")
    ax.plot(mu, theory, "x", label="Cattaneo-Mindlin for each case's Q, N")
    ax.plot(mu, ca, "o", mfc="none", label="ibfem")
    ax.set_xlabel("friction coefficient mu")
    ax.set_ylabel("c / a")
    ax.set_title("example 4: stick zone against friction")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    png = out / "plots" / "stick_ratio_vs_cattaneo_mindlin.png"
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=120)
    print(f"plot: {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
