"""`socnavgen eval`: the paper's Tables I-III on any model."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import typer
from rich.table import Table

from socnavgen.cli.common import console, print_machine, progress


def register(app: typer.Typer) -> None:
    """Add `eval` to the main app."""
    app.command("eval")(evaluate)


def _table(title: str, rows: list, key: str) -> Table:  # noqa: ANN001 - pydantic rows
    """Metrics as rows, one column per method/scene: readable in an 80-column terminal."""
    from socnavgen.evaluation.report import _fmt

    table = Table(title=title)
    if not rows:
        return table
    table.add_column("")
    for r in rows:
        table.add_column(_fmt(getattr(r, key)) + (" (rough)" if getattr(r, "rough", False) else ""), justify="right")
    for f in type(rows[0]).model_fields:
        if f in (key, "rough"):
            continue
        table.add_row(f.replace("_", " "), *(_fmt(getattr(r, f)) for r in rows))
    return table


def evaluate(
    llm: str = typer.Option("local", "--llm", help="model to evaluate: openai:MODEL[@URL], gguf:PATH, local, replay:FILE"),
    out: Path = typer.Option(Path("eval_out"), "--out", "-o", help="folder for runs and results (re-run to resume)"),
    runs: int = typer.Option(5, "--runs", min=1, help="runs per scene and method for Tables II-III (paper: 5)"),
    proposals: int = typer.Option(5, "--proposals", min=1, help="proposals per context for Table I (paper: 5)"),
    tables: str = typer.Option("I,III", "--tables", help="which tables: I, III or I,III"),
    methods: str = typer.Option("ours,naive", "--methods", help="ours, naive or both"),
    suite_file: Path | None = typer.Option(None, "--suite", help="YAML with your own scenes (see --show-suite)"),
    location: str | None = typer.Option(None, "--location", help="location folder (overrides the suite's)"),
    verify: bool = typer.Option(True, "--verify/--no-verify", help="simulate and verify every valid run"),
    no_cache: bool = typer.Option(False, "--no-cache", help="do not reuse cached replies"),
    temperature: float = typer.Option(0.7, "--temperature", help="sampling temperature (runs differ above 0)"),
    max_restarts: int = typer.Option(2, "--max-restarts", min=0, help="conversation restarts per stage"),
    show_suite: bool = typer.Option(False, "--show-suite", help="print the bundled suite YAML and exit"),
    fixtures: Path | None = typer.Option(None, "--fixtures", help="instead: replay the recorded model fixtures "
                                                                  "in this folder, verify them, print Table III"),
) -> None:
    """Measure scenario, path and behavior-tree validity as the SocRATES paper did, on any model.

    Example: socnavgen eval --llm openai:gpt-4o --runs 5 --out eval_gpt4o

    Writes OUT/results.md (tables with model, settings and date), OUT/results.csv (one row per run),
    OUT/ratings.md (Table I proposals to rate by hand) and OUT/runs/ (every run folder). Re-running
    with the same OUT resumes: finished runs are read back, not asked again.
    """
    from socnavgen.evaluation.harness import EvalSettings, run_eval
    from socnavgen.evaluation.report import table1, table3, write_reports
    from socnavgen.evaluation.suite import DEFAULT_SUITE, load_suite

    if show_suite:
        print_machine((resources.files("socnavgen.evaluation") / "data" / DEFAULT_SUITE).read_text())
        return
    if fixtures is not None:
        _replay_fixtures(fixtures, out, verify)
        return
    suite = load_suite(suite_file)
    settings = EvalSettings(llm=llm, out=out, runs=runs, proposals=proposals,
                            tables=[t.strip() for t in tables.split(",") if t.strip()],
                            methods=[m.strip() for m in methods.split(",") if m.strip()], verify=verify,
                            use_cache=not no_cache, temperature=temperature, max_restarts=max_restarts)
    where = location or suite.location
    from socnavgen.evaluation.harness import plan_jobs

    total = len(plan_jobs(suite, settings, where))
    with progress() as bar:
        task = bar.add_task(f"evaluating {llm}", total=total)

        def advance(job, outcome) -> None:  # noqa: ANN001
            state = "valid" if (outcome.valid or outcome.scenario_valid and job.table == "I") else "invalid"
            bar.update(task, advance=1, description=f"{job.table} {job.scene} {job.method} #{job.index}: {state}")

        outcomes = run_eval(suite, settings, where, on_result=advance)
    from socnavgen.run import RunFolder

    manifests = (RunFolder(Path(o.folder)) for o in outcomes)
    model = next((m.read_manifest().model for m in manifests if m.manifest_path.is_file()), None)
    shown = settings.model_dump(mode="json")
    files = write_reports(out, outcomes, suite, shown, model)
    if "III" in settings.tables:
        console.print(_table("Table III: path / behavior-tree validity", table3(outcomes, suite), "method"))
    if "I" in settings.tables:
        console.print(_table("Table I: proposals passing stage-1 checks", table1(outcomes), "scene"))
    console.print("wrote " + ", ".join(str(f) for f in files))


def _replay_fixtures(folder: Path, out: Path, verify: bool) -> None:
    """`eval --fixtures DIR`: Table III's 'verified in simulation' over recorded capable-model replies."""
    from socnavgen.errors import SocnavgenError
    from socnavgen.evaluation.fixtures import fixture_paths, fixtures_markdown, replay_fixture
    from socnavgen.safeio import atomic_write_text

    paths = fixture_paths(folder)
    if not paths:
        raise SocnavgenError("no fixture with a recorded request in this folder", file=folder,
                             hint="fixtures are YAML files with `request:` and `stages:` (tests/fixtures/replay)")
    rows = []
    with progress() as bar:
        task = bar.add_task("replaying fixtures", total=len(paths))
        for path in paths:
            rows.append(replay_fixture(path, out / "fixtures" / path.stem, root=Path.cwd(), verify=verify,
                                       first_answers=True))
            bar.update(task, advance=1, description=f"{path.stem}: verified={rows[-1].verified}")
    text = fixtures_markdown(rows)
    out.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out / "fixtures.md", text + "\n")
    console.print(text, markup=False)
    console.print(f"wrote {out / 'fixtures.md'}")
