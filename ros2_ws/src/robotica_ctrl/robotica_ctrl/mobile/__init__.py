"""
Mobile-robot path tracking (book ch. 9): path geometry and the pure-pursuit tracker (§9.3.1).

:mod:`robotica_ctrl.mobile.path` projects a pose onto a polyline path; the tracker in
:mod:`robotica_ctrl.mobile.pure_pursuit` turns that projection into a velocity command.
"""

__all__ = ['path', 'pure_pursuit']
