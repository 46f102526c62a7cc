"""
Inverse-kinematics server: the ``~/inverse_kinematics`` service (HEMERO ``ikine``, book §4.4).

Each ``robotica_msgs/InverseKinematics`` request is solved numerically by
:func:`robotica_kin.ik.ikine_solve` for the robot it names (``robot``), else the DH table it
carries (``dh``), else the node's robot (parameters ``robot`` or ``dh_table``). Zero ``stol``
and ``ilimit`` mean the defaults 1e-6 and 1000; an empty ``q0`` or ``mask`` means the solver's
default. A solver that does not converge answers ``converged = false`` with its last iterate and
a message; bad input (unknown robot, NaN, wrong sizes, a non-unit quaternion, an ``ilimit``
outside [0, ``MAX_ILIMIT``], an ``stol`` above ``MAX_STOL``, a table of more than
``MAX_JOINTS`` joints) answers ``converged = false``, an empty ``q`` and the reason (cut to
``ERROR_TEXT_LIMIT`` characters). The node never stops on a request, and answers each within
seconds.
"""
import math

from numpy.linalg import LinAlgError
from robotica_kin.ik import ikine_solve
from robotica_kin.ros.dh_messages import declare_robot, pose_matrix, request_robot
from robotica_kin.ros.entry_point import run_node
from robotica_kin.ros.guarded import error_text, GuardedNode
from robotica_msgs.srv import InverseKinematics

DEFAULT_STOL = 1e-6      # pose-error tolerance used when a request gives 0
MAX_STOL = 1.0           # a larger one (1 m, 1 rad) called any start converged (stol = 1e308)
DEFAULT_ILIMIT = 1000    # iterations used when a request gives 0
MAX_ILIMIT = 10_000      # iterations a request may ask for: 1.6 s for 100 joints (2**31 - 1
#                          iterations kept the server from answering anyone for hours)


def _solver_options(request: InverseKinematics.Request) -> dict:
    """Return the keyword arguments of ``ikine_solve`` for a request, or raise ValueError."""
    if not (math.isfinite(request.stol) and 0.0 <= request.stol <= MAX_STOL):
        raise ValueError(f'stol must be in [0, {MAX_STOL}] (0: {DEFAULT_STOL}), got '
                         f'{request.stol}')
    if not 0 <= request.ilimit <= MAX_ILIMIT:
        raise ValueError(f'ilimit must be in [0, {MAX_ILIMIT}] (0: {DEFAULT_ILIMIT}), got '
                         f'{request.ilimit}')
    return {'stol': request.stol or DEFAULT_STOL,
            'ilimit': request.ilimit or DEFAULT_ILIMIT,
            'q0': list(request.q0) or None,
            'mask': list(request.mask) or None}


class InverseKinematicsServer(GuardedNode):
    """ROS shell around :func:`robotica_kin.ik.ikine_solve`."""

    def __init__(self) -> None:
        super().__init__('ik_server')
        self._robot = declare_robot(self, 'Default robot of the requests')
        self.create_service(InverseKinematics, '~/inverse_kinematics', self._on_request)
        self.get_logger().info(f'default robot {self._robot.name!r} ({self._robot.n} joints)')

    def _on_request(self, request: InverseKinematics.Request,
                    response: InverseKinematics.Response) -> InverseKinematics.Response:
        self.get_logger().debug(f'inverse_kinematics request: {request}')
        try:
            robot = request_robot(request.robot, request.dh, self._robot)
            options = _solver_options(request)
            result = ikine_solve(robot, pose_matrix(request.pose), **options)
        except (ValueError, LinAlgError) as err:
            response.converged = False
            response.message = error_text(err)
            self.get_logger().warn(f'inverse_kinematics refused: {response.message}')
            return response
        response.q = [float(v) for v in result.q]
        response.converged = bool(result.success)
        response.iterations = int(result.iterations)
        response.residual = float(result.residual)
        if not response.converged:
            stol = options['stol']
            response.message = (f'no solution within the joint limits: residual '
                                f'{response.residual:.3g} after {response.iterations} '
                                f'iterations (stol {stol:g}); q is the last iterate')
            self.get_logger().warn(f'inverse_kinematics for {robot.name!r}: '
                                   f'{response.message}')
        return response


def main(args=None) -> None:
    """Run the inverse-kinematics server until Ctrl-C."""
    run_node(InverseKinematicsServer, args)
