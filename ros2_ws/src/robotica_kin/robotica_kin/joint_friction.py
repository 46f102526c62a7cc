"""
The joint friction law of a ``dyn`` table, checked once and evaluated without checks.

Its own module so that the dynamics (:mod:`robotica_kin.dynamics`) and the Pinocchio arm that
keeps one (:mod:`robotica_kin.pinocchio_model`) both use it without importing each other.
"""
import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.dh import as_dyn_model, DHModel

__all__ = ['JointFriction']


class JointFriction:
    """
    The joint friction law of a ``dyn`` table, checked once and evaluated without checks.

    ``F = G² B q' + |G| Tc`` per joint (book (5.84)-(5.86), HEMERO §A.3; see :func:`friction`).
    For loops that call it every step (a simulator's RK4 stages, a controller at 1 kHz): calling
    it takes float64 arrays of shape (n,) or (m, n) as they are.

    Examples
    --------
    >>> row = [0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2.0, 0.5, 0.1, -0.1]
    >>> JointFriction([row])(np.array([3.0, -3.0, 0.0])[:, None]).ravel()
    array([ 6.2, -6.2,  0. ])

    """

    def __init__(self, dyn: DHModel | ArrayLike) -> None:
        table = as_dyn_model(dyn).dyn
        assert table is not None
        gear = table[:, 16]
        self.viscous = gear ** 2 * table[:, 17]     # [N m s/rad] at the joint
        self.coulomb_positive = np.abs(gear) * table[:, 18]   # [N m] for q' > 0
        self.coulomb_negative = np.abs(gear) * table[:, 19]   # [N m] for q' < 0
        self.is_zero = not (self.viscous.any() or self.coulomb_positive.any()
                            or self.coulomb_negative.any())
        self.has_coulomb = bool(self.coulomb_positive.any() or self.coulomb_negative.any())

    def __call__(self, qd: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return F(q') [N m | N], the shape of ``qd``."""
        if not self.has_coulomb:
            return self.viscous * qd
        coulomb = np.where(qd > 0.0, self.coulomb_positive,
                           np.where(qd < 0.0, self.coulomb_negative, 0.0))
        return self.viscous * qd + coulomb
