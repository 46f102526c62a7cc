"""
robotica_sim: simulators, sensor emulators, odometry, the bag recorder and the robotica command.

Pure cores (no rclpy) are the top-level modules; the ROS 2 shells are in ``robotica_sim.nodes``
and the command line in ``robotica_sim.cli``.
"""

__all__ = ['diff_drive_simulation', 'encoder_model', 'scenario', 'run_summary']
