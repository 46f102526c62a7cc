"""
End-to-end: UMBmark (Borenstein & Feng 1996), the systematic drift of the odometry.

The shipped ``umbmark_ccw`` drives a 4 m square counter-clockwise open loop: four times 4 m at
1 m/s (400 steps of 10 ms) and a turn in place of π/2 (100 steps at π/2 rad/s). The true wheels
are exact, so the truth is back at the start; the odometry's nominal geometry is off by the
scenario's per-wheel radius errors (e_L = -0.004, e_R = +0.004) and track error
(e_b = 0.02), so its end pose is not.

Closed form of the estimate (slides §13.6, book (4.109)-(4.110), exact arc (4.93)): a segment
in which the true wheels travel U_L, U_R is read as (1 + e_L) U_L and (1 + e_R) U_R, i.e. an
arc of length s = ((1 + e_L) U_L + (1 + e_R) U_R) / 2 turning by
Δθ = ((1 + e_R) U_R - (1 + e_L) U_L) / b_n, b_n = b (1 + e_b); within a segment the ratio of
the wheel travels is constant, so the per-step arcs compose into that one arc. A straight of
true length L has U_L = U_R = L: s = L (1 + ē), Δθ = L (e_R - e_L) / b_n, ē = (e_L + e_R) / 2.
A turn in place by α has U_R = -U_L = b α / 2: s = b α (e_R - e_L) / 4,
Δθ = α (1 + ē) / (1 + e_b). The expected end pose is the composition of the eight arcs.

Tolerance: the encoders floor the wheel angle to 4096 counts per revolution (0.15 mm of
travel a count), and the counts are cumulative, so each wheel's reading lags its true travel
by less than one count at any instant: the estimated heading is off the closed form's by at
most 2 counts / b_n ≈ 7.5e-4 rad at every instant (not more and more), and the position by at
most that times the 16 m driven (1.2 cm) plus a count. We allow 1.5 cm and 1e-3 rad, against
a drift of about 0.5 m and 0.2 rad that the test also checks is there (the run gave 0.1 mm).
"""
import math
from pathlib import Path
import subprocess

import pytest
from rosbags.highlevel import AnyReader

pytestmark = [pytest.mark.slow, pytest.mark.ros]
C, B = 0.1, 0.4                              # true wheel radius and track [m]
E_LEFT, E_RIGHT, E_TRACK = -0.004, 0.004, 0.02   # the scenario's odometry errors
SIDE, TURN = 4.0, math.pi / 2.0              # [m], [rad] counter-clockwise


def arc(pose, s, dtheta):
    """Return ``pose`` (x, y, θ) moved along an exact arc of length s turning by dtheta."""
    x, y, theta = pose
    if abs(dtheta) < 1e-12:
        return x + s * math.cos(theta), y + s * math.sin(theta), theta
    r = s / dtheta
    return (x + r * (math.sin(theta + dtheta) - math.sin(theta)),
            y - r * (math.cos(theta + dtheta) - math.cos(theta)), theta + dtheta)


def expected_end_pose():
    """Compose the odometry's arcs of the four legs and four turns (module docstring)."""
    b_n, e_mean = B * (1.0 + E_TRACK), 0.5 * (E_LEFT + E_RIGHT)
    pose = (0.0, 0.0, 0.0)
    for _ in range(4):
        pose = arc(pose, SIDE * (1.0 + e_mean), SIDE * (E_RIGHT - E_LEFT) / b_n)
        pose = arc(pose, B * TURN * (E_RIGHT - E_LEFT) / 4.0,
                   TURN * (1.0 + e_mean) / (1.0 + E_TRACK))
    return pose


def yaw(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y ** 2 + q.z ** 2))


def last_pose(reader, topic):
    connections = [c for c in reader.connections if c.topic == topic]
    *_, (connection, _, raw) = reader.messages(connections=connections)
    msg = reader.deserialize(raw, connection.msgtype)
    pose = msg.pose.pose
    return pose.position.x, pose.position.y, yaw(pose.orientation)


def test_umbmark_square_drifts_as_the_closed_form_says(tmp_path, ros_domain):
    run_dir = tmp_path / 'umbmark_ccw'
    proc = subprocess.run(['robotica', 'run', 'umbmark_ccw', '--output-dir', str(run_dir),
                           '--quiet', '--visualisation', 'off'],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    with AnyReader([Path(run_dir / 'bag')]) as reader:
        truth = last_pose(reader, '/ground_truth/odom')
        estimate = last_pose(reader, '/odom')
    # The true wheels are exact: the robot is back where it started (RK4 of constant v, ω).
    assert truth[:2] == pytest.approx((0.0, 0.0), abs=1e-6)
    assert math.remainder(truth[2], 2.0 * math.pi) == pytest.approx(0.0, abs=1e-6)
    x, y, theta = expected_end_pose()
    assert math.hypot(x, y) > 0.3 and abs(math.remainder(theta, 2.0 * math.pi)) > 0.1
    assert estimate[:2] == pytest.approx((x, y), abs=0.015)
    assert math.remainder(estimate[2] - theta, 2.0 * math.pi) == pytest.approx(0.0, abs=1e-3)
