"""
Markers node: a run made visible in RViz or Foxglove as visualization_msgs/MarkerArray.

Publishes ``markers`` (visualization_msgs/MarkerArray) at ``publish_rate`` [Hz] of the node's
clock, each array holding the markers whose data changed since the previous one. Namespaces
and ids are fixed, so each marker replaces its previous version:

====================== ============ ======================================================
namespace (id)         type         from
====================== ============ ======================================================
``path`` (0)           LINE_STRIP   ``path`` (nav_msgs/Path, latched), in its frame
``target`` (0)         SPHERE       ``path_tracker/tracking_error`` ``target_point``
``footprint`` (0, 1)   LINE_STRIP   the vehicle's outline at ``odom`` (0, blue) and at
                                    ``ground_truth/odom`` (1, white), in their frames
``covariance`` (0)     LINE_STRIP   the ``covariance_k``-sigma ellipse of ``odom``'s x-y
                                    pose covariance, about the estimated position
``gps`` (0)            POINTS       the newest ``gps_history`` fixes of ``gps/fix``, in
                                    ``world_frame_id`` (the ENU frame of ``origin.*``)
``tool`` (0)           LINE_LIST    an axis triad (x red, y green, z blue) at the arm's
                                    reference tool pose: ``fkine`` of
                                    ``joint_controller/controller_state``'s
                                    ``reference_position``, in ``arm_frame_id``
====================== ============ ======================================================

Each marker is stamped with the stamp of the message it shows (the sim time of its data) and
lives ``marker_lifetime`` [s] (it vanishes when its data stops), except the path, which lives
until replaced and is sent again once a second so that a viewer that connects late gets it.
The vehicle is ``vehicle.type`` with the simulator's geometry ``vehicle.*`` ('': no footprint);
its outline is :func:`robotica_kin.marker_geometry.vehicle_outline`, the convex hull of the
wheels of its URDF with a nose ahead. The arm is chosen as every arm node chooses it
(``robot``, ``dh_table``, ``joint_names``).

The node drives nothing. A message it cannot draw (non-finite or absurd values, a covariance
that is not one, a reference of the wrong size, a malformed stamp) is logged by the guard and
dropped; the marker keeps its previous version.
"""
from collections import deque
import math
from typing import Any, Callable

from builtin_interfaces.msg import Duration
from geometry_msgs.msg import Point, Pose, Quaternion
from nav_msgs.msg import Odometry, Path
import numpy as np
from numpy.typing import ArrayLike, NDArray
from rclpy.experimental import EventsExecutor
from robotica_kin.bounds import bounded, bounded_array, MAX_JOINT_POSITION, MAX_LATITUDE, \
    MAX_LONGITUDE
from robotica_kin.forward_kinematics import fkine
from robotica_kin.geodetic import GeodeticOrigin
from robotica_kin.marker_geometry import (covariance_ellipse, ellipse_polygon,
                                          MARKERS_PARAMETERS, vehicle_outline)
from robotica_kin.mobile.vehicles import GEOMETRY_PARAMETERS, VehicleGeometry
from robotica_kin.ros.convert import (path_points, quaternion_to_yaw, seconds_to_stamp,
                                      stamp_to_seconds, yaw_to_quaternion)
from robotica_kin.ros.dh_messages import declare_robot, pose_message
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import GuardedNode
from robotica_kin.ros.parameters import declare_specs
from robotica_kin.ros.qos import INPUT_QOS_OVERRIDES, LATCHED_QOS, STREAM_PUB_QOS, STREAM_SUB_QOS
from robotica_msgs.msg import JointControllerState, TrackingError
from sensor_msgs.msg import NavSatFix, NavSatStatus
from std_msgs.msg import ColorRGBA, Header
from visualization_msgs.msg import Marker, MarkerArray

COLOURS = {'path': (0.1, 0.8, 0.2), 'target': (1.0, 0.2, 0.1), 'estimate': (0.2, 0.5, 1.0),
           'truth': (0.95, 0.95, 0.95), 'covariance': (0.3, 0.9, 1.0), 'gps': (1.0, 0.85, 0.0),
           'x': (1.0, 0.0, 0.0), 'y': (0.0, 1.0, 0.0), 'z': (0.0, 0.0, 1.0)}
ELLIPSE_POINTS = 48   # points around the covariance ellipse


def _colour(name: str, alpha: float = 1.0) -> ColorRGBA:
    r, g, b = COLOURS[name]
    return ColorRGBA(r=r, g=g, b=b, a=alpha)


def _points(xy: ArrayLike) -> list[Point]:
    """Return (n, 2) coordinates [m] as geometry_msgs/Point on the ground (z = 0)."""
    return [Point(x=float(x), y=float(y)) for x, y in np.asarray(xy, dtype=np.float64)]


def _finite(name: str, values: ArrayLike) -> NDArray[np.float64]:
    array = np.asarray(values, dtype=np.float64)
    if not np.isfinite(array).all():
        raise ValueError(f'{name} must be finite, got {array.tolist()}')
    return array


def _planar_pose(msg: Odometry) -> Pose:
    """Return the planar pose of an Odometry (x, y, yaw; a clean unit quaternion)."""
    p = msg.pose.pose
    x, y, yaw = _finite('pose', [p.position.x, p.position.y, quaternion_to_yaw(p.orientation)])
    return Pose(position=Point(x=float(x), y=float(y)), orientation=yaw_to_quaternion(yaw))


class MarkersNode(GuardedNode):
    """Turn a run's topics into markers; the geometry is robotica_kin.marker_geometry's."""

    def __init__(self) -> None:
        super().__init__('markers')
        values = declare_specs(self, MARKERS_PARAMETERS)
        self._arm = declare_robot(self, 'The arm whose reference tool pose is drawn',
                                  joint_names='as in controller_state')
        vehicle_type = values['vehicle.type']
        self._outline = None if not vehicle_type else _points(vehicle_outline(
            vehicle_type, VehicleGeometry(**{name: values[f'vehicle.{name}']
                                             for name in GEOMETRY_PARAMETERS})))
        self._origin = GeodeticOrigin(values['origin.latitude'], values['origin.longitude'],
                                      values['origin.altitude'])
        self._k = values['covariance_k']
        self._width = values['line_width']
        self._axis = values['tool_axis_length']
        self._world_frame = values['world_frame_id']
        self._arm_frame = values['arm_frame_id']
        self._lifetime = seconds_to_stamp(values['marker_lifetime'], Duration)
        self._fixes: deque[tuple[float, float]] = deque(maxlen=values['gps_history'])
        self._markers: dict[tuple[str, int], Marker] = {}
        self._changed: set[tuple[str, int]] = set()
        rate = values['publish_rate']
        self._path_repeat = max(1, math.ceil(rate))   # ticks: the path again once a second
        self._ticks = 0
        self._reference: tuple[Header, NDArray[np.float64]] | None = None   # header, q
        self._pub = self.create_publisher(MarkerArray, 'markers', STREAM_PUB_QOS)
        inputs: list[tuple[Any, str, Callable[[Any], None]]] = [
            (Odometry, 'odom', self._on_odom),
            (Odometry, 'ground_truth/odom', self._on_truth),
            (NavSatFix, 'gps/fix', self._on_fix),
            (TrackingError, 'path_tracker/tracking_error', self._on_tracking_error),
            (JointControllerState, 'joint_controller/controller_state',
             self._on_controller_state)]
        self.create_subscription(Path, 'path', self._on_path, LATCHED_QOS)
        for msg_type, topic, callback in inputs:
            self.create_subscription(msg_type, topic, callback, STREAM_SUB_QOS,
                                     qos_overriding_options=INPUT_QOS_OVERRIDES)
        self.create_timer(1.0 / rate, self._publish)
        self.get_logger().info(f'footprint of {vehicle_type or "no vehicle"!r}, tool pose of '
                               f'{self._arm.name!r}; markers at {rate} Hz')

    # -- markers: built in the callbacks, sent by the timer --------------------------------
    def _set(self, ns: str, marker_id: int, marker_type: int, header: Any, colour: ColorRGBA,
             scale: float, points: list[Point] | None = None, pose: Pose | None = None,
             lifetime: Duration | None = None) -> Marker:
        stamp_to_seconds(header.stamp)   # a malformed stamp is refused here, not at publishing
        marker = Marker(ns=ns, id=marker_id, type=marker_type, action=Marker.ADD, color=colour,
                        points=points or [], pose=pose or Pose(orientation=Quaternion(w=1.0)),
                        lifetime=self._lifetime if lifetime is None else lifetime)
        marker.header.stamp = header.stamp
        marker.header.frame_id = header.frame_id or self._world_frame
        marker.scale.x = marker.scale.y = marker.scale.z = scale
        self._markers[(ns, marker_id)] = marker
        self._changed.add((ns, marker_id))
        return marker

    def _publish(self) -> None:
        self._tool_marker()
        self._ticks += 1
        keys = set(self._changed)
        if self._ticks % self._path_repeat == 0 and ('path', 0) in self._markers:
            keys.add(('path', 0))
        self._changed.clear()
        if keys:
            self._pub.publish(MarkerArray(markers=[self._markers[k] for k in sorted(keys)]))

    # -- inputs ------------------------------------------------------------------------------
    def _on_path(self, msg: Path) -> None:
        points = _finite('path', path_points(msg))
        self._set('path', 0, Marker.LINE_STRIP, msg.header, _colour('path'), self._width,
                  _points(points), lifetime=Duration())

    def _on_odom(self, msg: Odometry) -> None:
        pose = _planar_pose(msg)
        covariance = np.reshape(_finite('covariance', msg.pose.covariance), (6, 6))[:2, :2]
        ellipse = ellipse_polygon(*covariance_ellipse(covariance, self._k), n=ELLIPSE_POINTS)
        self._footprint(0, msg, pose, 'estimate')
        self._set('covariance', 0, Marker.LINE_STRIP, msg.header, _colour('covariance', 0.8),
                  self._width, _points(ellipse), Pose(position=pose.position,
                                                      orientation=Quaternion(w=1.0)))

    def _on_truth(self, msg: Odometry) -> None:
        self._footprint(1, msg, _planar_pose(msg), 'truth')

    def _footprint(self, marker_id: int, msg: Odometry, pose: Pose, colour: str) -> None:
        if self._outline is not None:
            self._set('footprint', marker_id, Marker.LINE_STRIP, msg.header, _colour(colour),
                      self._width, self._outline, pose)

    def _on_fix(self, msg: NavSatFix) -> None:
        if msg.status.status == NavSatStatus.STATUS_NO_FIX:
            return
        east, north, _ = _finite('fix in ENU', self._origin.geodetic_to_enu(
            bounded('latitude', msg.latitude, MAX_LATITUDE),
            bounded('longitude', msg.longitude, MAX_LONGITUDE), msg.altitude))
        stamp_to_seconds(msg.header.stamp)
        self._fixes.append((float(east), float(north)))
        header = Header(stamp=msg.header.stamp, frame_id=self._world_frame)
        self._set('gps', 0, Marker.POINTS, header, _colour('gps'), 3.0 * self._width,
                  _points(list(self._fixes)))

    def _on_tracking_error(self, msg: TrackingError) -> None:
        p = msg.target_point
        x, y, z = _finite('target_point', [p.x, p.y, p.z])
        self._set('target', 0, Marker.SPHERE, msg.header, _colour('target'), 5.0 * self._width,
                  pose=Pose(position=Point(x=float(x), y=float(y), z=float(z)),
                            orientation=Quaternion(w=1.0)))

    def _on_controller_state(self, msg: JointControllerState) -> None:
        names = list(msg.joint_names) or list(self._arm.joint_names)
        if len(names) != len(msg.reference_position) or len(set(names)) != len(names):
            raise ValueError(f'controller state with {len(names)} joint names and '
                             f'{len(msg.reference_position)} reference positions')
        missing = [name for name in self._arm.joint_names if name not in names]
        if missing:
            raise ValueError(f'controller state without the joints {missing}')
        q = bounded_array('reference_position', [msg.reference_position[names.index(name)]
                                                 for name in self._arm.joint_names],
                          MAX_JOINT_POSITION)
        stamp_to_seconds(msg.header.stamp)
        self._reference = (Header(stamp=msg.header.stamp, frame_id=self._arm_frame), q)

    def _tool_marker(self) -> None:
        """Set the tool marker from the newest reference (at the publishing rate: 1 kHz arms)."""
        if self._reference is None:
            return
        header, q = self._reference
        self._reference = None
        length = self._axis
        triad = [Point(), Point(x=length), Point(), Point(y=length), Point(), Point(z=length)]
        marker = self._set('tool', 0, Marker.LINE_LIST, header, _colour('x'), self._width,
                           triad, pose_message(_finite('tool pose', fkine(self._arm, q))))
        marker.colors = [_colour(axis) for axis in ('x', 'x', 'y', 'y', 'z', 'z')]


def main(args=None) -> None:
    """Run the markers node until Ctrl-C."""
    run_node(MarkersNode, args, executor_factory=EventsExecutor)
