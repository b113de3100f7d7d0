"""Input and output: scene files into a validated problem (:mod:`.scene`), results
(``summary.json``, VTU, plots: :mod:`.results`) and the progress display (:mod:`.progress`)."""
