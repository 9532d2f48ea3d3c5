"""Size of the stage-1/2/3 prompts on the three bundled locations, in characters and in tokens, whole and
as fitted to the `local` model's context (proposal/fit.py: what was left out to fit).

    python benchmarks/prompt_sizes.py            # tokens of SmolLM2-135M's tokenizer when installed

Each location gets a scenario card's run (no model): its request is stage 1's question, its scenario,
spec and paths are what stages 2 and 3 are asked about. Tokens are counted the way the pipeline counts
them when it fits a prompt to a model's context (the backend's tokenizer; an estimate without one).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

from socnavgen.cards.generate import write_card_run
from socnavgen.llm.base import ChatMessage
from socnavgen.location import load_location
from socnavgen.proposal.behaviors import behavior_messages, fitted_behavior_messages
from socnavgen.proposal.paths import fitted_paths_messages, paths_messages
from socnavgen.proposal.scenario import fitted_scenario_messages, scenario_messages

ROOT = Path(__file__).resolve().parents[1]
CASES = (("warehouse", "blind-corner"), ("hospital", "entering-elevator"), ("home", "narrow-doorway"))


class Model:
    """The `local` model's context and tokenizer (no weights loaded), or an 8192-token estimate without it."""

    supports_images = False

    def __init__(self) -> None:
        try:
            from socnavgen.llm import make_llm
            self.llm = make_llm("local", use_cache=False)
            self.context_tokens, self.unit = self.llm.context_tokens, "SmolLM2 tokens"
        except Exception:  # noqa: BLE001 - no llama-cpp / model: the estimate
            self.llm, self.context_tokens, self.unit = None, 8192, "tokens (estimate)"

    def count_tokens(self, messages: list[ChatMessage]) -> int:
        from socnavgen.llm.budget import estimate_tokens
        return self.llm.count_tokens(messages) if self.llm is not None else estimate_tokens(messages)


def rows(model: Model, location_name: str, card: str, tmp: Path) -> list[str]:
    folder = ROOT / "examples" / "locations" / location_name
    run = write_card_run(card, folder, tmp / location_name)
    location = load_location(folder)
    request, scenario, spec, plan = run.read_request(), run.read_scenario(), run.read_spec(), run.read_paths()
    notes: list[dict] = []
    stages = {
        "1 scenario": (scenario_messages(request, location), fitted_scenario_messages(
            request, location, model, note=notes.append)),
        "2 paths": (paths_messages(location, scenario, spec=spec, images=False), fitted_paths_messages(
            location, scenario, model, request, spec, note=notes.append)),
        "3 tree (human1)": (behavior_messages("human1", scenario, plan, spec), fitted_behavior_messages(
            "human1", scenario, plan, model, spec, note=notes.append)),
    }
    out = []
    for stage, (whole, fitted) in stages.items():
        cut = next((", ".join(n["left_out"]) for n in notes if n["stage"].startswith(stage.split()[1][:5])), "-")
        chars = sum(len(m.content) for m in whole)
        out.append(f"| {location_name} | {stage} | {chars} | {model.count_tokens(whole)} | "
                   f"{model.count_tokens(fitted)} | {cut} |")
    return out


def main() -> int:
    model = Model()
    print(f"| location | stage | characters | {model.unit} | fitted to {model.context_tokens} | left out |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for location_name, card in CASES:
            print("\n".join(rows(model, location_name, card, Path(tmp))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
