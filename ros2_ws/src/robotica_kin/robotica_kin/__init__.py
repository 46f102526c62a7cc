"""
Kinematic models of robotica, pure Python, NumPy and Pinocchio (no ROS).

Turns chapters 3 and 4 of A. Ollero, "Robótica. Manipuladores y robots móviles" (2001) and
its HEMERO toolbox into functions: homogeneous transforms (:mod:`~robotica_kin.transforms`),
Craig's modified DH models (:mod:`~robotica_kin.dh`, :mod:`~robotica_kin.robots`), forward
and inverse kinematics, Jacobians and velocity propagation, Pinocchio models built from DH
tables, ``plotbot``, manipulator dynamics (:mod:`~robotica_kin.dynamics`, ch. 5, and
:mod:`~robotica_kin.moving_base` for an arm on a moving vehicle); HEMERO's
names are gathered in :mod:`robotica_kin.hemero`. Also angle
conventions, fixed-step integration, and the mobile-robot models of §4.7 with the odometry of
§4.7.5. Units are SI and radians; mobile headings follow REP-103 (θ from the world x axis); the
book's φ (from the y axis) enters and leaves through :mod:`robotica_kin.angles`.

Submodules are imported on use, so ``import robotica_kin`` stays light; :class:`IKError` is
the one name re-exported here, as the issue of the inverse kinematics asks.
"""

from typing import Any

__all__ = [
    'IKError', 'analytic_ik', 'angles', 'dh', 'differential_motion', 'dynamics', 'finite',
    'forward_kinematics', 'geodetic',
    'hemero', 'ik', 'integrators', 'jacobian', 'mobile', 'moving_base', 'pinocchio_model',
    'plotbot', 'robots',
    'transforms', 'types', 'velocity_propagation',
]


def __getattr__(name: str) -> Any:
    """Return :class:`robotica_kin.ik.IKError` on first use (module ``__getattr__``, PEP 562)."""
    if name == 'IKError':
        from robotica_kin.ik import IKError
        return IKError
    raise AttributeError(f'module {__name__!r} has no attribute {name!r}')
