"""Size of the stage-1/2/3 prompts on the three bundled locations, in characters and in tokens.

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
from socnavgen.proposal.behaviors import behavior_messages
from socnavgen.proposal.paths import paths_messages
from socnavgen.proposal.scenario import scenario_messages

ROOT = Path(__file__).resolve().parents[1]
CASES = (("warehouse", "blind-corner"), ("hospital", "entering-elevator"), ("home", "narrow-doorway"))


def counter():  # noqa: ANN201 - a function messages -> tokens, and its name
    try:
        from socnavgen.llm.backends.gguf_backend import smollm2_path, vocab_tokenizer
        tokens = vocab_tokenizer(smollm2_path())
        return (lambda messages: len(tokens(messages))), "SmolLM2 tokens"
    except Exception:  # noqa: BLE001 - no llama-cpp / model: the estimate
        from socnavgen.llm.budget import estimate_tokens
        return estimate_tokens, "tokens (estimate)"


def main() -> int:
    count, unit = counter()
    print(f"| location | stage | characters | {unit} |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for location_name, card in CASES:
            folder = ROOT / "examples" / "locations" / location_name
            run = write_card_run(card, folder, Path(tmp) / location_name)
            location = load_location(folder)
            request, scenario, spec, plan = run.read_request(), run.read_scenario(), run.read_spec(), run.read_paths()
            stages: dict[str, list[ChatMessage]] = {
                "1 scenario": scenario_messages(request, location),
                "2 paths": paths_messages(location, scenario, spec=spec),
                "3 tree (human1)": behavior_messages("human1", scenario, plan, spec),
            }
            for stage, messages in stages.items():
                chars = sum(len(m.content) for m in messages)
                print(f"| {location_name} | {stage} | {chars} | {count(messages)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
