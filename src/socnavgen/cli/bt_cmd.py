"""`socnavgen bt ...` commands: check hand-written trees, show the node library."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table

from socnavgen.bt.library import NODES, NodeSpec, hunav2_text
from socnavgen.bt.validate import TARGETS, validate_bt_file
from socnavgen.cli import typer_app
from socnavgen.cli.common import console
from socnavgen.errors import InputFileError

app = typer_app(help="Behavior-tree tools: validate hand-written trees, show the node library.",
                  no_args_is_help=True)

TargetOption = Annotated[str, typer.Option(
    "--target", "-t",
    help="Export target whose node support is checked: socrates (the paper's HuNavSim fork), "
         "hunav2 (upstream HuNavSim 2.x) or hunav1 (upstream 1.x).")]


@app.command("check")
def check(
    files: Annotated[list[Path], typer.Argument(help="Behavior-tree XML files to check.", show_default=False)],
    target: TargetOption = "socrates",
    human_ids: Annotated[str | None, typer.Option(
        "--humans", help="Comma-separated ids of the scenario's humans (0-based), e.g. 0,1,2: "
                         "HumanSays/FollowHuman target_id must be one of them.")] = None,
) -> None:
    """Check behavior trees against the node library and list EVERY problem as file:line: message.

    Exit code 0 when all files are valid, 1 when any problem was found.

    Example:  socnavgen bt check runs/blind_corner/behaviors/*.xml --target hunav2
    """
    if target not in TARGETS:
        raise typer.BadParameter(f"unknown target {target!r}; choose one of {', '.join(TARGETS)}",
                                 param_hint="--target")
    ids: set[int] | None = None
    if human_ids is not None:
        try:
            ids = {int(part) for part in human_ids.split(",") if part.strip()}
        except ValueError as exc:
            raise typer.BadParameter("expected comma-separated integers like 0,1,2", param_hint="--humans") from exc
    missing = [path for path in files if not path.is_file()]
    if missing:  # a user error (exit 2), not a finding of the check (exit 1)
        raise InputFileError("no such file" + ("s: " + ", ".join(map(str, missing)) if len(missing) > 1 else ""),
                             file=missing[0], hint="check the path (a shell glob that matched nothing stays literal)")
    bad = 0
    for path in files:
        problems = validate_bt_file(path, target=target, human_ids=ids)
        if problems:
            bad += 1
            for problem in problems:
                console.print(str(problem), highlight=False, markup=False, soft_wrap=True)
        else:
            console.print(f"[green]ok[/] {path}", highlight=False)
    if bad:
        console.print(f"[red]{bad} of {len(files)} file(s) have problems[/]")
        raise typer.Exit(1)


def _ports_text(spec: NodeSpec) -> str:
    parts = []
    for port in spec.ports:
        text = f"{port.name}: {port.type}"
        if not port.required:
            text += f" = {port.default}" if port.default else " (optional)"
        if port.allowed:
            text += " {" + ", ".join(f"{k} {v}" for k, v in port.allowed.items()) + "}"
        parts.append(text)
    return ", ".join(parts)


def _targets_text(spec: NodeSpec) -> str:
    parts = []
    for target in TARGETS:
        if target not in spec.targets:
            continue
        other = getattr(spec, target, None) if target != "socrates" else None
        parts.append(f"{target} ({other})" if other and other != spec.name else target)
    return ", ".join(parts)


def library_markdown() -> str:
    """The node table as Markdown (docs/behavior-trees.md is generated from this)."""
    lines = ["| node | kind | ports | meaning | targets | HuNavSim 2.x | simulator note |",
             "|---|---|---|---|---|---|---|"]
    for spec in NODES:
        cells = [f"`{spec.name}`" + ("" if spec.in_prompt else " *"), spec.kind, _ports_text(spec) or "-",
                 spec.description, _targets_text(spec), hunav2_text(spec.name), spec.sim_note or ""]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    lines.append("")
    lines.append("`*` accepted by the validator and the simulator but not shown to the model.")
    return "\n".join(lines) + "\n"


@app.command("library")
def library(
    markdown: Annotated[bool, typer.Option("--markdown", help="Print a Markdown table (for docs).")] = False,
    target: Annotated[str | None, typer.Option("--target", "-t", help="Only nodes this target supports.")] = None,
) -> None:
    """Show the behavior-tree node library: every node, its ports and types, what it does, and
    which export targets support it (with the target's name for it).

    Example:  socnavgen bt library --target hunav2
    """
    if target is not None and target not in TARGETS:
        raise typer.BadParameter(f"unknown target {target!r}; choose one of {', '.join(TARGETS)}",
                                 param_hint="--target")
    if markdown:
        print(library_markdown(), end="")
        return
    nodes = [spec for spec in NODES if target is None or target in spec.targets]
    if console.width < WIDE:  # six columns in 80 would break words ("conditio n"): one paragraph per node
        _library_list(nodes)
        return
    table = Table(title="behavior-tree node library", show_lines=False)
    table.add_column("node", no_wrap=True)  # names stay whole (copy-paste); the rest folds
    for column in ("kind", "ports", "meaning", "targets", "HuNavSim 2.x"):
        table.add_column(column, overflow="fold")
    for spec in nodes:
        table.add_row(spec.name, spec.kind, _ports_text(spec), spec.description, _targets_text(spec),
                      hunav2_text(spec.name))
    console.print(table)


WIDE = 140  # columns below which the library is a list


def _library_list(nodes: list) -> None:
    """The library for narrow terminals and pipes: each node a paragraph, wrapped between words."""
    import textwrap

    width = max(40, console.width)
    console.print("behavior-tree node library", style="bold", highlight=False)
    for spec in nodes:
        console.print(f"\n[bold]{spec.name}[/] ({spec.kind})", highlight=False)
        for label, text in (("ports", _ports_text(spec) or "-"), ("", spec.description),
                            ("targets", _targets_text(spec)), ("HuNavSim 2.x", hunav2_text(spec.name))):
            console.print(textwrap.fill(f"{label}: {text}" if label else text, width=width, initial_indent="  ",
                                        subsequent_indent="  ", break_long_words=False, break_on_hyphens=False),
                          markup=False, highlight=False)
