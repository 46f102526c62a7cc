"""
Compass emulator node: ground-truth yaw -> magnetometer field and compass heading.

Each ``ground_truth/odom`` message gives the true yaw (REP-103, ENU, from east); the reading is
:class:`robotica_sim.sensors.compass.CompassModel` (book §7.7: declination, hard- and soft-iron
deviation, tilt error, white noise, reproducible from ``seed``). Published, with the truth's
stamp:

* ``compass/magnetic_field`` (sensor_msgs/MagneticField): the field in the sensor frame [T] and
  the white noise's covariance;
* ``compass/heading`` (sensor_msgs/Imu, orientation only, as REP-145 asks of an orientation
  sensor): the heading the compass computes, as a yaw quaternion, with the heading variance of
  the noise; the angular-velocity and acceleration covariances are marked "not provided" (-1).

The deviation of hard and soft iron is a bias, not noise: it is not in the covariance (it is
what a calibration would remove), so a filter that trusts the covariance sees it as an error.
"""
import math

from nav_msgs.msg import Odometry
from rclpy.experimental import EventsExecutor
from robotica_kin.ros.convert import quaternion_to_yaw, yaw_to_quaternion
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare, declare_specs
from robotica_kin.ros.qos import STREAM_PUB_QOS, STREAM_REPLAY_SUB_QOS
from robotica_sim.sensors.compass import (COMPASS_PARAMETERS, compass_params, CompassModel,
                                          heading_noise_stddev)
from sensor_msgs.msg import Imu, MagneticField

_DEG = math.pi / 180.0


class CompassEmulatorNode(GuardedNode):
    """Publish the magnetometer reading and compass heading of the true yaw."""

    def __init__(self) -> None:
        super().__init__('compass_emulator')
        values = declare_specs(self, COMPASS_PARAMETERS)
        params = compass_params(values)
        seed = values['seed']
        self._model = CompassModel(params, seed)
        self._field_variance = params.noise_stddev ** 2
        self._heading_variance = heading_noise_stddev(params) ** 2
        self._frame = declare(self, 'frame_id', 'base_link', 'frame_id of the readings',
                              read_only=True)
        self._field_pub = self.create_publisher(MagneticField, 'compass/magnetic_field',
                                                STREAM_PUB_QOS)
        self._heading_pub = self.create_publisher(Imu, 'compass/heading', STREAM_PUB_QOS)
        self.create_subscription(Odometry, 'ground_truth/odom', self._on_truth,
                                 STREAM_REPLAY_SUB_QOS)
        self.get_logger().info(f'heading noise {math.sqrt(self._heading_variance) / _DEG:.3g} '
                               'deg (1 sigma)')

    def _on_truth(self, msg: Odometry) -> None:
        yaw = quaternion_to_yaw(msg.pose.pose.orientation)
        if not math.isfinite(yaw):
            self.get_logger().warn('non-finite ground truth; no reading',
                                   throttle_duration_sec=5.0)
            return
        field, heading = self._model.measure(yaw)
        out = MagneticField()
        out.header.stamp = msg.header.stamp
        out.header.frame_id = self._frame
        out.magnetic_field.x, out.magnetic_field.y, out.magnetic_field.z = (float(v)
                                                                            for v in field)
        out.magnetic_field_covariance = [self._field_variance if i % 4 == 0 else 0.0
                                         for i in range(9)]
        self._field_pub.publish(out)
        imu = Imu(orientation=yaw_to_quaternion(heading))
        imu.header = out.header
        imu.orientation_covariance = [0.0] * 8 + [self._heading_variance]
        imu.angular_velocity_covariance[0] = -1.0
        imu.linear_acceleration_covariance[0] = -1.0
        self._heading_pub.publish(imu)


def main(args=None) -> None:
    """Run the compass emulator until Ctrl-C."""
    run_node(CompassEmulatorNode, args, executor_factory=EventsExecutor)
