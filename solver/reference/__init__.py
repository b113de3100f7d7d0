"""Analytical references the solver is checked against: Hertz, Cattaneo-Mindlin, McEwen's
subsurface field (:mod:`.theory`). Imports nothing of the solver."""
