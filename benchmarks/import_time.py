"""Time of ``from ibfem import geometry`` in a fresh interpreter (target under 0.25 s, numba not imported; exit 1 above 0.5 s or with a heavy module loaded), best of 5, and
the heavy modules it must not pull in. Writes benchmarks/results/import_time.json."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

CODE = (
    "import sys, time; t = time.perf_counter(); import geometry; dt = time.perf_counter() - t\n"
    "heavy = [m for m in ('solver', 'importers', 'pyvista', 'matplotlib', 'requests', 'trimesh',"
    " 'scipy.interpolate', 'scipy.spatial', 'numba') if m in sys.modules]\n"
    "print(dt); print(','.join(heavy))"
)


def main() -> int:
    times, heavy = [], ""
    for _ in range(5):
        out = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True, check=True).stdout.split("\n")
        times.append(float(out[0]))
        heavy = out[1]
    best = min(times)
    result = {"import_geometry_s": best, "all_s": times, "heavy_modules_loaded": heavy.split(",") if heavy else [], "target_s": 0.25}
    print(f"import geometry: best {best:.3f} s of {len(times)} (target 0.25 s); heavy modules loaded: {heavy or 'none'}")
    out_dir = Path(__file__).resolve().parent / "results"
    out_dir.mkdir(exist_ok=True)
    (out_dir / "import_time.json").write_text(json.dumps(result, indent=2))
    return 0 if best < 0.5 and not heavy else 1


if __name__ == "__main__":
    sys.exit(main())
