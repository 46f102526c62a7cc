"""
Node tests of planner: a path on the world model, a new goal replans, no path stops, bad input.

The world is a room of 4 x 4 m with a wall from (2, 0) to (2, 3): from (1, 1) to (3, 1) the
path must go round the wall's free end at y = 3, so it is longer than 2 * 2 m, and every pose of
it keeps the robot's radius from the wall (checked here with the wall's own geometry).
"""
import math

from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import OccupancyGrid, Path
import numpy as np
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_kin.ros.hostile import fuzz
from robotica_msgs.msg import PlanStatus

pytestmark = pytest.mark.ros
LATCHED = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
ROOM = ('world:\n  walls: [[0, 0, 4, 0], [4, 0, 4, 4], [4, 4, 0, 4], [0, 4, 0, 0], '
        '[2, 0, 2, 3]]\n')


@pytest.fixture
def world(tmp_path):
    path = tmp_path / 'room.yaml'
    path.write_text(ROOM)
    return str(path)


def _listen(node):
    plans, statuses = [], []
    node.create_subscription(Path, 'plan', plans.append, LATCHED)
    node.create_subscription(PlanStatus, '/planner/status', statuses.append, LATCHED)
    return plans, statuses


def _points(path: Path) -> np.ndarray:
    return np.array([[p.pose.position.x, p.pose.position.y] for p in path.poses])


def _wall_distance(points: np.ndarray) -> np.ndarray:
    """Return each point's distance [m] to the segment (2, 0)-(2, 3), by plain geometry."""
    nearest_y = np.clip(points[:, 1], 0.0, 3.0)
    return np.hypot(points[:, 0] - 2.0, points[:, 1] - nearest_y)


def test_plans_round_the_wall_and_replans_for_a_new_goal(start_node, ros_node, spin, world):
    node, executor = ros_node
    start_node('robotica_ctrl', 'planner', '-p', f'world_file:={world}', '-p',
               'start:=[1.0, 1.0]', '-p', 'goal:=[3.0, 1.0]', '-p', 'robot_radius:=0.2')
    plans, statuses = _listen(node)
    assert spin(executor, lambda: plans and statuses)
    points = _points(plans[-1])
    assert points[0] == pytest.approx([1.0, 1.0], abs=0.05)
    assert points[-1] == pytest.approx([3.0, 1.0], abs=0.05)
    assert points[:, 1].max() > 3.0                       # round the wall's end
    assert _wall_distance(points).min() >= 0.2 - 1e-9     # the robot's radius kept
    length = float(np.sum(np.hypot(*np.diff(points, axis=0).T)))
    assert statuses[-1].found and statuses[-1].cost == pytest.approx(length, rel=1e-6)
    assert length > 4.0
    goal = PoseStamped()
    goal.header.frame_id = 'map'
    goal.pose.position.x, goal.pose.position.y = 1.0, 3.5
    goal.pose.orientation.w = 1.0
    pub = node.create_publisher(PoseStamped, 'goal_pose', 10)   # volatile, as RViz's tool
    assert spin(executor, lambda: pub.get_subscription_count() > 0)
    pub.publish(goal)
    assert spin(executor, lambda: len(plans) >= 2 and len(statuses) >= 2)
    assert _points(plans[-1])[-1] == pytest.approx([1.0, 3.5], abs=0.05)
    assert statuses[-1].goal.position.y == pytest.approx(3.5)


@pytest.mark.parametrize('goal, reason', [
    ('[2.0, 1.0]', 'the goal is in an obstacle: (2, 1) m'),
    ('[9.0, 1.0]', 'is off the map'),
])
def test_no_path_is_an_empty_plan_and_the_reason(start_node, ros_node, spin, read_output, world,
                                                 goal, reason):
    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'planner', '-p', f'world_file:={world}', '-p',
                      'start:=[1.0, 1.0]', '-p', f'goal:={goal}')
    plans, statuses = _listen(node)
    assert spin(executor, lambda: plans and statuses)
    assert plans[-1].poses == [] and plans[-1].header.frame_id == 'map'   # the tracker stops
    assert not statuses[-1].found and reason in statuses[-1].reason
    assert spin(executor, lambda: 'no path' in read_output(proc))
    assert proc.poll() is None


def test_the_search_bound_is_reported(start_node, ros_node, spin, world):
    node, executor = ros_node
    start_node('robotica_ctrl', 'planner', '-p', f'world_file:={world}', '-p',
               'start:=[1.0, 1.0]', '-p', 'goal:=[3.0, 1.0]', '-p', 'max_expansions:=10')
    plans, statuses = _listen(node)
    assert spin(executor, lambda: statuses)
    assert not statuses[-1].found and statuses[-1].budget_exhausted
    assert statuses[-1].expansions == 10


def test_plans_on_the_map_topic_without_a_world_file(start_node, ros_node, spin):
    node, executor = ros_node
    start_node('robotica_ctrl', 'planner', '-p', 'start:=[0.25, 0.25]', '-p',
               'goal:=[1.75, 0.25]', '-p', 'robot_radius:=0.0')
    plans, statuses = _listen(node)
    grid = OccupancyGrid()
    grid.header.frame_id = 'map'
    grid.info.resolution, grid.info.width, grid.info.height = 0.5, 4, 4
    grid.info.origin.orientation.w = 1.0
    cells = np.zeros((4, 4), dtype=np.int8)
    cells[0:3, 2] = 100   # a wall in column 2, rows 0-2: round it through row 3
    grid.data = cells.ravel().tolist()
    node.create_publisher(OccupancyGrid, '/map', LATCHED).publish(grid)
    assert spin(executor, lambda: plans and statuses)
    assert statuses[-1].found, statuses[-1].reason
    assert _points(plans[-1])[:, 1].max() > 1.5   # through the free top row


def test_hostile_goals_and_poses_do_not_kill_it(start_node, ros_node, fuzz_survived, world):
    import random
    from nav_msgs.msg import Odometry

    def odom(t):
        msg = Odometry()
        msg.header.frame_id = 'map'
        msg.pose.pose.position.x, msg.pose.pose.position.y = 1.0, 1.0
        msg.pose.pose.orientation.w = 1.0
        return msg

    def goal(t):
        msg = PoseStamped()
        msg.header.frame_id = 'map'
        msg.pose.position.x, msg.pose.position.y = 3.0, 1.0 + 0.001 * (t % 1.0)
        msg.pose.orientation.w = 1.0
        return msg

    node, executor = ros_node
    proc = start_node('robotica_ctrl', 'planner', '-p', f'world_file:={world}', '-p',
                      'max_seconds:=0.5')
    received, ok = fuzz(node, executor, {'odom': (Odometry, odom),
                                         'goal_pose': (PoseStamped, goal)},
                        {'plan': Path}, lambda got: any(m.poses for m in got['plan'][-5:]),
                        random.Random('planner-16'), count=40)
    fuzz_survived(proc, received, ok)


@pytest.mark.parametrize('arguments, reason', [
    (('-p', 'world_file:=/no/such/world.yaml'), 'world.yaml'),
    (('-p', 'method:=rrt'), 'method'),
    (('-p', 'goal:=[1.0, 2.0, 3.0, 4.0]'), 'goal'),
    (('-p', 'start:=[1e300, 0.0]'), 'start'),
    (('-p', 'neighbours:=12'), 'neighbours must be 8 or 16'),
])
def test_bad_parameters_are_refused(start_node, read_output, arguments, reason):
    proc = start_node('robotica_ctrl', 'planner', *arguments)
    assert proc.wait(timeout=30) == 2
    text = read_output(proc)
    assert reason in text and 'Traceback' not in text


def test_distance_helper_is_right():
    # The independent check above: a point above the wall's end, one beside it.
    assert _wall_distance(np.array([[2.0, 4.0], [1.0, 1.0]])).tolist() == [1.0, 1.0]
    assert math.isclose(_wall_distance(np.array([[3.0, 4.0]]))[0], math.sqrt(2.0))


def test_a_curvature_bound_gives_clothoid_turns(start_node, ros_node, spin, world):
    node, executor = ros_node
    start_node('robotica_ctrl', 'planner', '-p', f'world_file:={world}', '-p',
               'start:=[1.0, 1.0]', '-p', 'goal:=[3.0, 1.0]', '-p', 'robot_radius:=0.2',
               '-p', 'max_curvature:=5.0', '-p', 'max_sharpness:=100.0')   # the room is tight
    plans, statuses = _listen(node)
    assert spin(executor, lambda: plans and statuses)
    assert statuses[-1].found, statuses[-1].reason
    points = _points(plans[-1])
    assert _wall_distance(points).min() >= 0.2 - 1e-9
    # The curvature of the published poses, from three consecutive points (the circle through
    # them), never exceeds the bound (samples 5 cm apart: a little slack for the chord).
    a, b, c = points[:-2], points[1:-1], points[2:]
    ab, bc, ca = (np.hypot(*(q - p).T) for p, q in ((a, b), (b, c), (c, a)))
    cross = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    keep = (ab > 1e-6) & (bc > 1e-6) & (ca > 1e-6)
    curvature = 2.0 * cross[keep] / (ab * bc * ca)[keep]
    assert curvature.max() <= 5.0 * 1.05


def _markers_by_id(node, executor, spin, start_node, world, method):
    """Plan from (1, 1) to (3, 1) round the wall with ``method``; return its markers by id."""
    from visualization_msgs.msg import MarkerArray
    start_node('robotica_ctrl', 'planner', '-p', f'world_file:={world}', '-p',
               'start:=[1.0, 1.0]', '-p', 'goal:=[3.0, 1.0]', '-p', 'robot_radius:=0.2',
               '-p', f'method:={method}')
    arrays = []
    node.create_subscription(MarkerArray, '/planner/markers', arrays.append, LATCHED)
    assert spin(executor, lambda: arrays)
    return {m.id: m for m in arrays[-1].markers if m.ns == 'plan' and m.action == m.ADD}


def test_the_visibility_graph_is_drawn_and_crosses_no_wall(start_node, ros_node, spin, world):
    node, executor = ros_node
    markers = _markers_by_id(node, executor, spin, start_node, world, 'visibility_graph')
    edges = np.array([[p.x, p.y] for p in markers[4].points]).reshape(-1, 4)
    assert len(edges) > 10
    # An edge inside the room (the grown outer walls' vertices lie outside it, and so do the
    # edges between them) that crosses the line x = 2 passes above the wall's free end (y = 3)
    # plus r.
    a, b = edges[:, :2], edges[:, 2:]
    inside = np.all((edges >= 0.2 - 1e-9) & (edges <= 3.8 + 1e-9), axis=1)
    crossing = inside & ((a[:, 0] - 2.0) * (b[:, 0] - 2.0) < 0.0)
    y_at_wall = a[:, 1] + (b[:, 1] - a[:, 1]) * (2.0 - a[:, 0]) / (b[:, 0] - a[:, 0] + 1e-300)
    assert crossing.any() and np.all(y_at_wall[crossing] >= 3.2 - 1e-6)


def test_a_potential_field_and_its_trap_are_drawn(start_node, ros_node, spin, world):
    # The wall between start and goal: the generalised potential stalls in front of it. The
    # field is drawn on a 0.25 m lattice: segments of 0.7 x 0.25 m from lattice points.
    node, executor = ros_node
    markers = _markers_by_id(node, executor, spin, start_node, world, 'potential')
    segments = np.array([[p.x, p.y] for p in markers[5].points]).reshape(-1, 4)
    assert len(segments) > 50
    lengths = np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])
    assert lengths == pytest.approx(0.175, abs=1e-9)
    offsets = (segments[:, :2] - segments[0, :2]) / 0.25
    assert np.allclose(offsets, np.round(offsets), atol=1e-9)
    assert 6 in markers   # the trap: the plan ended in a local minimum or a collision
