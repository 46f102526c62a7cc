"""
Many runs or bags at once on a Dask cluster: sweeps (``robotica sweep``) and batch grading.

``cluster`` opens the cluster (a local one on 127.0.0.1, or a running one by address) and maps
a function over items on it; ``sweep`` turns ``--vary`` and ``--seeds`` into validated runs;
``job`` runs and grades one of them on a worker, with a ROS domain id of its own; ``grading``
grades many bags. None of them imports rclpy: the runs are ``robotica run`` subprocesses.
"""

__all__ = ['cluster', 'grading', 'job', 'sweep']
