"""
Tests of robotica_ctrl.mobile.trajectory_tracking: posture tracking of book §9.4.2.

References, all independent of the code under test: the error (9.63) written in the book's
own heading convention (φ from the y axis) and worked by hand; the error dynamics
(9.64)-(9.67) written here and checked against finite differences of the unicycle; the
linearised closed loop (9.68) + (9.70) / (9.78) and its characteristic polynomials
(9.72) / (9.74) written here, whose roots are compared with the eigenvalues of a
finite-difference Jacobian of the law's closed loop; scipy's ``expm`` for the small-error
response; and the reference values of Ejemplos 9.3 and 9.4 (seed catalogue §7.10, computed
there by integrating the exact error dynamics). Closed loops integrate the unicycle
x' = v cos θ, y' = v sin θ, θ' = ω and the reference (9.59) with ``rk4_step``; the
reference posture along a circle is checked in closed form.
"""

import dataclasses
import functools
import math

from hypothesis import given, settings, strategies as st
import numpy as np
import pytest
from robotica_ctrl.mobile.path import PolylinePath
from robotica_ctrl.mobile.path_shapes import straight_line, unicycle_trajectory
from robotica_ctrl.mobile.trajectory_tracking import (
    design_linear_gains, LAWS, posture_error, PostureReference, TimedPath, tracking_command,
    tracking_gains, TrackingCommand, TrajectoryTracker, TrajectoryTrackingParams)
from robotica_kin.angles import heading_from_book, heading_to_book, wrap_to_pi
from robotica_kin.integrators import rk4_step
from scipy.linalg import expm

NO_LIMITS = {'max_linear': 1e3, 'max_angular': 1e3}


def unicycle_and_reference(t, state, params, v_ref, omega_ref):
    """Return d/dt of (robot pose, reference pose) under the law's command."""
    x, y, theta, x_r, y_r, theta_r = state
    command = tracking_command(state[:3], PostureReference(x_r, y_r, theta_r, v_ref, omega_ref),
                               params)
    return [command.linear * math.cos(theta), command.linear * math.sin(theta),
            command.angular,
            v_ref * math.cos(theta_r), v_ref * math.sin(theta_r), omega_ref]


def simulate(params, pose, reference_pose, velocities, duration, dt):
    """
    Integrate robot and reference for ``duration`` [s] with RK4 steps of ``dt`` [s].

    ``velocities(t)`` returns (v_r, ω_r), held over each step (the breakpoints of the
    examples fall on steps). Returns times (K,), robot poses (K, 3) and reference poses (K, 3).
    """
    state = np.concatenate([pose, reference_pose]).astype(float)
    steps = round(duration / dt)
    states = [state]
    for k in range(steps):
        t = k * dt
        state = rk4_step(unicycle_and_reference, t, state, dt, params,
                         *velocities(t + 1e-9))
        states.append(state)
    states = np.array(states)
    return dt * np.arange(steps + 1), states[:, :3], states[:, 3:]


def errors(poses, references):
    return np.array([posture_error(p, r) for p, r in zip(poses, references)])


# --- posture error (9.63) ----------------------------------------------------------------

def book_error(pose, reference_pose):
    """(9.63) as printed, in the book's convention: φ from the y axis."""
    x, y, theta = pose
    x_r, y_r, theta_r = reference_pose
    phi, phi_r = heading_to_book(theta), heading_to_book(theta_r)
    return np.array([-math.sin(phi) * (x_r - x) + math.cos(phi) * (y_r - y),
                     -math.cos(phi) * (x_r - x) - math.sin(phi) * (y_r - y),
                     phi_r - phi])


# (pose, reference pose, (e1, e2, e3)) worked by hand.
ERROR_TABLE = [
    ((0.0, 0.0, 0.0), (2.0, 0.0, 0.0), (2.0, 0.0, 0.0)),       # ahead
    ((0.0, 0.0, 0.0), (0.0, 1.5, 0.0), (0.0, 1.5, 0.0)),       # to the left
    ((0.0, 0.0, 0.0), (0.0, -1.5, 0.3), (0.0, -1.5, 0.3)),     # to the right, turned left
    ((1.0, 1.0, math.pi / 2), (1.0, 3.0, math.pi / 2), (2.0, 0.0, 0.0)),  # facing +y
    ((1.0, 1.0, math.pi / 2), (0.0, 1.0, math.pi / 2), (0.0, 1.0, 0.0)),  # -x is its left
    ((0.0, 0.0, math.pi), (-1.0, -2.0, math.pi), (1.0, 2.0, 0.0)),
    ((0.0, 0.0, math.pi / 4), (1.0, 1.0, 0.0), (math.sqrt(2.0), 0.0, -math.pi / 4)),
    ((0.0, 0.0, 3.0), (0.0, 0.0, -3.0), (0.0, 0.0, 2.0 * math.pi - 6.0)),  # wrapped
    ((0.0, 0.0, 0.1), (0.0, 0.0, 0.1 + 4.0 * math.pi), (0.0, 0.0, 0.0)),
]


@pytest.mark.parametrize(('pose', 'reference_pose', 'expected'), ERROR_TABLE)
def test_posture_error_table(pose, reference_pose, expected):
    error = posture_error(pose, reference_pose)
    assert error.dtype == np.float64 and error.shape == (3,)
    np.testing.assert_allclose(error, expected, atol=1e-12)
    # Invariant: (e1, e2) is the reference position in the robot frame, so its norm is the
    # distance; and the book's printed form agrees (e3 up to 2π).
    assert math.hypot(error[0], error[1]) == pytest.approx(math.dist(pose[:2],
                                                                     reference_pose[:2]))
    book = book_error(pose, reference_pose)
    np.testing.assert_allclose(error[:2], book[:2], atol=1e-12)
    assert wrap_to_pi(book[2] - error[2]) == pytest.approx(0.0, abs=1e-12)


finite = st.floats(-50.0, 50.0)


@settings(max_examples=60, deadline=None)
@given(pose=st.tuples(finite, finite, finite), reference_pose=st.tuples(finite, finite, finite),
       shift=st.tuples(finite, finite, st.floats(-math.pi, math.pi)))
def test_posture_error_is_invariant_to_a_change_of_world_frame(pose, reference_pose, shift):
    # The error lives in the robot frame: moving both poses by the same rigid motion keeps it.
    c, s = math.cos(shift[2]), math.sin(shift[2])

    def moved(p):
        return (c * p[0] - s * p[1] + shift[0], s * p[0] + c * p[1] + shift[1], p[2] + shift[2])

    error = posture_error(pose, reference_pose)
    np.testing.assert_allclose(posture_error(moved(pose), moved(reference_pose))[:2],
                               error[:2], atol=1e-9)
    assert wrap_to_pi(posture_error(moved(pose), moved(reference_pose))[2]
                      - error[2]) == pytest.approx(0.0, abs=1e-9)
    assert -math.pi < error[2] <= math.pi


@pytest.mark.parametrize('bad', [[0.0, 0.0], [0.0, 0.0, 0.0, 0.0], [math.nan, 0.0, 0.0],
                                 [0.0, math.inf, 0.0], [[0.0, 0.0, 0.0]]])
def test_posture_error_rejects_bad_poses(bad):
    with pytest.raises(ValueError, match='pose'):
        posture_error(bad, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match='reference_pose'):
        posture_error([0.0, 0.0, 0.0], bad)


def error_rate(error, v, omega, v_ref):
    """(9.64)-(9.67): e' = [ω e2 - v + v_r cos e3, -ω e1 + v_r sin e3, ω_r - ω]."""
    e1, e2, e3 = error
    return np.array([omega * e2 - v + v_ref * math.cos(e3), -omega * e1 + v_ref * math.sin(e3)])


@pytest.mark.parametrize(('pose', 'reference_pose', 'v', 'omega', 'v_ref', 'omega_ref'), [
    ((0.3, -0.2, 0.4), (1.0, 0.5, 1.2), 0.7, -0.3, 0.5, 0.2),
    ((-1.0, 2.0, -2.5), (0.5, 1.0, 2.0), -0.4, 1.1, 0.9, -0.6),
])
def test_error_dynamics_of_the_book_hold_for_the_unicycle(pose, reference_pose, v, omega,
                                                          v_ref, omega_ref):
    # Central differences of posture_error along the exact unicycle arcs of robot and
    # reference match (9.64)-(9.67), which the closed-loop tests below rely on.
    def arc(p, speed, rate, t):
        x, y, th = p
        return (x + speed * (math.sin(th + rate * t) - math.sin(th)) / rate,
                y - speed * (math.cos(th + rate * t) - math.cos(th)) / rate, th + rate * t)

    h = 1e-5
    rate = (posture_error(arc(pose, v, omega, h), arc(reference_pose, v_ref, omega_ref, h))
            - posture_error(arc(pose, v, omega, -h),
                            arc(reference_pose, v_ref, omega_ref, -h))) / (2.0 * h)
    error = posture_error(pose, reference_pose)
    np.testing.assert_allclose(rate[:2], error_rate(error, v, omega, v_ref), atol=1e-8)
    assert rate[2] == pytest.approx(omega_ref - omega, abs=1e-8)


# --- parameters --------------------------------------------------------------------------

def test_default_params_are_ejemplo_9_4():
    params = TrajectoryTrackingParams()
    assert (params.law, params.k2, params.delta, params.beta) == ('nonlinear', 19.0, 0.9, 13.75)
    assert (params.k1, params.k3) == (1.0, 4.0)  # Ejemplo 9.3(a), used by 'linear' only
    assert LAWS == ('linear', 'scheduled', 'nonlinear')


@pytest.mark.parametrize('bad', [0.0, -1.0, math.nan, math.inf, -math.inf])
@pytest.mark.parametrize('name', [f.name for f in dataclasses.fields(TrajectoryTrackingParams)
                                  if f.name != 'law'])
def test_params_reject_non_positive_or_non_finite(name, bad):
    with pytest.raises(ValueError, match=name):
        TrajectoryTrackingParams(**{name: bad})


@pytest.mark.parametrize('law', ['Linear', 'pid', '', None])
def test_params_reject_unknown_laws(law):
    with pytest.raises(ValueError, match='law'):
        TrajectoryTrackingParams(law=law)


@pytest.mark.parametrize('name', ['x', 'y', 'theta', 'v', 'omega'])
@pytest.mark.parametrize('bad', [math.nan, math.inf, 'a', None])
def test_reference_rejects_non_finite_values(name, bad):
    values = {'x': 0.0, 'y': 0.0, 'theta': 0.0, 'v': 0.5, 'omega': 0.1}
    values[name] = bad
    with pytest.raises(ValueError, match=name):
        PostureReference(**values)


@pytest.mark.parametrize(('args', 'match'), [
    ((0.0, 2.0, 0.5, 0.1), 'delta'), ((-0.5, 2.0, 0.5, 0.1), 'delta'),
    ((0.5, 2.0, 0.0, 0.1), 'v_ref'), ((0.5, 0.1, 0.5, 0.1), 'b'), ((0.5, 0.1, 0.5, -0.3), 'b'),
    ((0.5, math.nan, 0.5, 0.1), 'b'), ((0.5, 2.0, math.inf, 0.1), 'v_ref'),
])
def test_design_linear_gains_rejects_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        design_linear_gains(*args)


@pytest.mark.parametrize('pose', [[0.0, 0.0], [0.0, 0.0, math.nan], [math.inf, 0.0, 0.0]])
def test_update_rejects_bad_poses(pose):
    with pytest.raises(ValueError):
        tracking_command(pose, PostureReference(0.0, 0.0, 0.0, 0.5, 0.0),
                         TrajectoryTrackingParams())


# --- the laws, term by term --------------------------------------------------------------

def test_on_the_reference_the_command_is_the_reference():
    reference = PostureReference(1.0, -2.0, 0.7, 0.4, -0.3)
    for law in LAWS:
        command = tracking_command(reference.pose, reference, TrajectoryTrackingParams(law=law))
        assert (command.linear, command.angular) == (0.4, -0.3)
        np.testing.assert_array_equal(command.error, [0.0, 0.0, 0.0])
        assert not command.saturated


@pytest.mark.parametrize('v_ref', [0.5, -0.5])
def test_laws_by_hand(v_ref):
    # Robot at the origin facing +x; reference 0.1 m ahead, 0.05 m to the left, turned
    # 0.2 rad: e = (0.1, 0.05, 0.2); ω_r = 0.3.
    reference = PostureReference(0.1, 0.05, 0.2, v_ref, 0.3)
    pose = [0.0, 0.0, 0.0]
    sgn = math.copysign(1.0, v_ref)
    # Linear (9.70): v = v_r cos e3 + k1 e1, ω = ω_r + k2 sgn(v_r) e2 + k3 e3.
    command = tracking_command(pose, reference, TrajectoryTrackingParams(
        law='linear', k1=1.0, k2=2.0, k3=4.0, **NO_LIMITS))
    assert command.linear == pytest.approx(v_ref * math.cos(0.2) + 0.1)
    assert command.angular == pytest.approx(0.3 + 2.0 * sgn * 0.05 + 4.0 * 0.2)
    assert command.gains == (1.0, 2.0, 4.0)
    # Scheduled (9.77) with δ = 0.5, β = 3.64: b = sqrt(0.09 + 3.64 · 0.25) = 1,
    # k1 = k3 = 2 δ b = 1, k2 = β |v_r| = 1.82.
    command = tracking_command(pose, reference, TrajectoryTrackingParams(
        law='scheduled', delta=0.5, beta=3.64, **NO_LIMITS))
    np.testing.assert_allclose(command.gains, (1.0, 1.82, 1.0))
    assert command.linear == pytest.approx(v_ref * math.cos(0.2) + 0.1)
    assert command.angular == pytest.approx(0.3 + 1.82 * sgn * 0.05 + 0.2)
    # Nonlinear (9.78), same k1 = k3 = 1 (9.82), k2 = 19: ω = ω_r + k2 v_r (sin e3/e3) e2 + k3 e3.
    command = tracking_command(pose, reference, TrajectoryTrackingParams(
        law='nonlinear', delta=0.5, beta=3.64, k2=19.0, **NO_LIMITS))
    np.testing.assert_allclose(command.gains, (1.0, 19.0, 1.0))
    assert command.linear == pytest.approx(v_ref * math.cos(0.2) + 0.1)
    assert command.angular == pytest.approx(
        0.3 + 19.0 * v_ref * math.sin(0.2) / 0.2 * 0.05 + 0.2)
    np.testing.assert_allclose(command.error, [0.1, 0.05, 0.2], atol=1e-15)


def test_nonlinear_law_is_regular_at_zero_heading_error():
    command = tracking_command([0.0, 0.0, 0.0], PostureReference(0.0, 0.1, 0.0, 0.5, 0.0),
                               TrajectoryTrackingParams(**NO_LIMITS))
    k1, k2, k3 = command.gains
    assert command.angular == pytest.approx(k2 * 0.5 * 0.1)  # sin e3 / e3 -> 1


def test_scheduled_and_nonlinear_do_nothing_for_a_reference_at_rest():
    # (9.77): with v_r = ω_r = 0 the gains vanish (not controllable, §9.4.2).
    reference = PostureReference(1.0, 1.0, 1.0, 0.0, 0.0)
    for law in ('scheduled', 'nonlinear'):
        command = tracking_command([0.0, 0.0, 0.0], reference,
                                   TrajectoryTrackingParams(law=law))
        assert (command.linear, command.angular) == (0.0, 0.0)
        assert command.gains[0] == command.gains[2] == 0.0


@pytest.mark.parametrize('side', [1.0, -1.0])
def test_commands_are_clipped_to_the_limits(side):
    params = TrajectoryTrackingParams(law='linear', max_linear=0.3, max_angular=0.4)
    command = tracking_command(
        [0.0, 0.0, 0.0], PostureReference(side * 2.0, side * 1.0, 0.0, side * 0.2, 0.0), params)
    assert command.linear == side * 0.3
    assert command.angular == 0.4  # ω = k2 sgn(v_r) e2 = 19 · 1 > 0 either way
    assert command.saturated
    np.testing.assert_allclose(command.error, [side * 2.0, side * 1.0, 0.0])


def test_command_is_immutable():
    command = tracking_command([0.0, 0.0, 0.0], PostureReference(0.1, 0.0, 0.0, 0.5, 0.0),
                               TrajectoryTrackingParams())
    assert isinstance(command, TrackingCommand)
    with pytest.raises(ValueError):
        command.error[0] = 1.0
    with pytest.raises(AttributeError):
        command.linear = 1.0  # type: ignore[misc]


# --- poles of the linearised closed loop -------------------------------------------------

def closed_loop_jacobian(params, v_ref, omega_ref, h=1e-6):
    """
    Finite-difference Jacobian at e = 0 of e' = F(e) with the law's command.

    The robot pose that has error e to a reference at the origin heading +x is built by
    inverting (9.63); e' is (9.64)-(9.67).
    """
    reference = PostureReference(0.0, 0.0, 0.0, v_ref, omega_ref)

    def rate(error):
        theta = -error[2]
        c, s = math.cos(theta), math.sin(theta)
        pose = [-(c * error[0] - s * error[1]), -(s * error[0] + c * error[1]), theta]
        command = tracking_command(pose, reference, params)
        assert not command.saturated
        np.testing.assert_allclose(command.error, error, atol=1e-14)
        return np.append(error_rate(error, command.linear, command.angular, v_ref),
                         omega_ref - command.angular)

    columns = [(rate(h * unit) - rate(-h * unit)) / (2.0 * h) for unit in np.eye(3)]
    return np.column_stack(columns)


def assert_same_roots(eigenvalues, roots, tol=1e-6):
    eigenvalues = np.sort_complex(np.asarray(eigenvalues, dtype=complex))
    roots = np.sort_complex(np.asarray(roots, dtype=complex))
    np.testing.assert_allclose(eigenvalues, roots, atol=tol)


REFERENCES = [(0.5, 0.0), (0.2, 0.3), (1.0, -0.8), (-0.4, 0.5), (0.1, 0.2)]


@pytest.mark.parametrize(('v_ref', 'omega_ref'), REFERENCES)
@pytest.mark.parametrize(('delta', 'b'), [(0.7, 2.0), (1.5, 1.2), (0.9, 0.9)])
def test_linear_law_with_designed_gains_has_the_design_poles(v_ref, omega_ref, delta, b):
    # (9.74)-(9.75): poles -2δb and -δb ± b sqrt(δ² - 1).
    k1, k2, k3 = design_linear_gains(delta, b, v_ref, omega_ref)
    params = TrajectoryTrackingParams(law='linear', k1=k1, k2=k2, k3=k3, **NO_LIMITS)
    pair = b * np.sqrt(complex(delta ** 2 - 1.0))
    expected = [-2.0 * delta * b, -delta * b + pair, -delta * b - pair]
    assert_same_roots(np.linalg.eigvals(closed_loop_jacobian(params, v_ref, omega_ref)), expected)


@pytest.mark.parametrize(('v_ref', 'omega_ref'), REFERENCES + [(0.0, 0.4)])
@pytest.mark.parametrize('gains', [(1.0, 2.0, 4.0), (0.5, 7.0, 1.5)])  # first: Ejemplo 9.3(a)
def test_linear_law_has_the_roots_of_9_72(v_ref, omega_ref, gains):
    # (9.72) expanded: s³ + (k1 + k3) s² + (k1 k3 + k2 |v_r| + ω_r²) s
    #                  + k1 k2 |v_r| + k3 ω_r².
    k1, k2, k3 = gains
    params = TrajectoryTrackingParams(law='linear', k1=k1, k2=k2, k3=k3, **NO_LIMITS)
    w2, kv = omega_ref ** 2, k2 * abs(v_ref)
    roots = np.roots([1.0, k1 + k3, k1 * k3 + kv + w2, k1 * kv + k3 * w2])
    jacobian = closed_loop_jacobian(params, v_ref, omega_ref)
    assert_same_roots(np.linalg.eigvals(jacobian), roots)
    # and the matrix itself is (9.68) closed by (9.70).
    expected = [[-k1, omega_ref, 0.0], [-omega_ref, 0.0, v_ref],
                [0.0, -k2 * np.sign(v_ref), -k3]]
    np.testing.assert_allclose(jacobian, expected, atol=1e-8)


@pytest.mark.parametrize(('v_ref', 'omega_ref'), REFERENCES)
@pytest.mark.parametrize(('delta', 'beta'), [(0.9, 13.75), (0.5, 2.0), (1.3, 40.0)])
def test_scheduled_law_keeps_the_design_poles_at_every_speed(v_ref, omega_ref, delta, beta):
    # (9.76)-(9.77): b = sqrt(ω_r² + β v_r²); poles -2δb and -δb ± b sqrt(δ² - 1).
    params = TrajectoryTrackingParams(law='scheduled', delta=delta, beta=beta, **NO_LIMITS)
    b = math.sqrt(omega_ref ** 2 + beta * v_ref ** 2)
    pair = b * np.sqrt(complex(delta ** 2 - 1.0))
    expected = [-2.0 * delta * b, -delta * b + pair, -delta * b - pair]
    assert_same_roots(np.linalg.eigvals(closed_loop_jacobian(params, v_ref, omega_ref)), expected)


@pytest.mark.parametrize(('v_ref', 'omega_ref'), REFERENCES)
@pytest.mark.parametrize(('delta', 'beta', 'k2'), [(0.9, 13.75, 19.0), (0.6, 4.0, 4.0)])
def test_nonlinear_law_linearises_to_its_poles(v_ref, omega_ref, delta, beta, k2):
    # (9.78) about e = 0 with k1 = k3 = 2δ sqrt(ω_r² + β v_r²) (9.82): (9.72) with
    # k2 sgn(v_r) -> k2 v_r becomes (s + k1)(s² + k1 s + k2 v_r² + ω_r²); with k2 = β it is
    # the scheduled law's design (s + 2δb)(s² + 2δbs + b²).
    params = TrajectoryTrackingParams(law='nonlinear', delta=delta, beta=beta, k2=k2,
                                      **NO_LIMITS)
    k1 = 2.0 * delta * math.sqrt(omega_ref ** 2 + beta * v_ref ** 2)
    roots = np.append(np.roots([1.0, k1, k2 * v_ref ** 2 + omega_ref ** 2]), -k1)
    assert_same_roots(np.linalg.eigvals(closed_loop_jacobian(params, v_ref, omega_ref)), roots)


# --- closed loop on the unicycle ---------------------------------------------------------

def lyapunov(error, k2):
    """(9.79): V = k2 (e1² + e2²) / 2 + e3² / 2."""
    return 0.5 * k2 * (error[:, 0] ** 2 + error[:, 1] ** 2) + 0.5 * error[:, 2] ** 2


@pytest.mark.parametrize('law', LAWS)
@pytest.mark.parametrize(('v_ref', 'omega_ref'), [(0.5, 0.0), (0.5, 0.5), (-0.4, 0.0)],
                         ids=['straight', 'circle', 'straight_backwards'])
def test_converges_from_an_initial_offset(law, v_ref, omega_ref):
    # Reference from the origin heading +x; robot 0.5 m behind, 0.4 m to the right, turned
    # 0.4 rad: on the straight line, the circle of radius 1 m, and backwards. No limits.
    params = TrajectoryTrackingParams(law=law, **NO_LIMITS)
    times, poses, references = simulate(params, [-0.5, -0.4, 0.4], [0.0, 0.0, 0.0],
                                        lambda t: (v_ref, omega_ref), duration=15.0, dt=0.02)
    error = errors(poses, references)
    norm = np.linalg.norm(error, axis=1)
    assert norm[0] > 0.7
    # Decays: the worst error over each successive 3 s window shrinks, ending below 1 mm.
    window_max = norm[:-1].reshape(5, -1).max(axis=1)
    assert np.all(np.diff(window_max) < 0.0)
    assert norm[-1] < 1e-3
    if omega_ref != 0.0:  # on the circle: radius 1 m about (0, 1)
        assert math.dist(poses[-1, :2], (0.0, 1.0)) == pytest.approx(1.0, abs=1e-3)
    if law == 'nonlinear':
        # (9.81): V' = -k1 k2 e1² - k3 e3² <= 0 along the solution.
        v = lyapunov(error, params.k2)
        assert np.all(np.diff(v) <= 1e-9 * v[0])


@pytest.mark.parametrize('law', LAWS)
@pytest.mark.parametrize(('v_ref', 'omega_ref'), [(0.5, 0.0), (0.3, 0.4)])
def test_small_errors_follow_the_linearised_closed_loop(law, v_ref, omega_ref):
    # A 0.1 mm / 1e-4 rad offset evolves as expm(A t) e0, with A from (9.68) closed by (9.70)
    # (k2 sgn v_r), (9.77) or (9.78) (k2 v_r): the decay rates are the designed ones.
    params = TrajectoryTrackingParams(law=law, **NO_LIMITS)
    k1, k2, k3 = tracking_gains(params, v_ref, omega_ref)
    lateral = k2 * v_ref if law == 'nonlinear' else k2 * np.sign(v_ref)
    a = np.array([[-k1, omega_ref, 0.0], [-omega_ref, 0.0, v_ref], [0.0, -lateral, -k3]])
    e0 = np.array([1e-4, -1e-4, 1e-4])
    theta = -e0[2]
    c, s = math.cos(theta), math.sin(theta)
    pose = [-(c * e0[0] - s * e0[1]), -(s * e0[0] + c * e0[1]), theta]
    times, poses, references = simulate(params, pose, [0.0, 0.0, 0.0],
                                        lambda t: (v_ref, omega_ref), duration=6.0, dt=0.01)
    error = errors(poses, references)
    np.testing.assert_allclose(error[0], e0, atol=1e-15)
    predicted = np.array([expm(a * t) @ e0 for t in times[::50]])
    np.testing.assert_allclose(error[::50], predicted, atol=1e-3 * np.linalg.norm(e0))


@pytest.mark.parametrize('law', LAWS)
def test_converges_with_the_default_limits_active(law):
    # 2 m behind and 1 m to the left of a circle of radius 2 m: the first commands are
    # clipped to 1 m/s, 1.5 rad/s, yet the robot catches up with the reference.
    v_ref, omega_ref = 0.4, 0.2
    params = TrajectoryTrackingParams(law=law)
    reference = PostureReference(0.0, 0.0, 0.0, v_ref, omega_ref)
    assert tracking_command([-2.0, 1.0, -0.5], reference, params).saturated
    times, poses, references = simulate(params, [-2.0, 1.0, -0.5], [0.0, 0.0, 0.0],
                                        lambda t: (v_ref, omega_ref), duration=30.0, dt=0.02)
    commands = [tracking_command(p, PostureReference(*r, v_ref, omega_ref), params)
                for p, r in zip(poses, references)]
    assert max(abs(c.linear) for c in commands) <= 1.0
    assert max(abs(c.angular) for c in commands) <= 1.5
    assert not any(c.saturated for c in commands[-500:])
    assert np.linalg.norm(commands[-1].error) < 1e-3


# --- Ejemplos 9.3 and 9.4 (seed catalogue §7.10) -----------------------------------------

def ejemplo_velocities(t):
    """v_r = 0.2 m/s before 20 s, then 0.1; ω_r = 0.3 rad/s before 10 s, then 0.2."""
    return (0.2 if t < 20.0 else 0.1), (0.3 if t < 10.0 else 0.2)


@functools.lru_cache(maxsize=None)
def run_ejemplo(**params):
    """Robot from (1, 0.5), φ = π/6; reference from (0, 0), φ_r = 0; 30 s (cached)."""
    law = TrajectoryTrackingParams(**params, **NO_LIMITS)
    times, poses, references = simulate(
        law, [1.0, 0.5, heading_from_book(math.pi / 6.0)], [0.0, 0.0, heading_from_book(0.0)],
        ejemplo_velocities, duration=30.0, dt=0.01)
    assert not any(tracking_command(p, PostureReference(*r, *ejemplo_velocities(t)), law).saturated
                   for t, p, r in zip(times[::10], poses[::10], references[::10]))
    return times, references, errors(poses, references)


def at(times, values, t):
    return values[int(np.argmin(np.abs(times - t)))]


def test_ejemplo_9_3_reference():
    times, references, _ = run_ejemplo(law='linear', k1=1.0, k2=2.0, k3=4.0)
    final = at(times, references, 30.0)
    np.testing.assert_allclose(final[:2], [0.1821, -0.1980], atol=1e-4)
    # φ_r = θ_r - π/2, integrated without wrapping: 0.3 · 10 + 0.2 · 20 = 7 rad.
    assert final[2] - math.pi / 2.0 == pytest.approx(7.0, abs=1e-9)


def test_ejemplo_9_3_a_fixed_gains():
    # k1 = 1, k2 = 2, k3 = 4.
    times, _, error = run_ejemplo(law='linear', k1=1.0, k2=2.0, k3=4.0)
    np.testing.assert_allclose(at(times, error, 10.0), [0.066, 0.195, -0.102], atol=1e-3)
    np.testing.assert_allclose(at(times, error, 30.0), [0.0037, 0.0168, -0.0086], atol=1e-4)


def test_ejemplo_9_3_b_speed_scaling():
    # (9.77) with β = 13.75, δ = 0.9: clearly faster than the fixed gains.
    times, _, error = run_ejemplo(law='scheduled', beta=13.75, delta=0.9)
    np.testing.assert_allclose(at(times, error, 5.0), [0.010, 0.076, -0.241], atol=1e-3)
    np.testing.assert_allclose(at(times, error, 10.0), [0.0005, 0.0006, -0.0049], atol=1e-4)
    assert np.abs(error[times >= 20.0]).max() < 1e-5
    _, _, fixed = run_ejemplo(law='linear', k1=1.0, k2=2.0, k3=4.0)
    assert np.linalg.norm(at(times, error, 10.0)) < 0.05 * np.linalg.norm(at(times, fixed, 10.0))


def test_ejemplo_9_4_nonlinear():
    # (9.78) with k1 = k3 = 2δ sqrt(ω_r² + β v_r²) (9.82), β = 13.75, δ = 0.9, k2 = 19.
    times, _, error = run_ejemplo(law='nonlinear', beta=13.75, delta=0.9, k2=19.0)
    np.testing.assert_allclose(at(times, error, 5.0), [0.0045, 0.034, -0.203], atol=1e-3)
    np.testing.assert_allclose(at(times, error, 10.0), [-0.0004, -0.0011, 0.0047], atol=1e-4)
    assert np.abs(error[times >= 20.0]).max() < 1e-5


# --- the tracker along a path in time ----------------------------------------------------

def test_timed_reference_on_an_arc_is_exact():
    # v = 0.2 m/s, w = 0.3 rad/s from (0, 0, pi/2): the circle of radius 2/3 m about (-2/3, 0).
    samples = unicycle_trajectory([0.0, 0.0, math.pi / 2], [[0.2, 0.3, 10.0]], step=0.01)
    path = PolylinePath(samples[:, :2])
    reference = TimedPath(path, samples[:, 2]).reference(4.005)
    theta = math.pi / 2 + 0.3 * 4.005
    assert reference.x == pytest.approx(-2 / 3 + 2 / 3 * math.cos(0.3 * 4.005), abs=1e-6)
    assert reference.y == pytest.approx(2 / 3 * math.sin(0.3 * 4.005), abs=1e-6)
    assert reference.theta == pytest.approx(theta, abs=1e-5)
    assert reference.v == pytest.approx(0.2, rel=1e-4)
    assert reference.omega == pytest.approx(0.3, rel=1e-3)
    after = TimedPath(path, samples[:, 2]).reference(11.0)
    assert (after.v, after.omega) == (0.0, 0.0)


def test_untimed_reference_starts_at_the_first_update():
    path = PolylinePath(straight_line([0.0, 0.0], [4.0, 0.0]))
    tracker = TrajectoryTracker(path, TrajectoryTrackingParams(reference_speed=0.5))
    first = tracker.update([0.0, 0.0, 0.0], 100.0)
    later = tracker.update([0.0, 0.0, 0.0], 102.0)
    assert first.target_point.tolist() == [0.0, 0.0]
    assert later.target_point.tolist() == pytest.approx([1.0, 0.0])
    assert later.along_track == pytest.approx(1.0)   # the robot lags 1 m behind it
    command = tracking_command([0.0, 0.0, 0.0], PostureReference(1.0, 0.0, 0.0, 0.5, 0.0),
                               TrajectoryTrackingParams())
    assert (later.linear, later.angular) == (command.linear, command.angular)
    np.testing.assert_array_equal(later.extras['error'], command.error)
    assert later.extras['gains'] == command.gains


def test_finishes_once_reference_and_robot_are_at_the_end_until_reset():
    path = PolylinePath(straight_line([0.0, 0.0], [2.0, 0.0]))
    tracker = TrajectoryTracker(path, TrajectoryTrackingParams(reference_speed=1.0))
    tracker.update([0.0, 0.0, 0.0], 0.0)
    assert not tracker.update([1.5, 0.0, 0.0], 3.0).finished   # reference at its end, robot not
    out = tracker.update([1.97, 0.01, 0.0], 3.1)
    assert out.finished and (out.linear, out.angular) == (0.0, 0.0)
    assert tracker.update([0.0, 0.0, 0.0], 3.2).finished
    tracker.reset()
    assert not tracker.update([0.0, 0.0, 0.0], 3.3).finished   # a new reference from here
    with pytest.raises(ValueError, match='time'):
        tracker.update([0.0, 0.0, 0.0], math.nan)


def test_set_gains_switches_the_variant():
    path = PolylinePath(straight_line([0.0, 0.0], [4.0, 0.0]))
    tracker = TrajectoryTracker(path, TrajectoryTrackingParams(law='linear', **NO_LIMITS))
    assert tracker.update([0.0, -0.1, 0.0], 0.0).angular == pytest.approx(19.0 * 0.1)
    tracker.set_gains({'variant': 'scheduled'})
    assert tracker.params.law == 'scheduled'
    assert tracker.update([0.0, -0.1, 0.0], 0.0).angular == pytest.approx(13.75 * 0.5 * 0.1)
    with pytest.raises(ValueError):
        tracker.set_gains({'variant': 'fuzzy'})
    assert tracker.params.law == 'scheduled'
