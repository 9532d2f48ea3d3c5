"""The README.md written into every export: where each file goes and how to launch it."""

from __future__ import annotations

from socnavgen.bt.library import HUNAV2_FIRST_AGENT_ID
from socnavgen.export.models import ExportScene
from socnavgen.export.timing import Hold, describe


def _summary(scene: ExportScene, first_id: int = 0) -> str:
    """`first_id`: the target's id of human1 (the fork counts from 0, HuNavSim 1.x/2.x from 1)."""
    humans = "\n".join(
        f"- {h.name} (agent id {h.agent_id + first_id}, group {h.group_id}): starts at node {h.start.node} "
        f"({h.start.x:.2f}, {h.start.y:.2f}) facing {h.start.yaw:.2f} rad, goals "
        + " -> ".join(g.node for g in h.goals)
        + (f", meets the robot at {h.interaction_point}" if h.interaction_point else "")
        for h in scene.humans)
    return (f"Scenario `{scene.run_name}` on location `{scene.location_name}`, exported by socnavgen.\n\n"
            f"- robot: starts at node {scene.robot.start.node} ({scene.robot.start.x:.2f}, "
            f"{scene.robot.start.y:.2f}), waypoints " + " -> ".join(w.node for w in scene.robot.waypoints)
            + "\n" + humans + "\n\nAll coordinates are metres in the map frame of the location's nav2 map.\n")


def timing_section(holds: dict[str, Hold] | None) -> str:
    """How the timed people wait for the robot (their trees do it: export.timing)."""
    if not holds:
        return ""
    lines = "\n".join(f"- {describe(h)}" for h in holds.values())
    return ("\n## Timing\nThese people wait for the robot by themselves: their trees hold them at a spot before "
            "the place they meet it and let them go once the robot is that close (a distance, not a time, so "
            "the encounter happens there whatever the robot's speed). Start the robot within a few seconds of "
            "the people.\n" + lines + "\n")


def script_section(scene: ExportScene, where: str, how: str) -> str:
    """The robot's part: robot_script.yaml and how the target plays it."""
    spec = scene.spec
    cues = len(spec.script.cues) if spec is not None else 0
    rules = len(scene.plan.robot_gestures)
    return (f"\n## The robot's part\n`{where}` holds the robot's script ({cues} cue(s), {rules} gesture rule(s); "
            f"cruise speed {spec.script.speed if spec else 0.6:g} m/s): what the robot says and does, and when, "
            f"in world coordinates. {how}\n")


def spoken_section(spoken: dict | None) -> str:
    """hunav2: what each phrase condition of the trees became (HuNavSim 2.x cannot hear the robot)."""
    spoken = spoken or {}
    lines = [f"- {name} line {s.line}: {s.node}: {s.text}" for name, notes in spoken.items() for s in notes]
    if not lines:
        return ""
    return ("\n## What the robot says (approximated)\nHuNavSim 2.x has no input for the robot's speech, so each "
            "phrase condition of a tree is the condition under which the robot's script says the phrase, as "
            "the person sees it:\n" + "\n".join(lines) + "\n")


def socrates_readme(scene: ExportScene, holds: dict[str, Hold] | None = None) -> str:
    return f"""# SocRATES / HuNavSim fork export

{_summary(scene)}
## Where the files go
Copy the folders over the two packages of your ROS 2 workspace, then rebuild:

| file here | package folder |
|---|---|
| `hunav_agent_manager/behavior_trees/LLMBT_<i>.xml` | `src/hunav_sim/hunav_agent_manager/behavior_trees/` (agent `behavior: 7+i` loads `LLMBT_<i>.xml`) |
| `hunav_agent_manager/behavior_trees/BTRegularNav.xml` | same folder (the subtree the LLM trees include) |
| `hunav_agent_manager/config/custom_agents.yaml` | `src/hunav_sim/hunav_agent_manager/config/` |
| `hunav_gazebo_wrapper/config/robot_poses.yaml`, `trajectory.json` | `src/hunav_gazebo_wrapper/config/` |
| `hunav_gazebo_wrapper/config/launch_params.yaml` | same; set `robot_poses` and `scenario` to the ABSOLUTE paths of the two files above, and `world_name` to your Gazebo world folder |

`TreeNodesModel.xml` is for Groot2 only (open a tree, then import this model file).

## Launch
```
colcon build --packages-select hunav_agent_manager hunav_gazebo_wrapper && source install/setup.bash
ros2 launch hunav_gazebo_wrapper scenario_nav2_lino.launch.py      # world, humans, scenario_manager
ros2 launch hunav_gazebo_wrapper nav2_follow_waypoints.launch.py   # robot follows robot_poses.yaml
```
A teleop script can read `robot_poses.yaml` the same way: `initial_pose {{x, y, yaw}}` and
`waypoints[].position {{x, y, yaw}}` (yaw toward the next waypoint).
Humans without an interaction point have `""` in `trajectory.json`: the scenario manager never pauses them;
nor does it pause the people whose trees wait for the robot themselves (Timing below).
{timing_section(holds)}{script_section(scene, "hunav_gazebo_wrapper/config/robot_script.yaml",
    "The fork hears the robot on `/robot_gesture`: run `python3 hunav_gazebo_wrapper/scripts/"
    "socnavgen_robot_gestures.py hunav_gazebo_wrapper/config/robot_script.yaml` beside the simulation "
    "(ROS 2 with the fork's hunav_msgs, and `pip install socnavgen`); it plays the script from the robot's and "
    "the people's states with socnavgen's own cue logic and publishes each gesture. Waits and speeds are for "
    "the robot's operator or navigation.")}"""


def hunav2_readme(scene: ExportScene, base: str, simulator: str, spoken: dict | None = None,
                  holds: dict[str, Hold] | None = None) -> str:
    return f"""# HuNavSim 2.x export

{_summary(scene, HUNAV2_FIRST_AGENT_ID)}
## Where the files go
| file here | package folder |
|---|---|
| `hunav_gazebo_wrapper/scenarios/{base}.yaml` | `src/hunav_gazebo_wrapper/scenarios/` |
| `hunav_gazebo_wrapper/behavior_trees/{base}__agent_<id>_bt.xml` | `src/hunav_gazebo_wrapper/behavior_trees/` (the manager loads them from the wrapper's SOURCE folder) |
| `robot/robot_poses.yaml` | anywhere your robot launch or teleop script reads it |

`yaml_base_name: {base}` selects the tree files; `simulator: {simulator}` selects the wrapper package.
Each tree is self-contained (RegularNavTree inlined, goals queued with `SetGoal`) and carries a
`TreeNodesModel`, so it opens directly in Groot2; `TreeNodesModel.xml` lists every node HuNavSim 2.x registers with its ports.

## Launch
```
colcon build && source install/setup.bash
ros2 launch hunav_gazebo_wrapper simulation.launch.py configuration_file:={base}.yaml \\
    environment_name:=<your Gazebo world> gzpose_x:={scene.robot.start.x:.3f} gzpose_y:={scene.robot.start.y:.3f} \\
    gzpose_Y:={scene.robot.start.yaw:.3f}
```
The robot then drives the waypoints of `robot/robot_poses.yaml` (nav2 waypoint follower or teleop).
{timing_section(holds)}{script_section(scene, "robot/robot_script.yaml",
    "HuNavSim 2.x people cannot hear it; the robot still plays it (its operator, or your robot's speech).")}{spoken_section(spoken)}"""


def hunav1_readme(scene: ExportScene, behaviors: dict[str, int]) -> str:
    script = script_section(scene, "robot/robot_script.yaml", "HuNavSim 1.x people cannot hear it (built-in "
                            "behaviors only); it tells the robot's operator what to do.")
    table = "\n".join(f"- {name}: behavior {code}" for name, code in behaviors.items())
    return f"""# HuNavSim 1.x export (built-in behaviors only)

{_summary(scene, HUNAV2_FIRST_AGENT_ID)}
{table}

## Where the files go
| file here | package folder |
|---|---|
| `hunav_agent_manager/config/agents.yaml` | `src/hunav_sim/hunav_agent_manager/config/` |
| `robot/robot_poses.yaml` | anywhere your robot launch or teleop script reads it |

## Launch
```
colcon build && source install/setup.bash
ros2 launch hunav_gazebo_wrapper example_cafe.launch.py   # or your own world's launch file
```
{script}"""
