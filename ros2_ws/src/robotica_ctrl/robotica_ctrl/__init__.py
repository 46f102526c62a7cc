"""
Controllers of robotica, pure Python and NumPy (no ROS) except the node shells in ``nodes``.

Turns chapters 8 and 9 of A. Ollero, "Robótica. Manipuladores y robots móviles" (2001) into
code: joint-space trajectories (:mod:`robotica_ctrl.trajectory`, §8.2-8.3), joint controllers
(:mod:`robotica_ctrl.joint_control`: PID and computed torque, §8.4-8.5), and the mobile-robot
paths, trackers and reactive behaviours of :mod:`robotica_ctrl.mobile` (§9.3-9.6). Units are SI
and radians; poses follow REP-103 (x forward, θ from the x axis, counter-clockwise, lateral
offsets positive to the left).
"""

__all__ = ['joint_control', 'mobile', 'nodes', 'trajectory']
