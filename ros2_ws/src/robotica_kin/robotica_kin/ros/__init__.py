"""
The ROS 2 shell shared by every robotica node (imports rclpy).

QoS profiles by role, parameter declaration, message conversions, the DH/dyn model messages,
the entry point that runs a node and the guard every node runs under.
"""

__all__ = ['convert', 'dh_messages', 'entry_point', 'guarded', 'parameters', 'qos']
