"""
URDF descriptions generated from the models: an arm from its DH table, a vehicle from its geometry.

A viewer (RViz, Foxglove) or a URDF consumer (``robot_state_publisher``, Pinocchio, a
simulator) reads a robot as links joined by joints, each joint placed in its parent link by a
fixed ``<origin>`` and moving about or along its ``<axis>``. Craig's modified DH (book §4.3,
Table 4.2) maps onto that exactly:

- link ``link_i`` is Craig's frame {i} (``link_0`` the base frame {0}), the frames of
  :mod:`robotica_kin.pinocchio_model`; ``tool0`` is the tool frame (``DHModel.tool``) on a fixed
  joint, the frame of ``fkine``;
- joint i (named as the robot's joint) has parent ``link_{i-1}``, child ``link_i``, axis z and
  origin ``Rot(X, alpha_{i-1}) Tras(X, a_{i-1})`` times the row's constant part: ``Tras(Z, d_i)``
  for a revolute joint (sigma_i = 0), ``Rot(Z, theta_i)`` for a prismatic one. The moving part,
  ``Rot(Z, q_i)`` or ``Tras(Z, q_i)``, is the joint itself, so the chain is (4.6) for every q;
  as in HEMERO, theta_i of a revolute row and d_i of a prismatic row are not used;
- ``<limit>`` carries ``qlim`` and the effort [N m or N] and velocity [rad/s or m/s] limits given,
  else the physical bounds of :mod:`robotica_kin.bounds` (no robot of the book states them);
- ``<inertial>`` of ``link_i`` is row i of HEMERO's ``dyn`` table (book §A.3): the mass, the
  centre of mass in frame {i} and the inertia tensor about it in frame {i}'s axes. The motor
  inertia J_m G² (Pinocchio's ``armature`` in :func:`~robotica_kin.pinocchio_model.build_model`)
  has no URDF element and is left out;
- the visuals are grey cylinders along each link (from a frame's origin to the next one's),
  orange cylinders on the joint axes, a blue plinth under ``link_0`` and a red-green-blue axis
  triad at ``tool0``.

A vehicle's URDF (:func:`vehicle_urdf`) has ``base_link`` on the ground under the guide point of
:mod:`robotica_kin.mobile.vehicles` (REP-105: x forward, y left, z up), a body box or disc, the
wheels as cylinders on ``continuous`` joints (axis: a positive rate drives the contact point the
way the kinematic model's positive wheel speed does) and, for the steered types, the steering
joints that :meth:`~robotica_kin.mobile.vehicles.VehicleKinematics.joint_positions` publishes.
The odometry wheels are named as the simulator publishes them,
``VehicleKinematics.odometry_wheel_joints`` of :mod:`robotica_kin.mobile.vehicles` (one naming
for both); a vehicle with no wheels of its own on the guide axle gets them as passive measuring
wheels there. The sensor frames are fixed children of ``base_link`` with its axes:
``imu_link`` over the guide point at ``imu_height`` and ``gps_link``, the antenna, over it at
``antenna_height`` (the GPS emulator's parameter: its fixes are of the guide point raised by that
height, so the frame sits where the emulated antenna is); both at the guide point because the
emulators measure there (no lever arm is simulated: the gyro reads the body's yaw rate, the same
everywhere on a rigid planar body, in ``base_link`` axes, which the IMU's axes are taken to be).

:data:`ROBOT_DESCRIPTION_PARAMETERS` are the state publisher's parameters that choose a vehicle
(``vehicle.type`` and the geometry under the simulator's names, so one parameter file serves
both, and the sensor heights); :func:`robot_description` builds the URDF they choose.
"""

import math
from typing import Any, Mapping
import xml.etree.ElementTree as ElementTree

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotica_kin.bounds import MAX_FORCE_TORQUE, MAX_JOINT_VELOCITY
from robotica_kin.dh import as_dyn_model, dh_model, DHModel, linktrans
from robotica_kin.finite import finite_real
from robotica_kin.mobile.vehicles import (GEOMETRY_PARAMETERS, vehicle_kinematics, VEHICLE_TYPES,
                                          VehicleGeometry)
from robotica_kin.parameter_specs import parameter_values, ParameterSpec
from robotica_kin.transforms import rpy2tr, tr2rpy

__all__ = ['ANTENNA_HEIGHT', 'IMU_HEIGHT', 'ROBOT_DESCRIPTION_PARAMETERS',
           'SENSOR_FRAME_PARAMETERS', 'arm_urdf', 'robot_description', 'vehicle_urdf']

IMU_HEIGHT = 0.1       # [m] imu_link over the guide point: mid-body at the default wheel radius
ANTENNA_HEIGHT = 0.0   # [m] gps_link over the guide point: the GPS emulator's default
SENSOR_FRAME_PARAMETERS: dict[str, ParameterSpec] = {
    'imu_height': ParameterSpec(IMU_HEIGHT, 'Height of imu_link over the guide point [m] '
                                '(base_link axes)', 0.0, 100.0),
    'antenna_height': ParameterSpec(ANTENNA_HEIGHT, 'Antenna height above the ground plane [m]',
                                    0.0, 100.0),
}
"""Where the sensor frames are: the vehicle URDF's and the GPS emulator's antenna height."""
ROBOT_DESCRIPTION_PARAMETERS: dict[str, ParameterSpec] = {
    'vehicle.type': ParameterSpec('', "Vehicle to describe; '': the arm of robot or dh_table",
                                  choices=('',) + VEHICLE_TYPES),
    **{f'vehicle.{name}': spec for name, spec in GEOMETRY_PARAMETERS.items()},
    **SENSOR_FRAME_PARAMETERS,
}
"""The state publisher's choice of a vehicle: the simulator's names and ranges, the sensors'."""

_MATERIALS = {'link': '0.6 0.6 0.6 1', 'joint': '1.0 0.5 0.0 1', 'body': '0.2 0.3 0.6 1',
              'wheel': '0.1 0.1 0.1 1', 'x_axis': '1 0 0 1', 'y_axis': '0 1 0 1',
              'z_axis': '0 0 1 1', 'sensor': '0.9 0.8 0.1 1'}
_INERTIA_TOL = 1e-12   # relative: an eigenvalue of the inertia tensor below -tol * its size fails


def _number(value: float) -> str:
    """Return ``value`` as the shortest text that reads back as the same float."""
    return repr(float(value) + 0.0)   # + 0.0 turns -0.0 into 0.0


def _vector(values: ArrayLike) -> str:
    return ' '.join(_number(v) for v in np.asarray(values, dtype=np.float64))


def _origin(parent: ElementTree.Element, T: NDArray[np.float64]) -> None:
    """Append ``<origin xyz rpy>`` of the transform T (URDF's rpy: R = Rz(y) Ry(p) Rx(r))."""
    ElementTree.SubElement(parent, 'origin', xyz=_vector(T[:3, 3]), rpy=_vector(tr2rpy(T)))


def _transform(xyz: ArrayLike, rpy: ArrayLike = (0.0, 0.0, 0.0)) -> NDArray[np.float64]:
    """Return the 4x4 transform of URDF's ``xyz``, ``rpy`` (roll, pitch, yaw about fixed axes)."""
    T = rpy2tr(rpy)
    T[:3, 3] = xyz
    return T


def _robot(name: str) -> ElementTree.Element:
    robot = ElementTree.Element('robot', name=name)
    for material, rgba in _MATERIALS.items():
        ElementTree.SubElement(ElementTree.SubElement(robot, 'material', name=material), 'color',
                               rgba=rgba)
    return robot


def _visual(link: ElementTree.Element, T: NDArray[np.float64], material: str,
            shape: str, **size: Any) -> None:
    """Append a visual of ``shape`` (cylinder along its z, box, sphere) placed at T in the link."""
    visual = ElementTree.SubElement(link, 'visual')
    _origin(visual, T)
    geometry = ElementTree.SubElement(visual, 'geometry')
    if shape == 'box':
        ElementTree.SubElement(geometry, 'box', size=_vector(size['size']))
    else:
        ElementTree.SubElement(geometry, shape, {k: _number(v) for k, v in size.items()})
    ElementTree.SubElement(visual, 'material', name=material)


def _rod(link: ElementTree.Element, start: ArrayLike, end: ArrayLike, radius: float,
         material: str) -> None:
    """Append a cylinder of ``radius`` from point ``start`` to point ``end`` [m] of the link."""
    p0, p1 = np.asarray(start, dtype=np.float64), np.asarray(end, dtype=np.float64)
    u = p1 - p0
    length = float(np.linalg.norm(u))
    if length <= 1e-9:
        return
    pitch = math.atan2(math.hypot(u[0], u[1]), u[2])   # Rz(yaw) Ry(pitch) takes z onto u
    yaw = math.atan2(u[1], u[0])
    _visual(link, _transform(0.5 * (p0 + p1), (0.0, pitch, yaw)), material, 'cylinder',
            radius=radius, length=length)


def _joint(robot: ElementTree.Element, name: str, kind: str, parent: str, child: str,
           T: NDArray[np.float64], axis: ArrayLike | None = None) -> ElementTree.Element:
    joint = ElementTree.SubElement(robot, 'joint', name=name, type=kind)
    _origin(joint, T)
    ElementTree.SubElement(joint, 'parent', link=parent)
    ElementTree.SubElement(joint, 'child', link=child)
    if axis is not None:
        ElementTree.SubElement(joint, 'axis', xyz=_vector(axis))
    return joint


def _text(robot: ElementTree.Element) -> str:
    ElementTree.indent(robot)
    return '<?xml version="1.0"?>\n' + ElementTree.tostring(robot, encoding='unicode') + '\n'


def _arm_model(robot: DHModel | ArrayLike) -> DHModel:
    """Return ``robot`` as a DHModel; a raw DH or dyn table's bad row is named in the error."""
    if isinstance(robot, DHModel):
        return robot
    try:
        table = np.array(robot, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise ValueError(f'the DH or dyn table must be a numeric (n, 4), (n, 5) or (n, 20) '
                         f'table: {error}') from None
    if table.ndim != 2 or table.shape[1] not in (4, 5, 20) or table.shape[0] == 0:
        raise ValueError(f'the DH or dyn table must have shape (n, 4), (n, 5) or (n, 20), got '
                         f'{table.shape}')
    what = 'dyn' if table.shape[1] == 20 else 'DH'
    for i, row in enumerate(table):
        if not np.all(np.isfinite(row)):
            raise ValueError(f'{what} table row {i + 1} has a non-finite entry: {row.tolist()}')
    return as_dyn_model(table) if what == 'dyn' else dh_model(table)


def _check_dyn(model: DHModel) -> NDArray[np.float64]:
    """Return the model's dyn table after checking that each row is a physical body."""
    assert model.dyn is not None
    for i, row in enumerate(model.dyn):
        where = f'dyn table row {i + 1} ({model.joint_names[i]})'
        if row[5] < 0.0:
            raise ValueError(f'{where}: the mass must be >= 0 kg, got {row[5]!r}')
        ixx, iyy, izz, ixy, iyz, ixz = row[9:15]
        inertia = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        eigenvalues = np.linalg.eigvalsh(inertia)
        if eigenvalues[0] < -_INERTIA_TOL * max(1.0, float(np.abs(eigenvalues).max())):
            raise ValueError(f'{where}: the inertia tensor must be positive semi-definite, its '
                             f'eigenvalues are {eigenvalues.tolist()} kg m^2')
    return model.dyn


def _limits(values: ArrayLike | None, default: float, model: DHModel,
            name: str) -> NDArray[np.float64]:
    if values is None:
        return np.full(model.n, default)
    limits = np.asarray(values, dtype=np.float64)
    if limits.shape != (model.n,):
        raise ValueError(f'{name} must have one value per joint ({model.n},), got shape '
                         f'{limits.shape}')
    for joint, value in zip(model.joint_names, limits):
        if not (math.isfinite(value) and value > 0.0):
            raise ValueError(f'{name} of {joint} must be finite and > 0, got {value!r}')
    return limits


def arm_urdf(robot: DHModel | ArrayLike, *, effort: ArrayLike | None = None,
             velocity: ArrayLike | None = None, link_radius: float | None = None) -> str:
    """
    Return the URDF (XML text) of a manipulator given by Craig's modified DH table.

    The mapping (links = Craig's frames {i}, joint origins, limits, inertials from ``dyn``,
    visuals) is the module's; a robot without a ``dyn`` table gets no ``<inertial>``.

    Parameters
    ----------
    robot : DHModel or array_like
        The robot, or a raw HEMERO table: DH (n, 4) / (n, 5) or dyn (n, 20) (book §A.3).
    effort : array_like, shape (n,), optional
        Joint effort limits [N m or N], > 0; default :data:`~robotica_kin.bounds.MAX_FORCE_TORQUE`.
    velocity : array_like, shape (n,), optional
        Joint velocity limits [rad/s or m/s], > 0; default
        :data:`~robotica_kin.bounds.MAX_JOINT_VELOCITY`.
    link_radius : float, optional
        Radius [m] of the drawn links; default 3 % of the summed link lengths and offsets.

    Returns
    -------
    str
        The URDF, ``<robot name="...">`` with the robot's name.

    Raises
    ------
    ValueError
        For a malformed table (naming the non-finite row), a dyn row that is not a body
        (negative mass, inertia tensor not positive semi-definite; the row is named), or bad
        limits or radius.

    Examples
    --------
    >>> from robotica_kin.robots import planar_rr
    >>> text = arm_urdf(planar_rr())
    >>> root = ElementTree.fromstring(text)
    >>> [(j.get('name'), j.get('type')) for j in root.iter('joint')]
    [('joint_1', 'revolute'), ('joint_2', 'revolute'), ('tool0_joint', 'fixed')]
    >>> arm_urdf([[0, 0, 0, 0], [0, 1.0, float('nan'), 0]])
    Traceback (most recent call last):
    ...
    ValueError: DH table row 2 has a non-finite entry: [0.0, 1.0, nan, 0.0]

    """
    model = _arm_model(robot)
    dyn = None if model.dyn is None else _check_dyn(model)
    efforts = _limits(effort, MAX_FORCE_TORQUE, model, 'effort')
    velocities = _limits(velocity, MAX_JOINT_VELOCITY, model, 'velocity')
    placements = [linktrans(model.alpha[i], model.a[i], model.theta[i] if model.prismatic[i]
                            else 0.0, 0.0 if model.prismatic[i] else model.d[i])
                  for i in range(model.n)]
    if link_radius is None:
        size = float(np.sum(np.abs(model.a)) + np.sum(np.abs(model.d[~model.prismatic]))
                     + np.linalg.norm(model.tool[:3, 3]))
        link_radius = max(0.03 * size, 0.005)
    elif not (math.isfinite(link_radius) and link_radius > 0.0):
        raise ValueError(f'link_radius must be finite and > 0 m, got {link_radius!r}')
    urdf = _robot(model.name)
    links = [ElementTree.SubElement(urdf, 'link', name=f'link_{i}') for i in range(model.n + 1)]
    for i, link in enumerate(links):
        if i > 0 and dyn is not None:
            row = dyn[i - 1]
            inertial = ElementTree.SubElement(link, 'inertial')
            ElementTree.SubElement(inertial, 'origin', xyz=_vector(row[6:9]), rpy='0 0 0')
            ElementTree.SubElement(inertial, 'mass', value=_number(row[5]))
            ixx, iyy, izz, ixy, iyz, ixz = row[9:15]
            ElementTree.SubElement(inertial, 'inertia', ixx=_number(ixx), ixy=_number(ixy),
                                   ixz=_number(ixz), iyy=_number(iyy), iyz=_number(iyz),
                                   izz=_number(izz))
        if i == 0:   # a plinth under the base frame
            _rod(link, (0.0, 0.0, -2.0 * link_radius), (0.0, 0.0, 0.0), 2.5 * link_radius,
                 'body')
        else:
            _rod(link, (0.0, 0.0, -2.0 * link_radius), (0.0, 0.0, 2.0 * link_radius),
                 1.2 * link_radius, 'joint')
            if model.prismatic[i - 1]:   # the slider: its travel behind the moving frame
                travel = float(model.qlim[i - 1, 1] - model.qlim[i - 1, 0])
                _rod(link, (0.0, 0.0, -travel), (0.0, 0.0, 0.0), 0.8 * link_radius, 'link')
        end = model.tool if i == model.n else placements[i]
        _rod(link, (0.0, 0.0, 0.0), end[:3, 3], link_radius, 'link')
    for i in range(model.n):
        joint = _joint(urdf, model.joint_names[i],
                       'prismatic' if model.prismatic[i] else 'revolute', f'link_{i}',
                       f'link_{i + 1}', placements[i], (0.0, 0.0, 1.0))
        ElementTree.SubElement(joint, 'limit', lower=_number(model.qlim[i, 0]),
                               upper=_number(model.qlim[i, 1]), effort=_number(efforts[i]),
                               velocity=_number(velocities[i]))
    tool = ElementTree.SubElement(urdf, 'link', name='tool0')
    for axis, material in enumerate(('x_axis', 'y_axis', 'z_axis')):
        tip = np.zeros(3)
        tip[axis] = 4.0 * link_radius
        _rod(tool, (0.0, 0.0, 0.0), tip, 0.3 * link_radius, material)
    _joint(urdf, 'tool0_joint', 'fixed', f'link_{model.n}', 'tool0', np.asarray(model.tool))
    return _text(urdf)


def _wheel(urdf: ElementTree.Element, name: str, parent: str, xyz: ArrayLike, yaw: float,
           geometry: VehicleGeometry, mimic: str | None = None) -> None:
    """Append a wheel link and its continuous joint (axis y of a frame turned by ``yaw``)."""
    c = geometry.wheel_radius
    link = ElementTree.SubElement(urdf, 'link', name=name.replace('_joint', '_link'))
    _visual(link, _transform((0.0, 0.0, 0.0), (math.pi / 2.0, 0.0, 0.0)), 'wheel', 'cylinder',
            radius=c, length=0.4 * c)
    joint = _joint(urdf, name, 'continuous', parent, link.get('name', ''),
                   _transform(xyz, (0.0, 0.0, yaw)), (0.0, 1.0, 0.0))
    if mimic is not None:
        ElementTree.SubElement(joint, 'mimic', joint=mimic)


def _steering(urdf: ElementTree.Element, name: str, xyz: ArrayLike,
              geometry: VehicleGeometry) -> str:
    """Append a steering joint (revolute about z, ±max_steering_angle); return its link."""
    link = ElementTree.SubElement(urdf, 'link', name=name.replace('_joint', '_link'))
    joint = _joint(urdf, name, 'revolute', 'base_link', link.get('name', ''), _transform(xyz),
                   (0.0, 0.0, 1.0))
    limit = geometry.max_steering_angle
    ElementTree.SubElement(joint, 'limit', lower=_number(-limit), upper=_number(limit),
                           effort=_number(MAX_FORCE_TORQUE), velocity=_number(MAX_JOINT_VELOCITY))
    return link.get('name', '')


def vehicle_urdf(vehicle_type: str, geometry: VehicleGeometry | None = None, *,
                 imu_height: float = IMU_HEIGHT, antenna_height: float = ANTENNA_HEIGHT) -> str:
    """
    Return the URDF (XML text) of a vehicle of :data:`~robotica_kin.mobile.vehicles.VEHICLE_TYPES`.

    ``base_link`` lies on the ground under the guide point; wheel centres are at height c
    (``wheel_radius``). Wheels (continuous joints, axis y of the wheel frame):

    - differential: ``left_wheel_joint``, ``right_wheel_joint`` at (0, ±b/2);
    - skid_steer: the same two, and ``rear_left_wheel_joint``, ``rear_right_wheel_joint``
      (mimicking them) at x = -``half_length``; the front pair at x = +``half_length``;
    - mecanum: ``front_left_wheel_joint`` … ``rear_right_wheel_joint`` at (±half_length, ±b/2);
    - omni_three, synchronous: ``wheel_0_joint`` … ``wheel_2_joint`` at ``base_radius`` and
      angles 0, 120°, 240°; an omni wheel's axle is radial, turned so that a positive rate drives
      the base counter-clockwise, as in :mod:`robotica_kin.mobile.omnidirectional`;
    - tricycle, bicycle: ``steering_joint`` (revolute about z) at (l, 0) carrying
      ``front_wheel_joint``; rear wheels ``left_wheel_joint``, ``right_wheel_joint`` at (0, ±b/2)
      (the bicycle: one ``rear_wheel_joint`` at the origin);
    - ackermann: ``front_left_steering_joint``, ``front_right_steering_joint`` at (l, ±b/2) with
      ``front_left_wheel_joint``, ``front_right_wheel_joint``; rear wheels as the tricycle's;
    - the odometry wheels (``odometry_wheel_joints`` of the type's kinematics, the names of the
      simulator's ``joint_states``) of mecanum, omni_three, synchronous and bicycle, which have no
      wheels of their own there: ``left_odometry_wheel_joint``, ``right_odometry_wheel_joint``
      at (0, ±b/2).

    Sensor frames (fixed joints ``imu_joint``, ``gps_joint``, axes of ``base_link``):
    ``imu_link`` at (0, 0, ``imu_height``), ``gps_link`` at (0, 0, ``antenna_height``) [m].

    Raises
    ------
    ValueError
        For an unknown type (the message lists the known ones), a ``geometry`` that is not a
        :class:`~robotica_kin.mobile.vehicles.VehicleGeometry` or a sensor height that is not
        finite and >= 0.

    Examples
    --------
    >>> root = ElementTree.fromstring(vehicle_urdf('differential'))
    >>> sorted(j.get('name') for j in root.iter('joint'))
    ['gps_joint', 'imu_joint', 'left_wheel_joint', 'right_wheel_joint']

    """
    if vehicle_type not in VEHICLE_TYPES:
        raise ValueError(f'unknown vehicle type {vehicle_type!r}; known: {VEHICLE_TYPES}')
    if geometry is None:
        geometry = VehicleGeometry()
    elif not isinstance(geometry, VehicleGeometry):
        raise ValueError(f'geometry must be a VehicleGeometry, got {type(geometry).__name__}')
    heights = {'imu': finite_real('imu_height', imu_height),
               'gps': finite_real('antenna_height', antenna_height)}
    for sensor, height in heights.items():
        if height < 0.0:
            raise ValueError(f'{"imu_height" if sensor == "imu" else "antenna_height"} must be '
                             f'>= 0 m, got {height!r}')
    c, half_b, half_l = geometry.wheel_radius, 0.5 * geometry.track, geometry.half_length
    l, width = geometry.wheelbase, max(geometry.track - 0.6 * c, 0.5 * geometry.track)
    urdf = _robot(f'{vehicle_type}_vehicle')
    base = ElementTree.SubElement(urdf, 'link', name='base_link')
    body = _transform((0.0, 0.0, c))
    wheels: list[tuple[Any, ...]] = []
    if vehicle_type in ('differential', 'skid_steer', 'mecanum'):
        _visual(base, body, 'body', 'box', size=(2.0 * half_l, width, c))
        if vehicle_type == 'differential':
            _visual(base, _transform((-0.8 * half_l, 0.0, 0.25 * c)), 'wheel', 'sphere',
                    radius=0.25 * c)   # the caster
            wheels = [('left_wheel_joint', (0.0, half_b, c)),
                      ('right_wheel_joint', (0.0, -half_b, c))]
        elif vehicle_type == 'skid_steer':
            wheels = [('left_wheel_joint', (half_l, half_b, c)),
                      ('right_wheel_joint', (half_l, -half_b, c)),
                      ('rear_left_wheel_joint', (-half_l, half_b, c), 'left_wheel_joint'),
                      ('rear_right_wheel_joint', (-half_l, -half_b, c), 'right_wheel_joint')]
        else:
            wheels = [(f'{x_name}_{y_name}_wheel_joint', (x, y, c))
                      for x_name, x in (('front', half_l), ('rear', -half_l))
                      for y_name, y in (('left', half_b), ('right', -half_b))]
        for name, xyz, *mimic in wheels:
            _wheel(urdf, name, 'base_link', xyz, 0.0, geometry, *mimic)
    elif vehicle_type in ('omni_three', 'synchronous'):
        radius = geometry.base_radius
        _visual(base, body, 'body', 'cylinder', radius=max(radius - 0.3 * c, 0.5 * radius),
                length=c)
        for k in range(3):
            beta = 2.0 * math.pi * k / 3.0
            xyz = (radius * math.cos(beta), radius * math.sin(beta), c)
            # An omni wheel drives along d = (-sin β, cos β): its frame's y axis is -radial.
            # Synchronous wheels all point along the heading (the model's body turns with them).
            yaw = beta + math.pi / 2.0 if vehicle_type == 'omni_three' else 0.0
            _wheel(urdf, f'wheel_{k}_joint', 'base_link', xyz, yaw, geometry)
    else:
        _visual(base, _transform((0.5 * l, 0.0, c)), 'body', 'box',
                size=(l + 2.0 * c, width if vehicle_type != 'bicycle' else 0.6 * c, c))
        if vehicle_type == 'ackermann':
            for side, y in (('left', half_b), ('right', -half_b)):
                steer = _steering(urdf, f'front_{side}_steering_joint', (l, y, c), geometry)
                _wheel(urdf, f'front_{side}_wheel_joint', steer, (0.0, 0.0, 0.0), 0.0, geometry)
        else:
            steer = _steering(urdf, 'steering_joint', (l, 0.0, c), geometry)
            _wheel(urdf, 'front_wheel_joint', steer, (0.0, 0.0, 0.0), 0.0, geometry)
        if vehicle_type == 'bicycle':
            _wheel(urdf, 'rear_wheel_joint', 'base_link', (0.0, 0.0, c), 0.0, geometry)
        else:
            _wheel(urdf, 'left_wheel_joint', 'base_link', (0.0, half_b, c), 0.0, geometry)
            _wheel(urdf, 'right_wheel_joint', 'base_link', (0.0, -half_b, c), 0.0, geometry)
    wheel_joints = {joint.get('name') for joint in urdf.iter('joint')}
    odometry_wheels = vehicle_kinematics(vehicle_type, geometry).odometry_wheel_joints
    for name, y in zip(odometry_wheels, (half_b, -half_b)):
        if name not in wheel_joints:   # measuring wheels under the guide point
            _wheel(urdf, name, 'base_link', (0.0, y, c), 0.0, geometry)
    for sensor, height in heights.items():   # a small box for the IMU, a disc for the antenna
        link = ElementTree.SubElement(urdf, 'link', name=f'{sensor}_link')
        if sensor == 'imu':
            _visual(link, np.eye(4), 'sensor', 'box', size=(0.4 * c, 0.4 * c, 0.2 * c))
        else:
            _visual(link, np.eye(4), 'sensor', 'cylinder', radius=0.4 * c, length=0.1 * c)
        _joint(urdf, f'{sensor}_joint', 'fixed', 'base_link', link.get('name', ''),
               _transform((0.0, 0.0, height)))
    return _text(urdf)


def robot_description(parameters: Mapping[str, Any], arm: DHModel) -> str:
    """
    Return the URDF that a state publisher's ``parameters`` choose.

    ``parameters`` maps names of :data:`ROBOT_DESCRIPTION_PARAMETERS` (missing ones take their
    defaults, others are ignored): ``vehicle.type`` '' describes ``arm`` (:func:`arm_urdf`),
    else that vehicle with the geometry ``vehicle.*`` and the sensor heights
    (:func:`vehicle_urdf`).

    Raises
    ------
    ValueError
        :class:`~robotica_kin.parameter_specs.ParameterError` for a value out of its range or
        choices, or as :func:`arm_urdf` and :func:`vehicle_urdf`.

    Examples
    --------
    >>> from robotica_kin.robots import planar_rr
    >>> text = robot_description({'vehicle.type': 'bicycle'}, planar_rr())
    >>> ElementTree.fromstring(text).get('name')
    'bicycle_vehicle'
    >>> ElementTree.fromstring(robot_description({}, planar_rr())).get('name')
    'planar_rr'

    """
    values = parameter_values(ROBOT_DESCRIPTION_PARAMETERS, parameters)
    if not values['vehicle.type']:
        return arm_urdf(arm)
    geometry = VehicleGeometry(**{name: values[f'vehicle.{name}'] for name in GEOMETRY_PARAMETERS})
    return vehicle_urdf(values['vehicle.type'], geometry, imu_height=values['imu_height'],
                        antenna_height=values['antenna_height'])
