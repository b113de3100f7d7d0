"""Applications built on the library: ``make validate`` (:mod:`.validate`) and ``make demo``
(:mod:`.demo`)."""
