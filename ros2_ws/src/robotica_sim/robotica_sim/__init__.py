"""
robotica_sim: simulators, sensor emulators, odometry, the bag recorder and the robotica command.

Pure cores (no rclpy) are the top-level modules; the ROS 2 shells are in ``robotica_sim.nodes``
and the command line in ``robotica_sim.cli``.
"""

__all__ = ['allan', 'compass_model', 'encoder_model', 'gps_model', 'gyro_model', 'run_summary',
           'scenario', 'vehicle_simulation']
