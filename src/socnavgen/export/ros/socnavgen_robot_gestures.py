#!/usr/bin/env python3
"""Publish the robot's scripted gestures of a socnavgen scenario on the SocRATES fork's /robot_gesture.

    python3 socnavgen_robot_gestures.py hunav_gazebo_wrapper/config/robot_script.yaml

Needs ROS 2 (rclpy, std_msgs, the fork's hunav_msgs) and socnavgen (pip install socnavgen). It listens to the
agent manager's /robot_states (hunav_msgs/Agent) and /human_states (hunav_msgs/Agents), plays the script with
socnavgen's own cue logic (socnavgen.export.robot_script.ScriptPlayer: the simulator's code) and publishes the
gesture code (std_msgs/UInt32) whenever it changes. Time counts from the first /human_states message."""

from __future__ import annotations

import sys

from socnavgen.export.robot_script import ScriptPlayer, load_script


class GestureState:
    """The node's logic without ROS: robot and people messages in, a gesture code out when it changes."""

    def __init__(self, player: ScriptPlayer) -> None:
        self.player = player
        self.robot: tuple[float, float, float] | None = None
        self.start: float | None = None
        self.last = 0

    def on_robot(self, agent) -> None:  # noqa: ANN001 - hunav_msgs/Agent
        self.robot = (agent.position.position.x, agent.position.position.y, agent.yaw)

    def on_humans(self, agents) -> int | None:  # noqa: ANN001 - hunav_msgs/Agents
        """The gesture to publish now, or None when it did not change (or the robot is not known yet)."""
        stamp = agents.header.stamp.sec + agents.header.stamp.nanosec * 1e-9
        self.start = stamp if self.start is None else self.start
        if self.robot is None:
            return None
        people = [(a.position.position.x, a.position.position.y) for a in agents.agents]
        code = self.player.gesture(stamp - self.start, self.robot, people, [a.gesture for a in agents.agents])
        if code == self.last:
            return None
        self.last = code
        return code


def main(argv: list[str] | None = None) -> None:
    args = sys.argv[1:] if argv is None else argv
    if not args:
        raise SystemExit("usage: socnavgen_robot_gestures.py ROBOT_SCRIPT.yaml")
    import rclpy
    from hunav_msgs.msg import Agent, Agents
    from std_msgs.msg import UInt32

    state = GestureState(ScriptPlayer(load_script(args[0])))
    rclpy.init()
    node = rclpy.create_node("socnavgen_robot_gestures")
    out = node.create_publisher(UInt32, "/robot_gesture", 10)

    def humans(msg) -> None:  # noqa: ANN001
        code = state.on_humans(msg)
        if code is not None:
            out.publish(UInt32(data=code))

    node.create_subscription(Agent, "/robot_states", state.on_robot, 10)
    node.create_subscription(Agents, "/human_states", humans, 10)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
