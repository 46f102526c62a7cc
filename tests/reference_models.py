"""
Independent reference models for the tests: the book's closed forms, written out once.

Nothing of robotica computes these: the planar 2R of Ej. 5.1 by its closed form (5.76)-(5.77),
and forward kinematics as the plain product of Craig's link transforms (4.5). Importable from
any test (``pytest.ini`` puts ``tests/`` on the path).
"""
import math

import numpy as np


def closed_form_2r(m1: float, m2: float, l1: float, l2: float, q, qd, qdd, g: float = 9.81):
    """
    Return ``(M, V, G, tau)`` of the planar 2R of Ej. 5.1 by the book's closed form (5.76)-(5.77).

    Point masses m1, m2 [kg] at the link ends l1, l2 [m], gravity g [m/s²] along -y (primes
    restored as the catalog notes). Used by the dynamics, moving-base and arm-simulator tests.
    """
    c1, c2, s2 = math.cos(q[0]), math.cos(q[1]), math.sin(q[1])
    c12 = math.cos(q[0] + q[1])
    M = np.array([[l2**2 * m2 + 2 * l1 * l2 * m2 * c2 + l1**2 * (m1 + m2),
                   l2**2 * m2 + l1 * l2 * m2 * c2],
                  [l2**2 * m2 + l1 * l2 * m2 * c2, l2**2 * m2]])
    V = np.array([-m2 * l1 * l2 * s2 * qd[1]**2 - 2 * m2 * l1 * l2 * s2 * qd[0] * qd[1],
                  m2 * l1 * l2 * s2 * qd[0]**2])
    G = np.array([m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1, m2 * l2 * g * c12])
    return M, V, G, M @ np.asarray(qdd, dtype=float) + V + G


def link_transform(alpha: float, a: float, theta: float, d: float) -> np.ndarray:
    """Return Craig's link transform (4.5) written out: the tests' independent reference."""
    ca, sa, ct, st = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
    return np.array([[ct, -st, 0, a], [st * ca, ct * ca, -sa, -sa * d],
                     [st * sa, ct * sa, ca, ca * d], [0, 0, 0, 1]])


def fk_by_link_product(robot, q) -> np.ndarray:
    """Return a DHModel's tool pose as the product of (4.5) link transforms (no Pinocchio)."""
    T = np.eye(4)
    for i, qi in enumerate(q):
        if robot.prismatic[i]:
            T = T @ link_transform(robot.alpha[i], robot.a[i], robot.theta[i], qi)
        else:
            T = T @ link_transform(robot.alpha[i], robot.a[i], qi, robot.d[i])
    return T @ robot.tool
