"""Test helper: how well a dense stiffness matrix is conditioned."""

import numpy as np


def conditioning(k: np.ndarray) -> tuple[float, float]:
    """(smallest eigenvalue, largest diagonal / smallest eigenvalue) of the symmetric ``k``."""
    w = np.linalg.eigvalsh(k)
    return w[0], np.diag(k).max() / w[0]
