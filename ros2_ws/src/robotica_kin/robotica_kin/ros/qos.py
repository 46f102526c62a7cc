"""
QoS profiles by role, shared by every robotica node (STYLE.md §5, "QoS by role").

* Streams (clock, ground truth, wheel angles, encoder ticks, odometry, tracking errors, status)
  are published RELIABLE and TRANSIENT_LOCAL with a history of ``STREAM_HISTORY`` messages: a
  reliable publisher also serves best-effort (sensor-data) subscribers, and the history lets a
  recorder whose subscription is matched a moment late still get the first messages of a run.
  Stream subscribers ask for RELIABLE, VOLATILE: in lockstep a lost message would stall a step,
  and a volatile reader gets no stale history. They keep ``STREAM_SUB_DEPTH`` messages: a node
  off the lockstep chain (a sensor emulator) falls behind in bursts on a loaded machine, and with
  keep-last 10 a figure-eight run lost 6 of 750 gyro readings that way.
* Replayed streams: the inputs of the nodes off the lockstep chain (the sensor emulators' ground
  truth and joint states, the odometry's gyro, compass and GPS, the simulator's followed
  topics) are subscribed RELIABLE and TRANSIENT_LOCAL, keeping ``STREAM_HISTORY`` messages: a
  subscription matched late gets the publisher's history instead of losing the start of the
  run. On a loaded machine one pair of processes took 3 s to discover each other; the gyro
  emulator, subscribed volatile, then never saw the first 0.8 s of ground truth, and the
  odometry's heading missed part of the first turn. These inputs need a TRANSIENT_LOCAL
  publisher (every robotica stream is one): a volatile one is incompatible and not matched.
  A node that replays history must not misuse it: the odometry drops what is older than its
  first encoder reading (which it reads volatile, so that a restarted odometry starts now).
* Inputs that a user's own stack may feed (the odometry's encoder, gyro, GPS and compass
  readings, the path tracker's pose, the joint controller's joint states) accept rclpy's QoS
  overrides by parameter (``INPUT_QOS_OVERRIDES``): a driver that publishes sensor-data QoS
  (best effort, volatile), which a reliable or transient-local reader never matches, is read with
  ``-p qos_overrides./imu/data.subscription.reliability:=best_effort -p
  qos_overrides./imu/data.subscription.durability:=volatile``.
* Commands are RELIABLE, VOLATILE: a late-joining consumer must never receive an old command.
  Their consumers keep the newest only (keep-last 1); their publishers keep a history of
  ``STREAM_HISTORY``, so that a recorder that falls behind for a moment (a 1 kHz lockstep arm)
  loses none: with keep-last 1 on the writer a reliable sample not yet acknowledged by the
  recorder is overwritten by the next one.
* Latched data (paths, models) are RELIABLE, TRANSIENT_LOCAL, keep-last 1 on both ends.
* Transforms: ``/tf_static`` with ``LATCHED_QOS`` (tf2_ros's ``StaticBroadcasterQoS``);
  ``/tf`` with ``TF_QOS``, a stream's profile: reliable as tf2_ros's ``DynamicBroadcasterQoS``,
  but TRANSIENT_LOCAL with ``STREAM_HISTORY`` messages instead of volatile keep-last 100, so that
  a recorder that falls behind or is matched late still gets every transform of a run (with
  keep-last 100 a demo bag lost 80 of the state publisher's 1601). A tf2 listener (reliable,
  volatile) is matched as before.
"""
from rclpy.qos import DurabilityPolicy, QoSPolicyKind, QoSProfile, ReliabilityPolicy
from rclpy.qos_overriding_options import QoSOverridingOptions

STREAM_HISTORY = 500   # messages: 10 s at 50 Hz, several seconds of a lockstep run

STREAM_PUB_QOS = QoSProfile(depth=STREAM_HISTORY, reliability=ReliabilityPolicy.RELIABLE,
                            durability=DurabilityPolicy.TRANSIENT_LOCAL)
STREAM_SUB_DEPTH = 100   # messages: 2 s at 50 Hz
STREAM_SUB_QOS = QoSProfile(depth=STREAM_SUB_DEPTH, reliability=ReliabilityPolicy.RELIABLE)
STREAM_REPLAY_SUB_QOS = QoSProfile(depth=STREAM_HISTORY, reliability=ReliabilityPolicy.RELIABLE,
                                   durability=DurabilityPolicy.TRANSIENT_LOCAL)
COMMAND_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE)
COMMAND_PUB_QOS = QoSProfile(depth=STREAM_HISTORY, reliability=ReliabilityPolicy.RELIABLE)
LATCHED_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
TF_QOS = STREAM_PUB_QOS
INPUT_QOS_OVERRIDES = QoSOverridingOptions(policy_kinds=(
    QoSPolicyKind.RELIABILITY, QoSPolicyKind.DURABILITY, QoSPolicyKind.HISTORY,
    QoSPolicyKind.DEPTH))
