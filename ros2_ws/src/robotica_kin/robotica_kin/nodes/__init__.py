"""ROS 2 shells of robotica_kin and the message conversions shared by every robotica node."""

__all__ = ['convert', 'entry_point', 'parameters', 'qos']
