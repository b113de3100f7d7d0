"""The cut cells' fictitious stiffness acts on the non-linear modes of a cell only: zero work on
every linear displacement (rigid motions and constant strains), positive on each single node's
shape function, and equal to the full cell's stiffness on the purely bilinear (trilinear) modes."""

import numpy as np
import pytest

from ibfem.solver.fem.fictitious import nonlinear_part, nonlinear_projector
from ibfem.solver.fem.hexahedra import REFERENCE_CORNERS, cell_stiffness as cube_stiffness, full_cube_moments
from ibfem.solver.fem.hexahedra import monomial_stiffness as cube_monomials
from ibfem.solver.fem.integration import REFERENCE_NODES, cell_stiffness, full_cell_moments, monomial_stiffness
from ibfem.solver.model.elasticity import elasticity_matrix, lame_parameters


def _full(dim):
    """The full cell's stiffness (steel, local units) and its corners."""
    if dim == 2:
        c = elasticity_matrix(*lame_parameters(2e11, 0.3, "plane_strain"), 2)
        return cell_stiffness(full_cell_moments(), monomial_stiffness(c)), REFERENCE_NODES
    c = elasticity_matrix(*lame_parameters(2e11, 0.3, "solid"), 3)
    return cube_stiffness(full_cube_moments(), 1.0, cube_monomials(c)), REFERENCE_CORNERS


@pytest.mark.parametrize("dim", [2, 3])
def test_no_work_on_linear_fields_and_full_stiffness_on_the_others(dim):
    k_full, corners = _full(dim)
    k = nonlinear_part(k_full, corners)
    rng = np.random.default_rng(dim)
    grad, shift = rng.normal(size=(dim, dim)), rng.normal(size=dim)
    u = (corners @ grad.T + shift).ravel()  # any linear field: rigid motions and constant strains
    assert np.abs(k @ u).max() < 1e-12 * np.abs(k_full).max() * np.abs(u).max()
    # a purely non-linear field (orthogonal to the linear ones at the nodes) sees the full stiffness
    q = nonlinear_projector(corners)
    v = q @ rng.normal(size=len(u))
    assert v @ k @ v == pytest.approx(v @ k_full @ v, rel=1e-12)
    # every single node's shape function keeps a stiffness (conditioning of tiny cut cells)
    assert (np.diag(k) > 0.05 * np.diag(k_full)).all()
    np.testing.assert_allclose(k, k.T, atol=1e-12 * np.abs(k).max())
    assert np.linalg.eigvalsh(k).min() > -1e-10 * np.abs(k).max()
