"""Input and output: scene files into a validated problem (:mod:`.scene`), results
(``summary.json``, VTU, plots: :mod:`.results`) and the progress display (:mod:`.progress`)."""

from . import scene_solid as _scene_solid  # noqa: F401  registers model = "solid" with scene.SCENE_MODELS
