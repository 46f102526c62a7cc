"""ROS 2 node shells of robotica_ctrl."""

__all__ = ['path_tracker']
