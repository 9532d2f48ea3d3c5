"""BehaviorTree.CPP 4's loader applied to a HuNavSim 2.x tree file: the file is read by THE parser
(bt.parse, bt.expand) with the vocabulary 2.x's factory has, the nodes HuNavSim 2.x registers with
their declared ports (`bt.library.HUNAV2_REGISTERED`) and BT.CPP 4's built-ins. So what makes
`createTreeFromFile` throw (an unknown node, an undeclared port, a SubTree naming no tree, no main tree)
and what makes the first tick throw (a port the 2.x code reads that has no default and is not written;
a blackboard entry read before anything set it) are problems. Used by the exporter's tests next to the
real BT.CPP (behaviortreepy), whose Python API cannot declare ports."""

from __future__ import annotations

from functools import cache

from socnavgen.bt.expand import check_text
from socnavgen.bt.library import HUNAV2_REGISTERED, LIBRARY, NodeSpec, Port, PortType, registered_spec

# BT.CPP 4 built-ins beyond the library's own controls that 2.x files hold (the exporter's goal queue)
RUN_ONCE = NodeSpec(name="RunOnce", kind="decorator", min_children=1, max_children=1, targets={"hunav2"},
                    in_prompt=False, description="BT.CPP 4 built-in: ticks its child until it finishes once, "
                                                 "then skips it",
                    ports=[Port(name="then_skip", type=PortType.BOOL, required=False, default="true",
                                description="after the first run: skip (true) or return its status")])


@cache
def hunav2_vocabulary() -> dict[str, NodeSpec]:
    """Every node HuNavSim 2.x's factory knows: what it registers, and BT.CPP 4's built-ins."""
    builtins = {n.name: n for n in LIBRARY.values() if n.kind not in ("action", "condition")}
    registered = {n.id: registered_spec(n) for n in HUNAV2_REGISTERED.values()}
    return {**builtins, **registered, RUN_ONCE.name: RUN_ONCE, "AlwaysSuccess": LIBRARY["AlwaysSuccess"]}


def hunav2_problems(text: str, source: str = "<tree>") -> list[str]:
    """Every reason this v4 file would fail to load or throw at a tick in HuNavSim 2.x ([] = none)."""
    doc, _, problems = check_text(text, source, hunav2_vocabulary())
    found = [str(p) for p in problems]
    if doc is not None and doc.format_version != 4:
        found.append(f'{source}: BTCPP_format must be "4" for BT.CPP 4')
    if doc is not None and doc.includes:
        found.append(f"{source}: include {list(doc.includes)} (2.x loads one self-contained file per agent)")
    return found
