"""`replay:FILE`: scripted replies, so every pipeline path (re-queries included) runs without a model.

FILE is either a script (YAML or JSON)::

    stages:
      scenario: ["<raw reply 1>", "<raw reply 2>"]   # a list: consumed in order, whatever the key
      behaviors:                                      # a mapping: per key (human name), in order
        human1: ["...", "..."]

or a recorded transcript.jsonl, whose replies are replayed per (stage, key) in recorded order, so a
recorded run reproduces exactly.
"""

from __future__ import annotations

import json
import threading
from collections import deque
from pathlib import Path
from typing import Any

from socnavgen.errors import InputFileError, LLMError
from socnavgen.llm.base import ChatMessage, Reply
from socnavgen.llm.engine import Backend, Completion, ImageRef, LLMOptions, Message, Request, T, load_image
from socnavgen.llm.transcript import read_transcript
from socnavgen.safeio import load_yaml_file

ANY_KEY = object()  # a stage scripted as a plain list answers every key


def _as_raw(reply: Any, file: Path, where: str) -> str:
    if isinstance(reply, str):
        return reply
    if isinstance(reply, dict | list):  # a structured reply written inline in YAML: send it as JSON
        return json.dumps(reply, ensure_ascii=False)
    raise InputFileError(f"{where}: a reply must be a string (or a mapping/list written as JSON), "
                         f"got {type(reply).__name__}", file=file)


def load_script(path: Path) -> dict[tuple[str, Any], deque[str]]:
    """(stage, key or ANY_KEY) -> replies in order."""
    path = Path(path)
    queues: dict[tuple[str, Any], deque[str]] = {}
    if path.suffix == ".jsonl":
        if not path.is_file():
            raise InputFileError("replay transcript not found", file=path)
        for entry in read_transcript(path):
            if isinstance(entry.get("raw"), str) and isinstance(entry.get("stage"), str):
                queues.setdefault((entry["stage"], entry.get("key")), deque()).append(entry["raw"])
        if not queues:
            raise InputFileError("the transcript holds no replies to replay", file=path)
        return queues
    data = load_yaml_file(path)
    stages = data.get("stages") if isinstance(data, dict) else None
    if not isinstance(stages, dict):
        raise InputFileError("a replay script needs a top-level 'stages:' mapping", file=path,
                             hint="stages: {scenario: ['<reply>'], behaviors: {human1: ['<reply>']}}")
    for stage, replies in stages.items():
        if isinstance(replies, list):
            queues[(str(stage), ANY_KEY)] = deque(_as_raw(r, path, f"stages.{stage}") for r in replies)
        elif isinstance(replies, dict):
            for key, per_key in replies.items():
                if not isinstance(per_key, list):
                    per_key = [per_key]
                queues[(str(stage), str(key))] = deque(
                    _as_raw(r, path, f"stages.{stage}.{key}") for r in per_key)
        elif isinstance(replies, str):
            queues[(str(stage), ANY_KEY)] = deque([replies])
        else:
            raise InputFileError(f"stages.{stage} must be a list of replies or a mapping key -> list",
                                 file=path)
    return queues


class ReplayBackend(Backend):
    kind = "replay"
    cacheable = False

    def __init__(self, spec: str, path: Path, options: LLMOptions) -> None:
        super().__init__(spec, "replay", options, supports_images=True, supports_grammar=False)
        self.path = Path(path)
        self._queues = load_script(self.path)
        self._scripted = {k: len(v) for k, v in self._queues.items()}
        self._lock = threading.Lock()
        self.calls: list[tuple[str, str | None, list[ChatMessage]]] = []

    def chat(self, messages: list[ChatMessage], schema: type[T], *, stage: str, key: str | None = None,
             grammar: str | None = None, temperature: float | None = None,
             max_tokens: int | None = None) -> Reply[T]:
        with self._lock:
            self.calls.append((stage, key, [m.model_copy(deep=True) for m in messages]))
        return super().chat(messages, schema, stage=stage, key=key, grammar=grammar,
                            temperature=temperature, max_tokens=max_tokens)

    def _prepare(self, message: ChatMessage) -> Message:
        """Images are only recorded (name + hash) since no model looks at them; a missing one is noted."""
        images = []
        for path in message.images if self.supports_images else ():
            try:
                images.append(load_image(path))
            except LLMError:
                images.append(ImageRef(name=Path(path).name, sha256="missing", data=b""))
        return Message(role=message.role, content=message.content, images=tuple(images))

    def _complete(self, request: Request, timeout: float) -> Completion:
        stage, key = request.stage, request.key
        with self._lock:
            for queue_key in ((stage, key), (stage, ANY_KEY)):
                queue = self._queues.get(queue_key)
                if queue is None:
                    continue
                if queue:
                    return Completion(text=queue.popleft(), model="replay")
                raise LLMError(f"replay script has no reply left for stage '{stage}', key '{key}' "
                               f"(it scripted {self._scripted[queue_key]})", file=self.path,
                               hint="add replies for this stage and key to the script")
        raise LLMError(f"replay script has no replies for stage '{stage}', key '{key}'", file=self.path,
                       hint=f"add 'stages: {{{stage}: [...]}}' (or a per-key mapping) to the script")
