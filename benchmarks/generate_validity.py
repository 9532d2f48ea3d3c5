"""First-attempt validity of stage 2 (paths) and stage 3 (behavior trees) with the in-process model,
WITH our grammars (graph- and library-constrained) and WITHOUT them (the backend then only enforces
the reply's JSON schema, so the JSON parses but nodes, edges and tree nodes are free).

    python benchmarks/generate_validity.py                    # local model, 10 tries per case
    python benchmarks/generate_validity.py --tries 5 --llm gguf:/path/model.gguf

Each try is a different prompt (stage 2: tutorial/example seed; stage 3: a different behavior text), so
a deterministic model still answers 10 different questions. Validity = the pipeline's own checks
(path_checks / the BT validator) pass on the FIRST answer, before any re-query. Prints a table.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from socnavgen.llm import make_llm
from socnavgen.location import load_location
from socnavgen.proposal.behaviors import GRAMMAR_DEPTH, behavior_messages, tree_checker
from socnavgen.proposal.path_checks import check_paths
from socnavgen.proposal.path_grammar import paths_grammar
from socnavgen.proposal.paths import paths_messages
from socnavgen.proposal.replies import BehaviorReply, PathsReply
from socnavgen.run import HumanPlan, PathPlan, ScenarioProposal

BEHAVIORS = [
    "Walks to the entrance; stops and looks at the robot when it is within 2 metres.",
    "Stands still until the robot says EXCUSE ME, then gives way to the robot.",
    "Is scared of robots and hurries away from the robot whenever it is visible within 3 metres.",
    "Walks normally, treating the robot as an ordinary obstacle.",
    "Follows the robot when the robot says FOLLOW ME, otherwise waits.",
    "Says WAIT to the robot when the robot blocks the way, then walks on.",
    "Blocks the robot for a while, then walks to the goal.",
    "Looks at the robot while it moves, and walks normally when it stops.",
    "Gives way to the robot when it is very close and in the way.",
    "Says PROCEED when the robot is visible within 2 metres, then walks on.",
]
SCENARIO = ScenarioProposal(
    scenario_description="The robot carries a box along the west corridor and meets two workers at a blind "
                         "corner; one of them stops, the other gives way.",
    number_of_humans=2,
    human_behaviors={"human1": "Stops when the robot is very close.", "human2": "Gives way to the robot."},
    expected_robot_behavior="Slow down at the corner and say PROCEED.")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--llm", default="local")
    parser.add_argument("--tries", type=int, default=10)
    parser.add_argument("--location", default="examples/locations/warehouse")
    parser.add_argument("--temperature", type=float, default=0.0)
    parser.add_argument("--stages", default="paths,behaviors")
    args = parser.parse_args()
    location = load_location(args.location)
    graph = location.graph
    humans = list(SCENARIO.human_behaviors)
    node = sorted(graph.nodes)[0]
    plan = PathPlan(robot=[node, sorted(graph.neighbors(node))[0]],
                    humans=[HumanPlan(name=h, path=[node], interaction_point=node) for h in humans])
    with tempfile.TemporaryDirectory() as tmp:
        llm = make_llm(args.llm, transcript=Path(tmp) / "transcript.jsonl", use_cache=False)
        rows = []
        for stage in args.stages.split(","):
            for constrained in (True, False):
                valid, seconds, mistakes = 0, [], []
                for i in range(args.tries):
                    started = time.monotonic()
                    if stage == "paths":
                        reply = llm.chat(paths_messages(location, SCENARIO, seed=i, images=False), PathsReply,
                                         stage="paths", key=f"try{i}", temperature=args.temperature,
                                         grammar=paths_grammar(graph, humans) if constrained else None,
                                         max_tokens=1024)
                        found = [reply.error] if not reply.ok else check_paths(reply.value, graph, humans)
                    else:
                        from socnavgen.bt.grammar import bt_reply_grammar
                        scenario = SCENARIO.model_copy(update={"human_behaviors": {
                            "human1": BEHAVIORS[i % len(BEHAVIORS)], "human2": "Walks normally."}})
                        reply = llm.chat(behavior_messages("human1", scenario, plan), BehaviorReply,
                                         stage="behaviors", key=f"try{i}", temperature=args.temperature,
                                         grammar=bt_reply_grammar([0, 1], agent_id=0, max_depth=GRAMMAR_DEPTH) if constrained else None,
                                         max_tokens=1536)
                        found = [reply.error] if not reply.ok else tree_checker("human1", humans)(reply.value)
                    seconds.append(time.monotonic() - started)
                    valid += not found
                    if found:
                        mistakes.append(str(found[0])[:90])
                    print(f"{stage:9} grammar={'ours' if constrained else 'json '} try {i + 1}: "
                          f"{'valid' if not found else 'INVALID ' + str(found[0])[:80]} ({seconds[-1]:.1f} s)",
                          flush=True)
                rows.append((stage, "ours" if constrained else "JSON schema only", valid, args.tries,
                             statistics.mean(seconds), mistakes[0] if mistakes else ""))
    print(f"\nmodel: {llm.model}  location: {args.location}  temperature: {args.temperature}")
    print(f"{'stage':10} {'grammar':18} {'first-attempt valid':>20} {'mean s':>8}  first mistake seen")
    for stage, grammar, valid, tries, mean, mistake in rows:
        print(f"{stage:10} {grammar:18} {f'{valid}/{tries} ({100 * valid / tries:.0f}%)':>20} {mean:8.1f}  {mistake}")


if __name__ == "__main__":
    main()
