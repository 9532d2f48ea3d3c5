"""What the verifier can tell about a spec before anything is simulated (stage 1 asks it): every criterion that
contradicts its own spec (blame rule S1) and every `stl` formula that cannot be monitored (syntax, unknown
signals, intervals longer than any episode or not sampled by the simulator's step)."""

from __future__ import annotations

import re

from socnavgen.run.spec import ScenarioSpec
from socnavgen.verify.blame import spec_problem
from socnavgen.verify.stl import formula_problems

_NODE_PLACE = re.compile(r"_to_(node_[a-z0-9]+)")


def spec_problems(spec: ScenarioSpec, node_ids: list[str] | None = None) -> list[str]:
    """Each problem as one sentence naming the criterion. `node_ids`: the scene graph's nodes a formula may name
    as node_<id>; None (stage 1, before paths) accepts any node_<id>."""
    problems = [problem for c in spec.criteria if (problem := spec_problem(c, spec))]
    humans = sorted({p.human for e in spec.encounters for p in e.humans}
                    | {h for c in spec.criteria for h in [c.human, *c.humans] if h}, key=lambda n: int(n[5:]))
    places = [e.id for e in spec.encounters] + ["goal"]
    for c in spec.criteria:
        if c.kind != "stl" or not (c.formula or "").strip():
            continue
        nodes = [f"node_{n}" for n in node_ids] if node_ids is not None else _NODE_PLACE.findall(c.formula or "")
        problems += [f"criterion {c.id}: {p}" for p in formula_problems(c.formula or "", humans, places + nodes)]
    return problems
