"""
Joint-space trajectories of book ch. 10 with HEMERO's names (seed catalogue Part 8).

``pol3`` (cubic segments, §10.3.1/§10.6.1), ``pol5`` (quintic segments, §10.6.3) and ``parab``
(linear segments with parabolic blends, §10.6.4) return coefficients and samples every ``dt``.
"""

from .parabolic_blend import parab
from .polynomial import pol3, pol5

__all__ = ['parab', 'pol3', 'pol5']
