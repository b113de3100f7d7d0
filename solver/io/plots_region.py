"""The picture of a 3D contact region of general shape (a line or flat contact): the pressure's cell means
over the patch in the tangent plane (the cells the region fills less than three quarters merged
with their inner neighbour, each mean drawn at its cells' centroid) with the region's boundary
(free edges, where the contact is complete, marked), and the cell means along both axes."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

__all__ = ["region_figure"]


def region_figure(plt, title: str, c: Mapping[str, Any]) -> Any:
    """The figure of one contact block with a ``boundary`` (solver.contact.region_report)."""
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(13, 5), constrained_layout=True)
    for k, style in ((0, "o-"), (1, "s--")):
        pr = c["pressure"].get(f"axis{k}", {"s": [], "value": []})
        ax.plot(pr["s"], pr["value"], style, ms=3, label=f"pressure (cell means), axis {k}")
    ax.set_xlabel("s along the axis from the contact point [m]")
    ax.set_ylabel("pressure [Pa]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    m = c["pressure_map"]
    s = np.asarray(m["s"], dtype=float).reshape(-1, 2)
    image = ax2.scatter(s[:, 0], s[:, 1], c=m["value"], s=12, marker="s", cmap="viridis")
    fig.colorbar(image, ax=ax2, shrink=0.8, label="pressure [Pa]")
    point, axes = np.asarray(c["point"], dtype=float), np.asarray(c["axes"], dtype=float)
    edge = (np.asarray(c["boundary"]["points"], dtype=float) - point) @ axes.T
    free = np.asarray(c["boundary"]["free_edge"], dtype=bool)
    closed = np.vstack([edge, edge[:1]])
    ax2.plot(closed[:, 0], closed[:, 1], "k-", lw=1.0, label="boundary")
    if free.any():
        ax2.plot(edge[free, 0], edge[free, 1], "r.", ms=4, label="free edge (complete contact)")
    # the peak where the smooth fit of the map puts it (the largest square's centroid without one)
    peak_at = c.get("peak_fit", {}).get("at", c["peak_at"])
    ax2.plot(*(np.asarray(peak_at, dtype=float) - point) @ axes.T, "w*", ms=10, mec="k", label="peak")
    ax2.set_aspect("equal")
    ax2.set_xlabel("axis 0 [m]")
    ax2.set_ylabel("axis 1 [m]")
    ax2.legend(fontsize=8)
    a, b = c["semi_axes"]
    fig.suptitle(f"{title}: contact {'/'.join(c['bodies'])}, half-extents {a:.4g} x {b:.4g} m, "
                 f"peak {c['peak_pressure']:.4g} Pa")
    return fig
