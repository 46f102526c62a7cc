"""ROS 2 node shells of robotica_sim: parameters and topics around the pure cores."""

__all__ = ['encoder_emulator', 'odometry', 'recorder', 'simulator']
