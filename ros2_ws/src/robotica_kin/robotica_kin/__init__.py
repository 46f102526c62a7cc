"""
Kinematic models of robotica, pure Python and NumPy (no ROS).

Turns chapter 4 of A. Ollero, "Robótica. Manipuladores y robots móviles" (2001) into
functions: angle conventions, fixed-step integration, and the mobile-robot models of §4.7
with the odometry of §4.7.5. Units are SI and radians; headings follow REP-103 (θ from the
world x axis); the book's φ (from the y axis) enters and leaves through
:mod:`robotica_kin.angles`.
"""

__all__ = ['angles', 'integrators', 'mobile', 'types']
