"""
A compliant plane that the end effector of a simulated arm presses on (book §8.7.1, (8.164)).

The surface is a plane through the point ``x_e`` [m] with unit normal ``n`` pointing into the
environment, both in the base frame {0}. At the end-effector point ``p`` with velocity ``v``,
the penetration is ``δ = n·(p - x_e)`` and, in contact (δ > 0), the force that the end effector
exerts on the environment is

    ψ = f_n n + μ f_n v_t / max(|v_t|, v_μ),     f_n = max(0, K_e δ + B_e n·v),

zero without contact. ``K_e δ`` is the environment stiffness of (8.164), ``ψ = K_e (x - x_e)``
along n; ``B_e`` [N s/m] an optional normal damping (the total never pulls: no adhesion);
``μ`` an optional Coulomb friction along the tangential velocity ``v_t = v - (n·v) n``, which
the robot drags the surface with (the environment pushes back with -ψ). Below ``v_μ`` [m/s]
the friction grows linearly with the speed (a regularised Coulomb law) instead of switching
sign at every step of a fixed-step integration.

The joints feel ``τ_e = Jᵀ ψ`` (8.165)-(8.166), J the linear rows of ``jacob0``:
:class:`~robotica_sim.simulation.arm.ArmSimulation` computes it at the start of each step and
holds it over the step, as it holds the torque (zero-order hold). The step against the contact:
holding a spring force over a step h delays it by h/2 on average, which acts as a negative
damping ratio of about ``ω h / 4`` for the contact's natural frequency
``ω = sqrt(K_e / m_n)`` (:meth:`CompliantPlane.natural_frequency`; m_n the arm's mass along n).
Ej. 8.10 (K_e = 1200 N/m, PP robot, m_n = 2.16 kg): ω = 23.6 rad/s, and at h = 1 ms the hold
takes 0.006 from the damping ratio of about 0.1 that the law's K_v = 10 N s/m gives; the RK4
step itself is accurate for ω h ≪ 1 (here 0.024). Keep ω h below about 0.1.
"""

from dataclasses import dataclass
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.finite import finite_real
from robotica_kin.parameter_specs import named_error, parameter_values, ParameterSpec

__all__ = ['CompliantPlane', 'ContactWrench', 'ENVIRONMENT_PARAMETERS', 'compliant_plane']

ENVIRONMENT_PARAMETERS: dict[str, ParameterSpec] = {
    'environment.stiffness': ParameterSpec(
        0.0, 'K_e [N/m] of a compliant plane the end effector presses on, book (8.164) (Ej. 8.10: '
        '1200); 0: no environment', 0.0, 1e9),
    'environment.point': ParameterSpec((0.0, 0.0, 0.0), 'x_e: a point of the undeformed plane '
                                       '[m], base frame {0}'),
    'environment.normal': ParameterSpec((1.0, 0.0, 0.0), 'Its normal, pointing into the '
                                        'environment, base frame {0} (any length)'),
    'environment.damping': ParameterSpec(0.0, 'B_e [N s/m] along the normal (never pulls)',
                                         0.0, 1e9),
    'environment.friction': ParameterSpec(0.0, 'Coulomb coefficient along the tangential '
                                          'velocity; 0: frictionless', 0.0, 10.0),
}
"""The arm simulator's parameters of its environment, by name: :func:`compliant_plane`."""


def _point(name: str, value: ArrayLike) -> NDArray[np.float64]:
    array = np.array(value, dtype=np.float64)
    if array.shape != (3,) or not np.isfinite(array).all():
        raise ValueError(f'{name} must be 3 finite values in the base frame {{0}}, got {value!r}')
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class CompliantPlane:
    """
    A compliant plane, book (8.164): ψ = K_e δ n in contact (δ > 0), zero out of it.

    Attributes
    ----------
    point : array_like, shape (3,)
        x_e [m], a point of the undeformed surface, in {0}.
    normal : array_like, shape (3,)
        n, pointing into the environment, in {0}; any non-zero length (stored normalised).
    stiffness : float
        K_e [N/m] > 0.
    damping : float
        B_e [N s/m] >= 0 along n (default 0).
    friction : float
        Coulomb coefficient μ >= 0 along the tangential velocity (default 0: frictionless).
    friction_velocity : float
        v_μ [m/s] > 0, the speed below which the friction is proportional to it (1e-3).

    Raises
    ------
    ValueError
        For values that are not finite or out of their range, or a zero normal.

    Examples
    --------
    Ej. 8.10's surface x1 = 2 m (normal (1, -1, 0)/√2 in {0}), K_e = 1200 N/m, pressed 2.5 mm:

    >>> s = 1 / np.sqrt(2)
    >>> plane = CompliantPlane([2 * s, -2 * s, 0.0], [1.0, -1.0, 0.0], 1200.0)
    >>> float(np.linalg.norm(plane.force([2.0025 * s, -2.0025 * s, 0.0], np.zeros(3))))
    3.0

    """

    point: ArrayLike
    normal: ArrayLike
    stiffness: float
    damping: float = 0.0
    friction: float = 0.0
    friction_velocity: float = 1e-3

    def __post_init__(self) -> None:
        object.__setattr__(self, 'point', _point('point', self.point))
        normal = np.array(_point('normal', self.normal))
        length = float(np.linalg.norm(normal))
        if not length > 0.0:
            raise ValueError(f'normal must not be zero, got {self.normal!r}')
        object.__setattr__(self, 'normal', _point('normal', normal / length))
        for name, positive in (('stiffness', True), ('damping', False), ('friction', False),
                               ('friction_velocity', True)):
            value = finite_real(name, getattr(self, name))
            if value < 0.0 or (positive and value == 0.0):
                raise ValueError(f'{name} must be {">" if positive else ">="} 0, got {value!r}')
            object.__setattr__(self, name, value)

    def penetration(self, position: ArrayLike) -> float:
        """Return δ = n·(p - x_e) [m] of the point ``p`` (3,) [m] in {0}; > 0 in contact."""
        p = _point('position', position)
        return float(np.dot(np.asarray(self.normal), p - np.asarray(self.point)))

    def force(self, position: ArrayLike, velocity: ArrayLike) -> NDArray[np.float64]:
        """
        Return ψ (3,) [N] in {0}: the force the end effector at ``p`` exerts on the plane.

        ``position`` [m] and ``velocity`` [m/s] of the point, in {0}; zero out of contact.
        """
        depth = self.penetration(position)
        if depth <= 0.0:
            return np.zeros(3)
        n = np.asarray(self.normal)
        v = _point('velocity', velocity)
        normal_speed = float(np.dot(n, v))
        f_n = max(0.0, self.stiffness * depth + self.damping * normal_speed)
        psi = f_n * n
        if self.friction > 0.0 and f_n > 0.0:
            v_t = v - normal_speed * n
            psi += (self.friction * f_n / max(float(np.linalg.norm(v_t)),
                                              self.friction_velocity)) * v_t
        return psi

    def natural_frequency(self, mass: float) -> float:
        """
        Return ω = sqrt(K_e / m) [rad/s] of a mass ``m`` [kg] > 0 on this plane's stiffness.

        >>> CompliantPlane([0, 0, 0], [0, 0, -1], 1200.0).natural_frequency(3.0)
        20.0
        """
        m = finite_real('mass', mass)
        if not m > 0.0:
            raise ValueError(f'mass must be > 0 kg, got {mass!r}')
        return math.sqrt(self.stiffness / m)


@dataclass(frozen=True, eq=False)
class ContactWrench:
    """
    The contact wrench at the end effector: what it exerts on the environment (ψ, (8.164)).

    The contact is a point at the end effector (the tool frame's origin), so the torque about
    it is zero. The environment exerts the opposite wrench on the robot (:meth:`on_tool`).

    Attributes
    ----------
    force, torque : ndarray, shape (3,)
        ψ [N] and the torque about the end effector [N m], in the base frame {0}.
    force_tool, torque_tool : ndarray, shape (3,)
        The same in the tool frame's axes.
    penetration : float
        δ [m]; > 0 in contact (nan when the arm has no environment).

    """

    force: NDArray[np.float64]
    torque: NDArray[np.float64]
    force_tool: NDArray[np.float64]
    torque_tool: NDArray[np.float64]
    penetration: float

    def on_tool(self) -> NDArray[np.float64]:
        """
        Return the wrench the environment applies to the end effector, tool axes, (6,).

        ``-[force_tool; torque_tool]`` [N, N m]: what an ideal wrist F/T sensor at the tool
        frame reads (the ``contact_wrench`` input of the ``ft_sensor_emulator`` node).

        >>> zero = np.zeros(3)
        >>> ContactWrench(zero, zero, np.array([0.0, 0.0, 3.0]), zero, 0.0025).on_tool()
        array([-0., -0., -3., -0., -0., -0.])
        """
        return -np.concatenate([self.force_tool, self.torque_tool])


def compliant_plane(parameters: dict) -> CompliantPlane | None:
    """
    Return the plane of the arm simulator's ``environment.*`` parameters, None without one.

    Missing values take their defaults; ``environment.stiffness`` 0 means no environment.

    Raises
    ------
    robotica_kin.parameter_specs.ParameterError
        For a value out of its range or that the plane refuses (a zero normal), by name.

    Examples
    --------
    >>> compliant_plane({}) is None
    True
    >>> compliant_plane({'environment.stiffness': 1200.0}).stiffness
    1200.0

    """
    values = {name.removeprefix('environment.'): value
              for name, value in parameter_values(ENVIRONMENT_PARAMETERS, parameters).items()}
    if values['stiffness'] == 0.0:
        return None
    try:
        return CompliantPlane(**values)
    except ValueError as err:
        raise named_error(err, tuple(values), 'environment.') from None
