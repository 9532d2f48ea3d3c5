"""BehaviorTree.CPP 4 loader rules applied to a HuNavSim 2.x tree file, with the node table of what
2.x registers (`bt.library.HUNAV2_REGISTERED`): what makes `createTreeFromFile` throw (unknown node,
undeclared port, SubTree naming no tree, missing main tree) and what makes the first tick throw (a
port the 2.x code reads that has no default and is not written). Used by the exporter's tests next to
the real BT.CPP (behaviortreepy), whose Python API cannot declare ports."""

from __future__ import annotations

from socnavgen.bt.library import HUNAV2_BUILTINS, HUNAV2_REGISTERED
from socnavgen.bt.tree import parse_bt

NOT_NODES = {"TreeNodesModel", "include"}


def hunav2_problems(text: str, source: str = "<tree>") -> list[str]:
    """Every reason this v4 file would fail to load or throw at a tick in HuNavSim 2.x ([] = none)."""
    doc = parse_bt(text, source)
    problems: list[str] = []
    if doc.format_version != 4:
        problems.append(f"{source}: BTCPP_format must be \"4\" for BT.CPP 4")
    if doc.main_tree not in doc.trees:
        problems.append(f"{source}: main_tree_to_execute {doc.main_tree!r} names no BehaviorTree")
    if doc.includes:
        problems.append(f"{source}: include {doc.includes} (2.x loads one self-contained file per agent)")
    for tree in doc.trees.values():
        for elem in list(tree.walk())[1:]:
            where = f"{source}:{elem.line or '?'}: {elem.tag}"
            if elem.tag in NOT_NODES:
                continue
            if elem.tag == "SubTree":
                if elem.attrs.get("ID") not in doc.trees:
                    problems.append(f"{where} names no BehaviorTree of the file ({elem.attrs.get('ID')!r})")
                continue
            node = HUNAV2_REGISTERED.get(elem.tag)
            if node is None:
                if elem.tag not in HUNAV2_BUILTINS:
                    problems.append(f"{where}: node not recognized (HuNavSim 2.x does not register it)")
                continue
            declared = {p.name: p for p in node.ports}
            problems += [f"{where}: port '{k}' is not declared by the 2.x node" for k in elem.attrs
                         if k != "name" and k not in declared]
            problems += [f"{where}: port '{p.name}' has no default and the 2.x code reads it (throws at tick)"
                         for p in node.ports
                         if p.direction == "input" and p.read and p.default is None and p.name not in elem.attrs]
    return problems
