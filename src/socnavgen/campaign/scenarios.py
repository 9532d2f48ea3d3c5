"""Scenario sources -> a flat, ordered list of scenarios (a run folder + its location each).

Cards are instantiated once per campaign output folder (OUT/scenarios/<location>/<card>/), so a resumed
campaign and every worker see the very same run folders."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

from socnavgen.campaign.spec import CampaignSpec, CardsSource, FolderSource, RunsSource
from socnavgen.errors import InputFileError


@dataclass(frozen=True)
class Scenario:
    id: str  # unique in the campaign: "<location>/<card>" or the run folder's name
    run_dir: str
    location_dir: str
    source: str  # cards | runs | folder
    card: str | None
    location: str
    humans: int

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass
class Suite:
    scenarios: list[Scenario]
    skipped: list[str]  # "card on location: why it does not fit"


def _from_run(run_dir: Path, source: str, used: set[str], name: str | None = None) -> Scenario:
    from socnavgen.run import RunFolder

    run = RunFolder(run_dir)
    if not run.paths_path.is_file():
        raise InputFileError("not a run folder (no paths.json)", file=run_dir,
                             hint="list folders written by `socnavgen generate` or `cards generate`")
    location = run.location()
    plan = run.read_paths()
    card = run.read_request().card if run.request_path.is_file() else None
    base = name or run_dir.name
    sid, k = base, 2
    while sid in used:
        sid, k = f"{base}~{k}", k + 1
    used.add(sid)
    return Scenario(id=sid, run_dir=str(run_dir.resolve()), location_dir=str(Path(location.root).resolve()),
                    source=source, card=card, location=location.name, humans=len(plan.humans))


def build_suite(spec: CampaignSpec, out: Path) -> Suite:
    """Every scenario of the campaign, in file order; card runs are written under OUT/scenarios once."""
    out = Path(out)
    from socnavgen.cards.generate import place_card, write_card_run
    from socnavgen.cards.library import card_names, get_card
    from socnavgen.location import load_location

    scenarios: list[Scenario] = []
    skipped: list[str] = []
    used: set[str] = set()
    named: dict[str, Path] = {}  # location name -> its folder (cards are stored and named by location name)
    for source in spec.scenarios:
        if isinstance(source, RunsSource):
            scenarios += [_from_run(spec.resolve(r), "runs", used) for r in source.runs]
        elif isinstance(source, FolderSource):
            folder = spec.resolve(source.folder)
            if not folder.is_dir():
                raise InputFileError("scenario folder not found", file=folder, hint="check `folder:` in the campaign")
            runs = sorted(p for p in folder.iterdir() if (p / "paths.json").is_file())
            if not runs:
                raise InputFileError("no run folders (with paths.json) inside", file=folder)
            scenarios += [_from_run(r, "folder", used) for r in runs]
        elif isinstance(source, CardsSource):
            names = card_names() if source.cards == "all" else source.cards
            for loc_path in source.locations:
                loc_dir = spec.resolve(loc_path)
                location = load_location(loc_dir)
                first = named.setdefault(location.name, loc_dir.resolve())
                if first != loc_dir.resolve():
                    raise InputFileError(f"two locations are both named {location.name!r} ({first} and {loc_dir}): "
                                         "their scenarios would be mixed up",
                                         file=loc_dir / "location.yaml", hint="give one of them another `name:`")
                for name in names:
                    run_dir = out / "scenarios" / location.name / name
                    if not (run_dir / "paths.json").is_file():
                        fit = place_card(get_card(name), location)
                        if not fit.fits:
                            skipped.append(f"{name} on {location.name}: {fit.reason}")
                            continue
                        write_card_run(name, loc_dir.resolve(), run_dir)
                    scenarios.append(_from_run(run_dir, "cards", used, f"{location.name}/{name}"))
    if not scenarios:
        raise InputFileError("the campaign has no scenario that fits", hint="; ".join(skipped[:5]) or None)
    return Suite(scenarios, skipped)
