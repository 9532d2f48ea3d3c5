"""Speed of the in-process `local` model (SmolLM2-135M-Instruct GGUF) on this machine.

    python benchmarks/llm_local.py                 # 3 repeats of each case
    python benchmarks/llm_local.py --repeat 5 --spec gguf:/path/model.gguf

For a short and a long (SocRATES-sized) prompt, with and without the JSON-schema grammar, prints:
prompt and completion tokens, prompt-processing time, total latency and generation speed (tokens/s).
Prompt time is measured with a 1-token completion on a cleared KV cache; generation speed is
(completion tokens - 1) / (latency - prompt time). Load time is printed separately.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

from pydantic import BaseModel

from socnavgen.llm import ChatMessage, make_llm


class Scenario(BaseModel):
    scenario_description: str
    number_of_humans: int
    human_behaviors: dict[str, str]
    expected_robot_behavior: str


SHORT = ("Propose a social navigation test scenario for a delivery robot in a warehouse with two humans. "
         "Give a description, the number of humans, what human1 and human2 do, and what the robot should do.")


def long_prompt() -> str:
    """About 1,500 tokens: a scene graph listing like the path stage sends."""
    lines = ["Scene graph of the location (node id, type, pixel position; edges with type):"]
    kinds = ["OPEN AREA", "BLIND CORNER", "DOOR", "PASSAGEWAY", "INTERSECTION", "SHELF ROW"]
    for i in range(60):
        lines.append(f"node {i:02x}{'abcdefghij'[i % 10]}: {kinds[i % len(kinds)]} at ({30 + 7 * i}, {40 + 3 * i})")
    for i in range(59):
        lines.append(f"edge {i:02x}{'abcdefghij'[i % 10]} - {i + 1:02x}{'abcdefghij'[(i + 1) % 10]}: PASSAGEWAY")
    return "\n".join(lines) + "\n\n" + SHORT


def run_case(llm, prompt: str, constrained: bool, max_tokens: int) -> dict[str, float]:
    backend_llama = llm._load()
    llm.constrained = constrained
    messages = [ChatMessage(role="user", content=prompt)]
    backend_llama.reset()
    started = time.perf_counter()
    llm.chat(messages, Scenario, stage="bench", max_tokens=1)
    prompt_seconds = time.perf_counter() - started
    backend_llama.reset()
    started = time.perf_counter()
    reply = llm.chat(messages, Scenario, stage="bench", max_tokens=max_tokens)
    latency = time.perf_counter() - started
    gen = max(1, reply.usage.completion_tokens - 1)
    return {"prompt_tokens": reply.usage.prompt_tokens, "completion_tokens": reply.usage.completion_tokens,
            "prompt_s": prompt_seconds, "latency_s": latency,
            "prompt_tok_s": reply.usage.prompt_tokens / prompt_seconds,
            "gen_tok_s": gen / max(1e-6, latency - prompt_seconds), "valid": float(reply.ok)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--spec", default="local", help="local or gguf:PATH")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--max-tokens", type=int, default=200)
    parser.add_argument("--prompts", default="short,long", help="which prompts to run: short, long or both")
    args = parser.parse_args()

    started = time.perf_counter()
    llm = make_llm(args.spec, use_cache=False)
    llm._load()
    load_s = time.perf_counter() - started
    print(f"model: {llm.model}  ({args.spec}, n_ctx {llm.n_ctx}, {os.cpu_count()} cpus, "
          f"load {load_s:.2f} s, repeats {args.repeat}, max_tokens {args.max_tokens})")
    header = (f"{'prompt':<7}{'grammar':<9}{'prompt tok':>11}{'compl tok':>10}{'prompt s':>10}"
              f"{'latency s':>10}{'prompt tok/s':>13}{'gen tok/s':>10}{'valid':>7}")
    print(header)
    print("-" * len(header))
    chosen = {p.strip() for p in args.prompts.split(",")}
    for name, prompt in (("short", SHORT), ("long", long_prompt())):
        if name not in chosen:
            continue
        for constrained in (False, True):
            runs = [run_case(llm, prompt, constrained, args.max_tokens) for _ in range(args.repeat)]
            med = {k: statistics.median(r[k] for r in runs) for k in runs[0]}
            valid = sum(r["valid"] for r in runs)
            print(f"{name:<7}{'schema' if constrained else 'none':<9}{med['prompt_tokens']:>11.0f}"
                  f"{med['completion_tokens']:>10.0f}{med['prompt_s']:>10.2f}{med['latency_s']:>10.2f}"
                  f"{med['prompt_tok_s']:>13.0f}{med['gen_tok_s']:>10.1f}{f'{valid:.0f}/{len(runs)}':>7}")
    print("medians over repeats; 'valid' = replies that validated against the schema")


if __name__ == "__main__":
    main()
