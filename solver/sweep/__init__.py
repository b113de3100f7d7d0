"""Parameter sweeps: ``ibfem sweep SWEEP.toml`` runs many variants of one scene on Dask."""
