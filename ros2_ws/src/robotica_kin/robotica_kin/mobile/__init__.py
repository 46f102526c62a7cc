"""Mobile-robot kinematics (Ollero 2001, §4.7): configuration models and odometry."""

__all__ = ['differential_drive', 'odometry']
