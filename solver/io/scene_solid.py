"""3D scenes (``model = "solid"``, SPEC section 7): the file's pydantic models and the solver's
3D problem (issue 14)."""

from __future__ import annotations

from pathlib import Path
from typing import Any


def solid_scene_from_dict(data: dict, label: str, base_dir: Path, path: Path | None = None) -> Any:
    from solver.io.scene import SceneError

    raise SceneError([f'{label}: model = "solid": 3D scenes are not available in this build yet (issue 14)'])
