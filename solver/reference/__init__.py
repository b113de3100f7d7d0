"""References the solver is checked against: Hertz, Cattaneo-Mindlin, McEwen's subsurface
field (:mod:`.theory`), and converged solutions of shipped examples by an independent code where
the half-space theory is not the posed problem's solution (:mod:`.converged`). Imports nothing
of the solver."""
