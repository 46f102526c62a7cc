"""
The watch ``robotica run`` keeps on users' nodes: each must keep the contract of its role.

For every node of the plan that runs a user's command (:attr:`NodeSpec.role`), the watch
subscribes to the output that answers each step (:attr:`robotica_sim.runs.roles.Role.answer`,
best effort, so that it also sees a publisher whose QoS the simulator would not match) and
notes each answer's wall-clock time and whether it holds a non-finite number. :meth:`failure`
then names the first broken promise as one message a user can act on: the node never answered
step 0 within its ``answer_timeout``, stopped answering, or answered with NaN; each with what the
node subscribes to and publishes in the ROS graph, and the contract it should keep.
"""
import time
from typing import Optional

from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from robotica_kin.ros.guarded import non_finite_fields
from robotica_sim.bags.typestore import message_class
from robotica_sim.runs.plan import NodeSpec
from robotica_sim.runs.roles import COMMAND, Role, role_contract, topic_name

__all__ = ['ContractWatch']

_WATCH_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT)


class _Answers:
    """What the watch has seen of one user's node: its answers and the first bad one."""

    def __init__(self, spec: NodeSpec, role: Role, timeout: float) -> None:
        self.spec, self.role, self.timeout = spec, role, timeout
        self.topic = topic_name(role.answer, spec.name)
        self.count = 0
        self.last = 0.0            # [s] wall clock (monotonic) of the newest answer
        self.last_sim = 0.0        # [s] simulated time when it came
        self.non_finite: Optional[list[str]] = None   # the fields of the first bad answer


class ContractWatch:
    """The users' nodes of a run, watched against their roles' contracts."""

    def __init__(self, node: Node, specs: list[NodeSpec], steered: bool,
                 timeouts: dict[str, float]) -> None:
        """
        Watch each node of ``specs`` that has a role, from ``node``.

        ``timeouts``: each role's ``answer_timeout`` [s, wall clock]; ``steered``: the
        vehicle is steered (its tracker answers on ``vehicle_command``).
        """
        self._node = node
        self._sim_time = 0.0
        self._answers: list[_Answers] = []
        for spec in specs:
            if not spec.role:
                continue
            answers = _Answers(spec, role_contract(spec.role, steered), timeouts[spec.role])
            output = next(t for t in answers.role.outputs if t.name == answers.role.answer)
            node.create_subscription(message_class(output.type), answers.topic,
                                     lambda msg, a=answers: self._note(a, msg), _WATCH_QOS)
            self._answers.append(answers)

    def __len__(self) -> int:
        """Return how many users' nodes the run has."""
        return len(self._answers)

    def label(self, name: str) -> Optional[str]:
        """Return how messages name the user's node ``name`` (None: not a user's node)."""
        return next((f'`{a.spec.label}` (the {a.role.name})' for a in self._answers
                     if a.spec.name == name), None)

    def _note(self, answers: _Answers, msg) -> None:
        """Count an answer; keep the fields of the first non-finite one."""
        answers.count += 1
        answers.last = time.monotonic()
        answers.last_sim = self._sim_time
        if answers.non_finite is None:
            answers.non_finite = non_finite_fields(msg) or None

    def unpublished(self, elapsed: float) -> Optional[str]:
        """
        Return which user's node has no publisher of its answer ``elapsed`` [s] after start.

        Called while the run waits for discovery (nothing is stepped yet): a node that has not
        created the publisher of its answer within its ``answer_timeout`` never will.
        """
        for a in self._answers:
            if elapsed > a.timeout and not any(
                    info.node_name == a.spec.name
                    for info in self._node.get_publishers_info_by_topic(a.topic)):
                return (f'`{a.spec.label}` never published {a.role.answer} for step 0 within '
                        f'{a.timeout:g} s (it has no publisher of {a.topic}); {self._graph(a)}. '
                        f'{self._contract(a)}')
        return None

    def failure(self, sim_time: float, started: float, running: bool = True) -> Optional[str]:
        """
        Return how a user's node broke its contract so far, or None.

        ``sim_time`` [s] is the newest ``/clock``; ``started`` the wall-clock (monotonic) time
        the simulation was started; ``running``: the simulator still steps (an answer is due).
        """
        self._sim_time = sim_time
        now = time.monotonic()
        for a in self._answers:
            name = f'`{a.spec.label}`'
            if a.non_finite is not None:   # published at or before this check's time
                return (f'{name} published a {a.role.answer} with a non-finite '
                        f'{", ".join(a.non_finite[:4])} (seen by t = {sim_time:.3f} s): the '
                        f'simulator refused it and stopped the robot. {self._contract(a)}')
            if not running:
                continue
            if a.count == 0 and now - started > a.timeout:
                return (f'{name} never published {a.role.answer} for step 0 within '
                        f'{a.timeout:g} s; {self._graph(a)}. {self._contract(a)}')
            if a.count and now - a.last > a.timeout and sim_time > a.last_sim:
                # (the simulator went on without it: one step per lockstep.timeout; a stalled
                # simulator, whose time stands still, is not this node's fault)
                return (f'{name} stopped answering: no {a.role.answer} for {a.timeout:g} s '
                        f'since t = {a.last_sim:.3f} s ({a.count} answers); {self._graph(a)}. '
                        f'{self._contract(a)}')
        return None

    def _graph(self, a: _Answers) -> str:
        """Return what the node subscribes to and publishes, as the ROS graph shows it."""
        try:
            subs = self._node.get_subscriber_names_and_types_by_node(a.spec.name, '/')
            pubs = self._node.get_publisher_names_and_types_by_node(a.spec.name, '/')
        except Exception:   # rclpy's NodeNameNonExistentError: no such node in the graph
            return (f'no node /{a.spec.name} is in the ROS graph (does the command create a '
                    'node and spin it?)')
        hidden = ('/parameter_events', '/rosout', '/clock')
        return (f'it subscribes to: {_topics(subs, hidden)}; '
                f'it publishes: {_topics(pubs, hidden)}{self._qos_hint(a)}')

    def _qos_hint(self, a: _Answers) -> str:
        """Return why the node's answer may reach nobody: a QoS the contract does not allow."""
        output = next(t for t in a.role.outputs if t.name == a.role.answer)
        for info in self._node.get_publishers_info_by_topic(a.topic):
            if info.node_name != a.spec.name:
                continue
            qos = info.qos_profile
            reliable = qos.reliability == ReliabilityPolicy.RELIABLE
            latched = qos.durability == DurabilityPolicy.TRANSIENT_LOCAL
            if not reliable or (output.qos != COMMAND and not latched):
                need = 'reliable' if output.qos == COMMAND else 'reliable, transient local'
                return (f' (its {a.role.answer} publisher offers {qos.reliability.name.lower()}'
                        f', {qos.durability.name.lower()}: a {output.qos} must be published '
                        f'{need}, else its subscribers are not matched)')
        return ''

    @staticmethod
    def _contract(a: _Answers) -> str:
        article = 'an' if a.role.name[0] in 'aeiou' else 'a'
        return (f'The contract of {article} {a.role.name} is: {a.role.text()} '
                '(docs/your_node.md)')


def _topics(names_and_types: list, hidden: tuple[str, ...]) -> str:
    """Return 'topic [type], ...' of a graph query, without the topics every node has."""
    shown = [f'{topic} [{types[0]}]' for topic, types in names_and_types if topic not in hidden]
    return ', '.join(shown) or 'nothing'
