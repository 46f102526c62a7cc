"""
Trajectories of book ch. 10 with HEMERO's names (seed catalogue Part 8).

Joint space: ``pol3`` (cubic segments, §10.3.1/§10.6.1), ``pol5`` (quintic segments, §10.6.3)
and ``parab`` (linear segments with parabolic blends, §10.6.4) return coefficients and samples
every ``dt``; ``via_velocities`` gives the heuristic via-point velocities of §10.6.1;
``cubic_spline`` (natural or clamped), ``bspline``/``bspline_knots`` and ``bezier`` (§10.3.2)
smooth a sequence of points. ``cartesian_line`` is a straight line of the end effector
with axis-angle orientation interpolation (§10.5), solved point by point with inverse
kinematics.
``SampledTrajectory`` interpolates timed samples (what a ``JointTrajectory`` message carries);
``sinusoid`` is the test reference of Ej. 8.2 and the appendix's PUMA example.
"""

from .bspline import bezier, bspline, bspline_knots
from .cartesian_line import cartesian_line
from .parabolic_blend import parab
from .polynomial import pol3, pol5
from .sampled_trajectory import SampledTrajectory
from .sinusoid import sinusoid
from .splines import cubic_spline, via_velocities

__all__ = ['SampledTrajectory', 'bezier', 'bspline', 'bspline_knots', 'cartesian_line',
           'cubic_spline', 'parab', 'pol3', 'pol5', 'sinusoid', 'via_velocities']
