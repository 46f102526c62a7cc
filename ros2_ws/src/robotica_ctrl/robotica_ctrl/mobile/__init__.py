"""
Mobile-robot path tracking (book ch. 9): path geometry and the tracking laws.

:mod:`robotica_ctrl.mobile.path` projects a pose onto a polyline path,
:mod:`robotica_ctrl.mobile.path_shapes` samples the reference shapes; the laws turn poses into
velocity commands: :mod:`~robotica_ctrl.mobile.pure_pursuit` (§9.3.1),
:mod:`~robotica_ctrl.mobile.adaptive_lookahead` (pure pursuit with L by speed, curvature or
error), :mod:`~robotica_ctrl.mobile.quintic_tracker` (Shin's quintic, §9.3.2),
:mod:`~robotica_ctrl.mobile.trajectory_tracking` (§9.4.2, Canudas de Wit et al.),
:mod:`~robotica_ctrl.mobile.frenet_path_following` (§9.4.3–9.4.4),
:mod:`~robotica_ctrl.mobile.gpc_tracker` (the GPC path tracker of §9.5, on the generalised
predictive controller of :mod:`~robotica_ctrl.mobile.gpc`) and
:mod:`~robotica_ctrl.mobile.open_loop` (a profile played without feedback), and
:mod:`~robotica_ctrl.mobile.reversing_pure_pursuit` (pure pursuit that reverses at a path's
cusps, for manoeuvres such as parallel parking). Each law answers
with the one :class:`~robotica_ctrl.mobile.tracker_base.TrackerOutput` through the
:class:`~robotica_ctrl.mobile.tracker_base.TrackingLaw` interface;
:mod:`~robotica_ctrl.mobile.tracking_laws` builds any of them by name with its parameters.
:mod:`~robotica_ctrl.mobile.reactive` holds the reactive behaviours of §9.6 (wall following,
corridor centring, VFF, generalised potential, speed modulation), run by
:mod:`~robotica_ctrl.mobile.reactive_navigation` on :mod:`~robotica_ctrl.mobile.range_perception`.
"""

__all__ = ['adaptive_lookahead', 'frenet_path_following', 'gpc', 'gpc_tracker', 'open_loop',
           'path', 'path_shapes', 'pure_pursuit', 'quintic_tracker', 'range_perception',
           'reactive', 'reactive_navigation', 'reversing_pure_pursuit', 'tracker_base',
           'tracking_laws', 'trajectory_tracking']
