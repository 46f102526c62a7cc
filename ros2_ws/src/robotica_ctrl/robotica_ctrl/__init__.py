"""
Controllers of robotica, pure Python and NumPy (no ROS).

Turns chapter 9 of A. Ollero, "Robótica. Manipuladores y robots móviles" (2001) into code:
reference paths (:mod:`robotica_ctrl.path_shapes`) and the mobile-robot path trackers of
:mod:`robotica_ctrl.mobile` (pure pursuit, §9.3.1). Units are SI and radians; poses follow
REP-103 (x forward, θ from the x axis, counter-clockwise, lateral offsets positive to the left).
"""

__all__ = ['mobile', 'path_shapes']
