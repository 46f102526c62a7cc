"""
What the adaptive laws of book §8.4.2-§8.4.3 share: a regressor and the estimates φ̂ it weighs.

:class:`~.adaptive_computed_torque.AdaptiveComputedTorque` (8.79)-(8.95) and
:class:`~.slotine_li.SlotineLi` (8.111)-(8.136) both write the dynamics as a regressor times the
parameters φ (:class:`~.regressor.ParameterRegressor`) and integrate an adaptation law for the
estimates φ̂ (p,) by the explicit step ``φ̂ <- φ̂ + dt φ̂'`` of each :meth:`update`.
"""

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .law import _checked_rows, JointControlLaw, JointReference, JointState
from .regressor import ParameterRegressor

__all__ = ['AdaptiveLaw']


class AdaptiveLaw(JointControlLaw):
    """
    Base of the adaptive laws: the regressor, the initial estimates and the current ones.

    Parameters
    ----------
    regressor : ParameterRegressor
        The model, e.g. :class:`~.regressor.LinkMassRegressor` or
        :class:`~.regressor.TwoLinkRegressor`.
    initial_estimates : array_like, shape (p,)
        φ̂(0), in the units of the parameters (kg for link masses).

    Raises
    ------
    ValueError
        For initial estimates that are not finite or not one per parameter.

    """

    def __init__(self, regressor: ParameterRegressor, initial_estimates: ArrayLike) -> None:
        self.regressor = regressor
        self.n = int(regressor.n)
        self.p = len(regressor.parameter_names)
        estimates = _checked_rows(('initial_estimates',), (initial_estimates,))[0]
        if estimates.shape != (self.p,):
            raise ValueError(f'initial_estimates must have one value per parameter '
                             f'{regressor.parameter_names}, got shape {estimates.shape}')
        self.initial_estimates = estimates
        self._phi = estimates.copy()

    @property
    def estimates(self) -> NDArray[np.float64]:
        """Return a copy of the current estimates φ̂ (p,)."""
        return self._phi.copy()

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """Return the names of the parameters, in the order of φ̂ (e.g. ``'link_1.mass'``)."""
        return tuple(self.regressor.parameter_names)

    def reset(self) -> None:
        """Return the estimates to the initial ones."""
        self._phi = self.initial_estimates.copy()

    def check_joints(self, reference: JointReference, state: JointState, dt: float) -> None:
        """Check the inputs of :meth:`update` (ValueError), and that they have n joints."""
        n = self.check_inputs(reference, state, dt)
        if n != self.n:
            raise ValueError(f'the regressor has {self.n} joints, got {n}')
