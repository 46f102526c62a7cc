"""Mobile-robot kinematics (Ollero 2001, §4.7): configuration models, odometry and the EKF."""

__all__ = ['ackermann', 'bicycle', 'differential_drive', 'ekf_localization', 'odometry',
           'odometry_fusion', 'omnidirectional', 'skid_steer', 'tricycle', 'unicycle', 'vehicles']
