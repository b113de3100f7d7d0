"""Parameter sweeps (SPEC section 8): ``ibfem sweep SWEEP.toml`` on Dask (issue 16)."""
