"""`socnavgen generate`: scenario -> paths -> behavior trees into a run folder, with a live display."""

from __future__ import annotations

import sys
import threading
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.panel import Panel
from rich.prompt import Prompt
from rich.syntax import Syntax
from rich.table import Table

from socnavgen.cli.common import console, err_console, progress
from socnavgen.errors import SocnavgenError
from socnavgen.proposal.conversation import ProgressEvent
from socnavgen.proposal.review import ReviewDecision
from socnavgen.proposal.verify_loop import describe
from socnavgen.run import RunFolder, ScenarioRequest

TARGETS = ("socrates", "hunav2", "hunav1")
MAX_SHOWN_FAILURES = 10  # failing findings printed when --verify gives up (all are in sim/verify.json)
STAGE_TITLES = {"scenario": "stage 1 scenario", "paths": "stage 2 paths", "behaviors": "stage 3 trees",
                "naive": "naive (all at once)", "verify": "verify"}


class LiveProgress:
    """Turns pipeline events into one progress line per stage (and per human), attempts shown."""

    def __init__(self, bar) -> None:  # noqa: ANN001 - rich Progress
        self.bar = bar
        self.tasks: dict[tuple[str, str | None], int] = {}
        self.lock = threading.Lock()

    def __call__(self, event: ProgressEvent) -> None:
        with self.lock:
            label = STAGE_TITLES.get(event.stage, event.stage) + (f" {event.key}" if event.key else "")
            task = self.tasks.get((event.stage, event.key))
            if task is None:
                task = self.bar.add_task(label, total=1)
                self.tasks[(event.stage, event.key)] = task
            if event.kind == "attempt":
                extra = f" (restart {event.restart})" if event.restart else ""
                self.bar.update(task, description=f"{label}: attempt {event.attempt}{extra}")
            elif event.kind == "invalid":
                self.bar.update(task, description=f"{label}: attempt {event.attempt} invalid, re-asking")
            elif event.kind == "restart":
                self.bar.update(task, description=f"{label}: restarting the conversation")
            elif event.kind in ("done", "skipped"):
                note = f" ({event.message})" if event.message else ""
                self.bar.update(task, completed=1, description=f"{label}: {event.kind}{note}"[:100])
            elif event.kind == "failed":
                self.bar.update(task, description=f"{label}: FAILED")


def console_review(stage: str, key: str | None, result: str) -> ReviewDecision:
    """--review: show the stage's result and ask accept / retry / an edit request for the model."""
    lexer = "xml" if result.lstrip().startswith("<") else "json"
    title = STAGE_TITLES.get(stage, stage) + (f" {key}" if key else "")
    console.print(Panel(Syntax(result, lexer, word_wrap=True), title=title))
    answer = Prompt.ask("[bold]a[/]ccept, [bold]r[/]etry, or type what to change", default="a", console=console)
    text = answer.strip()
    if text.lower() in ("a", "accept", "y", "yes", ""):
        return ReviewDecision(action="accept")
    if text.lower() in ("r", "retry"):
        return ReviewDecision(action="retry")
    return ReviewDecision(action="edit", request=text)


def card_defaults(name: str) -> object:
    """The scenario card NAME (unknown names end with a did-you-mean message)."""
    from socnavgen.cards.library import get_card

    return get_card(name)


def _request(location: Path | None, context: str | None, task: str | None, rough: str | None, card: str | None,
             llm: str, from_run: Path | None, **settings: Any) -> ScenarioRequest:
    if from_run is not None:
        base = RunFolder(from_run).read_request()
        return base.model_copy(update={"llm": llm, **{k: v for k, v in settings.items() if k != "naive"}})
    if card:
        found = card_defaults(card)
        rough = rough or getattr(found, "rough", None)
        context = context or getattr(found, "context", None)
        task = task or getattr(found, "task", None)
    missing = [name for name, value in (("--location", location), ("--context", context), ("--task", task))
               if not value]
    if missing:
        raise SocnavgenError(f"missing {', '.join(missing)}",
                             hint="give the location folder, the social context and the robot task "
                                  "(or --from RUN to continue a run)")
    assert context is not None and task is not None  # not missing
    return ScenarioRequest(location=str(location), context=context, task=task, rough=rough, card=card, llm=llm,
                           **settings)


def _summary(run, folder: RunFolder) -> None:  # noqa: ANN001 - a proposal.Run
    manifest = run.manifest
    table = Table(title=f"run {folder.root}  ({manifest.status})")
    for column in ("stage", "status", "attempts", "restarts", "tokens in/out", "seconds"):
        table.add_column(column, justify="right" if column not in ("stage", "status") else "left")
    total_in = total_out = 0
    for name, record in manifest.stages.items():
        if ":" not in name:
            total_in += record.prompt_tokens
            total_out += record.completion_tokens
        table.add_row(name, record.status, str(record.attempts), str(record.restarts),
                      f"{record.prompt_tokens}/{record.completion_tokens}", f"{record.seconds:.1f}")
    console.print(table)
    console.print(f"[bold]scenario[/]: {run.scenario.scenario_description}", highlight=False)
    console.print(f"[bold]robot[/]: {' -> '.join(run.paths.robot)}", highlight=False)
    for human in run.paths.humans:
        group = f", group {human.group_id}" if human.group_id >= 0 else ""
        meet = f", meets the robot at {human.interaction_point}" if human.interaction_point else ""
        console.print(f"[bold]{human.name}[/]: {' -> '.join(human.path)}{group}{meet}", highlight=False)
    spec = getattr(run, "spec", None)
    for encounter in spec.encounters if spec is not None else []:
        who = ", ".join(f"{p.human} {p.reaction} on {p.trigger}" for p in encounter.humans)
        console.print(f"[bold]encounter {encounter.id}[/] at {encounter.node or encounter.place}: {who}",
                      highlight=False)
    files = [folder.request_path, folder.scenario_path, folder.spec_path, folder.paths_path,
             *[folder.behavior_path(h) for h in run.behaviors], folder.transcript_path, folder.manifest_path]
    root = folder.root.resolve()
    console.print("files: " + ", ".join(str(p.resolve().relative_to(root)) for p in files if p.exists()),
                  highlight=False)
    console.print(f"tokens: {total_in} in, {total_out} out", highlight=False)


def _export_check(folder: RunFolder, target: str | None) -> None:
    """Say now which export targets will refuse the trees (an export weeks later should not be the first to
    tell): a warning for the run's own --target, a note for the others."""
    from socnavgen.export import hunav2_approximations, target_refusals

    if not folder.paths_path.is_file() or not folder.behaviors():
        return
    try:
        refused = target_refusals(folder.root)
        approximated = hunav2_approximations(folder.root) if "hunav2" not in refused else []
    except SocnavgenError:
        return  # the run is incomplete or invalid: generate has already said why
    if approximated and target == "hunav2":  # HuNavSim 2.x cannot hear the robot: say what its trees hear instead
        console.print("note: `export --format hunav2` approximates what the robot says: "
                      + "; ".join(approximated[:4]) + (f" (and {len(approximated) - 4} more)" if len(approximated) > 4
                                                      else ""), highlight=False)
    for fmt, message in refused.items():
        if fmt == "hunav1" and target != "hunav1":
            continue  # 1.x runs only its built-in behaviors: refusing custom trees is its nature, not news
        first = message.splitlines()[0]
        detail = "; ".join(line.strip() for line in message.splitlines()[1:4])
        if fmt == (target or "socrates"):
            err_console.print(f"[yellow]warning[/]: `export --format {fmt}` (this run's target) will refuse it: "
                              f"{first} {detail}", highlight=False)
        else:
            console.print(f"[dim]note: `export --format {fmt}` will refuse it: {first} {detail}[/]", highlight=False)


def register(app: typer.Typer) -> None:
    """Add `generate` to the main app."""

    @app.command("generate")
    def generate_command(
        location: Annotated[Path | None, typer.Option(
            "--location", "-l", help="Location folder (location.yaml, map, scene_graph.json).")] = None,
        context: Annotated[str | None, typer.Option(
            "--context", "-c", help="Social context, e.g. 'Delivery robot in a small warehouse'.")] = None,
        task: Annotated[str | None, typer.Option("--task", "-t", help="The robot's task.")] = None,
        rough: Annotated[str | None, typer.Option(
            "--rough", "-r", help="Optional rough scenario the result must follow.")] = None,
        card: Annotated[str | None, typer.Option(
            "--card", help="Take the rough scenario (and defaults) from a scenario card, e.g. frontal-approach.")
        ] = None,
        llm: Annotated[str, typer.Option(
            "--llm", help="Model: local (offline SmolLM2-135M), gguf:PATH, openai:MODEL[@BASE_URL], "
                          "replay:FILE.")] = "local",
        out: Annotated[Path | None, typer.Option(
            "--out", "-o", help="Run folder to write (re-running on it resumes where it stopped).")] = None,
        proposals: Annotated[int, typer.Option(
            "--proposals", min=1, max=10, help="Ask for N distinct scenario proposals (all kept in proposals.json).")
        ] = 1,
        pick: Annotated[int, typer.Option("--pick", min=1, help="Which proposal to use (1 = the first).")] = 1,
        max_restarts: Annotated[int, typer.Option(
            "--max-restarts", min=0, max=20,
            help="Conversation restarts per stage after 3 failed corrections.")] = 2,
        no_cache: Annotated[bool, typer.Option("--no-cache", help="Ask the model again instead of reusing "
                                                                  "cached replies.")] = False,
        no_image: Annotated[bool, typer.Option("--no-image", help="Do not send the annotated map image.")] = False,
        max_parallel: Annotated[int, typer.Option("--max-parallel", min=1, max=32,
                                                  help="Requests in flight (behavior trees are asked in parallel).")
                                ] = 4,
        seed: Annotated[int, typer.Option("--seed", help="Seed of the generated tutorial and examples.")] = 0,
        temperature: Annotated[float, typer.Option("--temperature", min=0.0, max=2.0,
                                                   help="Sampling temperature (raised on restarts).")] = 0.0,
        review: Annotated[bool, typer.Option("--review", help="Stop after each stage: accept, retry, or type an "
                                                              "edit request for the model.")] = False,
        verify: Annotated[bool, typer.Option("--verify", help="Simulate the result and re-ask the blamed stage "
                                                              "when the intended interaction does not happen.")
                          ] = False,
        naive: Annotated[bool, typer.Option("--naive", help="Baseline: one prompt for everything, no tutorials "
                                                            "or examples (for evaluation).")] = False,
        export_target: Annotated[str | None, typer.Option(
            "--target", help="Export target (socrates, hunav2, hunav1): only nodes it can run are offered and "
                             "accepted.")] = None,
        timeout: Annotated[float, typer.Option(
            "--timeout", min=1.0, max=86400.0,
            help="Seconds one model request may take (a big local model on a CPU needs minutes).")] = 120.0,
        deadline: Annotated[float, typer.Option(
            "--deadline", min=1.0, max=86400.0,
            help="Seconds one model exchange may take, retries included (at least --timeout).")] = 600.0,
        from_run: Annotated[Path | None, typer.Option(
            "--from", help="Start from an earlier run (copied to --out if given, else changed in place).")] = None,
        redo: Annotated[list[str] | None, typer.Option(
            "--redo", help="With --from: regenerate this stage (scenario, paths or behaviors) and the ones after "
                           "it; repeatable.")] = None,
    ) -> None:
        """Generate a scenario: a textual scenario, robot and human paths on the scene graph, and a behavior
        tree per human, every answer validated and re-asked on mistakes.

        Example:

          socnavgen generate --location examples/locations/warehouse \\
            --context "Delivery robot in a small warehouse; employees walk around" \\
            --task "Transport a box from one point to another" \\
            --rough "The robot turns at a blind corner and meets a human who stops" \\
            --llm openai:gpt-4o --out runs/blind_corner

        Redo the paths (and trees) of that run with another model, keeping its scenario:

          socnavgen generate --from runs/blind_corner --redo paths --llm local --out runs/blind_corner_v2
        """
        from socnavgen.errors import LLMError
        from socnavgen.llm import make_llm
        from socnavgen.proposal import generate
        from socnavgen.proposal.pipeline import copy_run

        if redo and from_run is None:
            raise SocnavgenError("--redo needs --from RUN", hint="e.g. --from runs/x --redo paths")
        target = out or from_run
        if target is None:
            raise SocnavgenError("missing --out", hint="name the run folder to write, e.g. --out runs/my_scenario")
        if review and not sys.stdin.isatty():
            raise SocnavgenError("--review needs an interactive terminal (stdin is not one)",
                                 hint="run it in a terminal, or leave out --review")
        if export_target is not None and export_target not in TARGETS:
            raise SocnavgenError(f"unknown --target {export_target!r}", hint=f"use one of {', '.join(TARGETS)}")
        if pick > proposals:
            raise SocnavgenError(f"--pick {pick} but only {proposals} proposal(s) are asked for",
                                 hint="raise --proposals or lower --pick")
        settings = dict(proposals=proposals, pick=pick - 1, max_restarts=max_restarts, naive=naive, seed=seed,
                        temperature=temperature, use_image=not no_image,
                        **({"target": export_target} if export_target is not None else {}))
        if from_run is None:  # every input checked before anything is written (no empty run folder on a typo)
            request = _request(location, context, task, rough, card, llm, None, **settings)
        folder = RunFolder(target)
        # the model is built (spec parsed, key read from the environment) before the run folder exists
        model = make_llm(llm, transcript=folder.transcript_path, use_cache=not no_cache, max_parallel=max_parallel,
                         use_image=not no_image, timeout=timeout, deadline=max(deadline, timeout))
        # one writer per run folder: a second generate on it is refused, not interleaved
        folder.hold_lock()
        if from_run is not None:
            if out is not None and Path(out).resolve() != Path(from_run).resolve():
                copy_run(from_run, out)
            request = _request(location, context, task, rough, card, llm, from_run, **settings)
        created = not folder.root.exists()
        folder.root.mkdir(parents=True, exist_ok=True)
        try:
            with progress() as bar:
                result = generate(request, model, target, redo=set(redo or []) or None,
                                  review=console_review if review else None, progress=LiveProgress(bar),
                                  verify=verify)
        except LLMError:
            _forget_if_empty(folder, created)
            raise
        _summary(result, folder)
        _export_check(folder, request.target)
        if verify and result.verify is not None and result.verify.passed:
            record = result.manifest.stages.get("verify") if result.manifest is not None else None
            simulations = f" after {record.attempts} simulation(s)" if record is not None else ""
            required = [f for f in result.verify.findings if f.required]
            console.print(f"[green]verified[/]: every required criterion held ({len(required)} checked{simulations}; "
                          f"sim/verify.json, `socnavgen verify {folder.root}` shows each)", highlight=False)
        if verify and result.verify is not None and not result.verify.passed:
            failing = result.verify.failures
            err_console.print(f"[red]the verifier still finds problems[/] (manifest status: failed): {len(failing)} "
                              f"failing, in sim/verify.json (`socnavgen verify {folder.root}` shows all):",
                              highlight=False)
            for finding in failing[:MAX_SHOWN_FAILURES]:
                err_console.print(f"  FAIL {describe(finding)}", markup=False, highlight=False)
            raise typer.Exit(1)


def _forget_if_empty(folder: RunFolder, created: bool) -> None:
    """A run folder this command created, for a model that never answered (server unreachable, key refused):
    no reply came, so the folder (request, manifest, transcript of the failed exchange) goes. A folder with any
    reply is kept: its manifest says why the stage failed."""
    import shutil

    from socnavgen.llm.transcript import read_transcript

    if not created:
        return
    try:
        answered = any(entry.get("raw") is not None for entry in read_transcript(folder.transcript_path)) \
            if folder.transcript_path.is_file() else False
    except Exception:  # noqa: BLE001 - an unreadable transcript: keep the folder, say nothing more
        return
    if not answered:
        shutil.rmtree(folder.root, ignore_errors=True)
