"""Prompts that fit the model's context.

A backend that knows its context (gguf and `local`: llm/budget.py) gets each stage's prompt only if the
prompt and the stage's longest answer fit in it. When they do not, the stage builds its prompt again
leaving out, one after the other in this order (CUTS), what a small model needs least:

1. `more_examples` - every worked example but the first of each stage (stage 1's example scenarios,
                     stage 2's map examples, stage 3's example trees);
2. `signals`       - how to write an stl criterion: its syntax, example and signals (stage 1; the kind
                     stays named, with "use the other kinds");
3. `inventory`     - the place inventory's detail lists (narrow passages, each blind turn's two ways and
                     how near it is seen, where groups fit), stage 1's node positions and its note that
                     the inventory beats the description's widths; the kinds of place with their nodes,
                     what cannot work, the doorways and where nobody can step aside stay;
4. `robot`         - what the robot does by itself (passing, making way) and where it stops, why a block can
                     end at once, the start rule (stage 2 states and checks it again), and the finer points
                     of how the spec plays out (the implied meeting, when a cue fires, robot_far from t = 0,
                     pacing on a round trip, group places, a follower turned round on) (stage 1; what its
                     script can and cannot do stays);
5. `examples`      - the last worked example (a small model copies the answer's shape from it: without
                     any, SmolLM2-135M wrote "Human 1" as a person's behavior);
6. `tutorials`     - the question-and-answer tutorials (stage 2's scene-graph tutorial, stage 3's tree
                     Q&A; the syntax rules stay).

The request (context, task, location, rough scenario, the scenario and its spec), the rules, the facts
(but for the detail of cut 4) and the answer format are never left out. A prompt that does not fit even then is an error naming its
size, the context and what to change. A conversation that grows by corrections is trimmed to its first
prompt and the latest correction (`fit_history`). Backends without a known context (a server) get every
prompt whole.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence

from socnavgen.errors import LLMError
from socnavgen.llm.base import LLM, ChatMessage
from socnavgen.llm.budget import context_tokens, count_tokens, prompt_room

log = logging.getLogger("socnavgen.proposal")

CUTS: tuple[str, ...] = ("more_examples", "signals", "inventory", "robot", "examples", "tutorials")
Cut = frozenset[str]
NOTHING: Cut = frozenset()


def examples_kept(left_out: Cut, examples: list) -> list:  # noqa: ANN001 - any list of examples
    """The worked examples a prompt keeps: all, the first, or none (CUTS 1 and 5)."""
    if "examples" in left_out:
        return []
    return examples[:1] if "more_examples" in left_out else list(examples)
Builder = Callable[[Cut], list[ChatMessage]]
Note = Callable[[dict], None]


def fit_prompt(llm: LLM, build: Builder, *, reply_tokens: int, stage: str, note: Note | None = None
               ) -> list[ChatMessage]:
    """`build(left_out)` with the fewest CUTS that let it and `reply_tokens` of answer fit the context."""
    room = prompt_room(llm, reply_tokens)
    if room is None:
        return build(NOTHING)
    size = 0
    for k in range(len(CUTS) + 1):
        left_out = frozenset(CUTS[:k])
        messages = build(left_out)
        size = count_tokens(llm, messages)
        if size <= room:
            if k:
                log.info("stage %s: prompt shortened to %d tokens to fit the context (left out: %s)",
                         stage, size, ", ".join(CUTS[:k]))
                if note is not None:
                    note({"kind": "fit", "stage": stage, "left_out": list(CUTS[:k]), "prompt_tokens": size,
                          "context_tokens": context_tokens(llm), "reply_tokens": reply_tokens})
            return messages
    raise LLMError(f"stage {stage}: the prompt takes {size} tokens even without {', '.join(CUTS)}; the model's "
                   f"context of {context_tokens(llm)} tokens leaves {room} for it after {reply_tokens} for the answer",
                   hint="give the model a longer context (gguf: SOCNAVGEN_GGUF_N_CTX, up to what the model was "
                        "trained for), or use a model with a longer context")


def fit_history(llm: LLM, history: Sequence[ChatMessage], first: int, reply_tokens: int) -> list[ChatMessage]:
    """A conversation of the first prompt (`first` messages) and corrections, trimmed to fit: the earlier
    answer/correction pairs go first, then the latest answer (its correction still names every mistake),
    then the correction itself (a restart)."""
    room = prompt_room(llm, reply_tokens)
    history = list(history)
    if room is None or count_tokens(llm, history) <= room:
        return history
    base, rest = history[:first], history[first:]
    for tail in (rest[-2:], rest[-1:]):
        if count_tokens(llm, [*base, *tail]) <= room:
            return [*base, *tail]
    return base
