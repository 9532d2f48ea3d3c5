"""`socnavgen cards ...`: the 25 canonical scenario cards, and a no-LLM generator that places them on a map."""

from __future__ import annotations

from pathlib import Path

import typer
from rich import box
from rich.table import Table

from socnavgen.cards.generate import fit_all, write_card_run
from socnavgen.cards.library import all_cards, get_card
from socnavgen.cli import typer_app
from socnavgen.cli.common import console, progress
from socnavgen.errors import ValidationFailed
from socnavgen.location import load_location

app = typer_app(help="The 25 canonical scenario cards of Francis et al.", no_args_is_help=True)


@app.command("list")
def list_cards() -> None:
    """List every card with its one-line picture (R = robot, H = human, G = group member).

    Example: socnavgen cards list
    """
    wide = console.width >= 140  # narrow terminals and pipes (80 columns) get the essential columns only
    table = Table(show_lines=False, expand=False, box=box.SIMPLE_HEAD)
    table.add_column("card", no_wrap=True)  # names are typed back by the user: never break them
    table.add_column("picture", no_wrap=True)
    if wide:
        table.add_column("category", no_wrap=True)
        table.add_column("needs", overflow="fold", max_width=24)
    table.add_column("summary", overflow="fold", min_width=20, ratio=1)
    for card in all_cards():
        extra = [card.category, ", ".join(card.needs)] if wide else []
        table.add_row(card.name, card.picture, *extra, card.summary)
    console.print(table)


def describe_criterion(criterion: object) -> str:
    """A card's success criterion in words: `meets_human human1 within 2.5 m` rather than a dict."""
    fields = criterion.model_dump(exclude_none=True)  # type: ignore[attr-defined]
    words = [str(fields.pop("kind", "?")).replace("_", " ")]
    if "human" in fields:
        words.append(str(fields.pop("human")))
    if "node" in fields:
        words.append(f"runs {fields.pop('node')}")
    if "within" in fields:
        words.append(f"within {fields.pop('within'):g} m")
    words += [f"{k}={v}" for k, v in fields.items()]
    return " ".join(words)


@app.command("show")
def show(name: str = typer.Argument(..., help="card name, e.g. blind-corner (see `cards list`)")) -> None:
    """Print one card: definition, rough scenario (usable as --rough), expected robot behavior, criteria.

    Example: socnavgen cards show blind-corner
    """
    card = get_card(name)
    console.print(f"[bold]{card.title}[/] ({card.name}, {card.category})   {card.picture}", highlight=False)
    rows = [("summary", card.summary), ("place", f"{card.place} (robot route: {card.route})"),
            ("also needs", ", ".join(card.requires) or "-"), ("context", card.context), ("robot task", card.task),
            ("human behavior", card.human_behavior), ("rough scenario", card.rough),
            ("expected robot behavior", card.expected_robot_behavior)]
    for label, text in rows:
        console.print(f"[cyan]{label}:[/] {text}", highlight=False)
    for k, h in enumerate(card.humans):
        count = f"{h.count}x " if h.count > 1 else ""
        console.print(f"[cyan]humans {k + 1}:[/] {count}{h.role}, tree '{h.tree}'"
                      f"{' (a group)' if h.group else ''}: {h.behavior}", highlight=False)
    for c in card.criteria:
        console.print(f"[cyan]success:[/] {describe_criterion(c)}", highlight=False)
    console.print(f"\nwith an LLM: socnavgen generate --card {card.name} --location LOC --llm SPEC --out RUN")


@app.command("generate")
def generate(
    name: str | None = typer.Argument(None, help="card name (omit with --all)"),
    location: Path = typer.Option(..., "--location", "-l", help="location folder (location.yaml, map, scene graph)"),
    out: Path = typer.Option(..., "--out", "-o",
                             help="run folder to write; with --all, a folder that gets one run per card"),
    all_: bool = typer.Option(False, "--all", help="instantiate every card that fits and say why the others do not"),
    pick: int = typer.Option(1, "--pick", min=1,
                             help="use the K-th matching place (1 = the best, as generate --pick counts)"),
) -> None:
    """Place a card on the location's scene graph WITHOUT an LLM and write an ordinary run folder.

    The generator finds a matching place (blind corner, narrow edge, doorway into a room, intersection, open area...) by node-type keywords and map geometry, builds robot and human paths through it, and writes trees from the card's templates; export, simulate and verify work on the result.

    Example: socnavgen cards generate blind-corner --location examples/locations/warehouse -o runs/card_blind
    Example: socnavgen cards generate --all --location examples/locations/hospital -o runs/hospital_cards
    """
    if all_ == (name is not None):
        raise ValidationFailed("give a card name or --all (not both)", hint="socnavgen cards list shows the names")
    if not all_:
        run = write_card_run(name or "", location, out, pick - 1)
        console.print(f"[green]wrote[/] {run.root} (card {get_card(name or '').name})")
        console.print(f"next: socnavgen export {run.root} --format socrates -o OUT, or socnavgen simulate {run.root}")
        return
    loc = load_location(location)
    fits = fit_all(loc)
    written, skipped = 0, []
    with progress() as bar:
        task = bar.add_task("cards", total=len(fits))
        for fit in fits:
            if fit.fits:
                write_card_run(fit.card.name, location, out / fit.card.name, pick - 1)
                written += 1
            else:
                skipped.append((fit.card.name, fit.reason))
            bar.advance(task)
    console.print(f"[green]{written} card(s) fit {loc.name}[/]; runs are in {out}/<card>")
    for card_name, reason in skipped:
        console.print(f"[yellow]{card_name}[/]: {reason}", highlight=False)
