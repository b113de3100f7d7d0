"""Input and output: scene files into a validated problem (:mod:`.scene`; 3D scenes by
:mod:`.scene_solid`, imported when a scene names ``model = "solid"``), results (``summary.json``,
VTU, plots: :mod:`.results`) and the progress display (:mod:`.progress`). Importing the package
loads none of its modules."""
