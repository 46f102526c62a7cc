"""
The ROS 2 shell shared by every robotica node (imports rclpy).

QoS profiles by role, parameter declaration, message conversions, the DH/dyn model messages
and the entry point that runs a node.
"""

__all__ = ['convert', 'dh_messages', 'entry_point', 'parameters', 'qos']
