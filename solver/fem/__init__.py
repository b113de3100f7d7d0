"""The finite element layer: the quadtree background grid with exact cut cells
(:mod:`.grid`, :mod:`.integration`), a body's function space and point operators
(:mod:`.space`), assembly and the step boundary terms (:mod:`.assembly`,
:mod:`.step_boundary`), stress recovery (:mod:`.recovery`) and the linear algebra
(:mod:`.linalg`). Imports only the model layer and ``geometry``; knows no contact and no file."""
