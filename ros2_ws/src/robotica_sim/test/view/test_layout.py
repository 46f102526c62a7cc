"""
The Foxglove layout shipped in docs/ (docs/view.md): its panels exist, its paths are real fields.

A message path of the Foxglove app (``/odom.pose.pose.position.x``) that names no field shows
an empty plot without an error a user would notice; each one is resolved here on the message
classes of the topic's type (``/cmd_vel`` is ``Twist`` or, with ``enable_stamped_cmd_vel``,
``TwistStamped``: each series must resolve on one of them).
"""
import json
from pathlib import Path

from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry

LAYOUT = Path(__file__).resolve().parents[5] / 'docs' / 'foxglove_layout.json'
TOPIC_TYPES = {'/odom': (Odometry,), '/cmd_vel': (Twist, TwistStamped)}


def leaves(node) -> list[str]:
    """Return the panel ids of a layout tree (a panel id or a split of two subtrees)."""
    if isinstance(node, str):
        return [node]
    return leaves(node['first']) + leaves(node['second'])


def resolves(path: str) -> bool:
    """Return True if ``/topic.field.field`` ends on a number of the topic's type."""
    topic, *fields = path.split('.')
    for msg_type in TOPIC_TYPES[topic]:
        value = msg_type()
        for name in fields:
            value = getattr(value, name, None)
        if isinstance(value, float):
            return True
    return False


def test_layout_panels_and_paths():
    layout = json.loads(LAYOUT.read_text())
    panels = layout['configById']
    assert sorted(leaves(layout['layout'])) == sorted(panels)
    assert sorted(p.split('!')[0] for p in panels) == ['3D', 'Plot', 'Plot', 'RawMessages']
    scene = panels['3D!robotica']
    assert scene['topics']['/robot_description']['visible']
    assert scene['followTf'] == 'map'
    plotted = [s['value'] for p in panels if p.startswith('Plot!') for s in panels[p]['paths']]
    assert {p.split('.')[0] for p in plotted} == {'/odom', '/cmd_vel'}
    assert [p for p in plotted if not resolves(p)] == []
    assert panels['RawMessages!odom']['topicPath'] in TOPIC_TYPES


def test_path_check_sees_a_typo():
    assert resolves('/cmd_vel.twist.angular.z')
    assert not resolves('/odom.pose.position.x')      # Odometry's pose is PoseWithCovariance
    assert not resolves('/odom.pose.pose.position')   # a message, not a number
