"""The batched numeric Jacobian equals the symbolic one on every built-in robot."""

import numpy as np
import pytest
import sympy as sp

from rankloci.io import builtin_models, load_model
from rankloci.kinematics import geometric_jacobian
from rankloci.model import RobotModel
from rankloci.numeric.batch_jacobian import BatchJacobian

SEED = 11
# entries are sums of a few products of O(1)-O(10) m lengths and unit trig
# values, so two double-precision evaluations agree to ~1e-14
ATOL = 1e-12


@pytest.mark.parametrize("name", builtin_models())
def test_batch_equals_symbolic(name):
    model = load_model(name)
    assert isinstance(model, RobotModel)
    J = sp.lambdify(model.variables, geometric_jacobian(model, frame="base").subs(model.parameters))
    Q = np.random.default_rng(SEED).uniform(-np.pi, np.pi, (4, model.dof))
    batch = BatchJacobian(model)(Q)
    for k in range(len(Q)):
        np.testing.assert_allclose(batch[k], np.array(J(*Q[k]), dtype=float), atol=ATOL)
