"""ROS 2 nodes of robotica_kin: forward kinematics and the inverse kinematics server."""

__all__ = ['fk_node', 'ik_server']
