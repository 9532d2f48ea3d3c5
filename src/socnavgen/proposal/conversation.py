"""The re-query / restart policy shared by every stage (SocRATES Sec. III-C).

A reply that cannot be read or breaks a rule is answered inside the same conversation: the model's
reply plus a user message listing EVERY mistake. After `max_requeries` corrections the conversation
is thrown away and restarted from the first prompt (a long chat of mistakes tends to confuse a model
more than it helps), with a slightly higher temperature so a deterministic model does not repeat
itself. After `max_restarts` restarts the stage fails with the last mistakes.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Generic, Literal, TypeVar

from pydantic import BaseModel

from socnavgen.errors import StageFailed
from socnavgen.llm.base import LLM, ChatMessage, Usage
from socnavgen.llm.transcript import Transcript, read_transcript, utc_now
from socnavgen.proposal.fit import fit_history
from socnavgen.proposal.templates import render
from socnavgen.run import Manifest, RunFolder, StageRecord

T = TypeVar("T", bound=BaseModel)
MAX_ECHO_CHARS = 12_000  # a runaway reply is cut before it goes back into the chat history
INTERRUPTED_WAIT = 2.0  # s: the most an interrupted run waits for the manifest lock (Recorder.save)


@dataclass
class Policy:
    max_requeries: int = 3
    max_restarts: int = 2
    temperature: float = 0.0
    restart_temperature_step: float = 0.3

    def temperature_for(self, restart: int) -> float:
        return min(1.0, self.temperature + self.restart_temperature_step * restart)


@dataclass
class ProgressEvent:
    stage: str
    key: str | None
    kind: Literal["start", "attempt", "invalid", "restart", "done", "failed", "skipped"]
    attempt: int = 0
    restart: int = 0
    message: str = ""


ProgressFn = Callable[[ProgressEvent], None]


def no_progress(event: ProgressEvent) -> None:
    """Default progress sink: silent."""


class Recorder:
    """Keeps manifest.json current (attempts, restarts, tokens, seconds, status) from any thread."""

    def __init__(self, run: RunFolder, manifest: Manifest, progress: ProgressFn = no_progress) -> None:
        self.run = run
        self.manifest = manifest
        self.progress = progress
        self._lock = threading.Lock()
        self.transcript = Transcript(run.transcript_path)

    def note(self, entry: dict) -> None:
        """A pipeline note in transcript.jsonl (e.g. a prompt shortened to fit the model's context)."""
        self.transcript.append({"time": utc_now(), **entry})

    def checked(self, stage: str, key: str | None, attempt: int, mistakes: list[str]) -> None:
        """The pipeline's verdict on a reply, beside the LLM layer's exchange in transcript.jsonl."""
        self.transcript.append({"kind": "check", "time": utc_now(), "stage": stage, "key": key, "attempt": attempt,
                                "valid": not mistakes, "mistakes": mistakes})

    def _records(self, stage: str, key: str | None, aggregate: bool = True) -> list[StageRecord]:
        """The keyed record (e.g. behaviors:human2) and, for counters, the stage's total too."""
        names = [stage] if key is None else [stage, f"{stage}:{key}"] if aggregate else [f"{stage}:{key}"]
        return [self.manifest.stages.setdefault(name, StageRecord()) for name in names]

    def save(self, interrupted: bool = False) -> None:
        """Write manifest.json. After an interrupt, never wait for ever: Ctrl+C or SIGTERM can land between a
        `with self._lock` acquiring the lock and entering its block, leaving it held by this very thread; the
        manifest is then written anyway after INTERRUPTED_WAIT s, so the run says `failed`, never `running`."""
        got = self._lock.acquire(timeout=INTERRUPTED_WAIT if interrupted else -1)
        try:
            self.run.write_manifest(self.manifest)
        finally:
            if got:
                self._lock.release()

    def update(self, stage: str, key: str | None, fn: Callable[[StageRecord], None], aggregate: bool = True) -> None:
        with self._lock:
            for record in self._records(stage, key, aggregate):
                fn(record)
            self.run.write_manifest(self.manifest)

    def set_status(self, stage: str, key: str | None, status: str) -> None:
        def apply(record: StageRecord) -> None:
            record.status = status  # type: ignore[assignment]
        self.update(stage, key, apply, aggregate=False)

    def attempt(self, stage: str, key: str | None, usage: Usage) -> None:
        def apply(record: StageRecord) -> None:
            record.attempts += 1
            record.prompt_tokens += usage.prompt_tokens
            record.completion_tokens += usage.completion_tokens
            record.seconds = round(record.seconds + usage.seconds, 3)
        self.update(stage, key, apply)

    def restart(self, stage: str, key: str | None) -> None:
        def apply(record: StageRecord) -> None:
            record.restarts += 1
        self.update(stage, key, apply)

    def mistakes(self, stage: str, key: str | None, mistakes: list[str]) -> None:
        def apply(record: StageRecord) -> None:
            record.errors = list(mistakes)
        self.update(stage, key, apply, aggregate=key is None)


class Upstream(str):
    """A mistake whose cause is an earlier stage's answer (a criterion's distance, an encounter's place or reaction):
    the text goes back to this stage as usual (it may still fix it its own way); `upstream` says what the stage that
    can change the cause should know, `key` names the cause (the same cause in the next answer: this stage could not
    fix it)."""

    key: str
    upstream: str

    def __new__(cls, text: str, *, key: str, upstream: str) -> Upstream:
        made = super().__new__(cls, text)
        made.key, made.upstream = key, upstream
        return made


class UpstreamFailed(StageFailed):
    """`stage` cannot satisfy a rule whose cause is an earlier stage's answer (`causes`); `said`: the reasoning of
    its last answer (its own words on why, for the earlier stage)."""

    def __init__(self, message: str, stage: str, causes: list[Upstream], said: str = "", *,
                 file: Path | str | None = None, hint: str | None = None) -> None:
        super().__init__(message, file=file, hint=hint)
        self.stage, self.causes, self.said = stage, causes, said


def upstream_causes(mistakes: list[str], told: set[str]) -> list[Upstream]:
    """The mistakes only an earlier stage can fix now: those this stage was already told of and answered again (it
    could not, or said it could not)."""
    return [m for m in mistakes if isinstance(m, Upstream) and m.key in told]


@dataclass
class Outcome(Generic[T]):
    value: T
    history: list[ChatMessage] = field(default_factory=list)  # the conversation, ending with the accepted reply


def accepted_reply(run: RunFolder, stage: str, key: str | None) -> str | None:
    """The model's own last accepted reply of a stage (and key) as it wrote it, reasoning included, from
    transcript.jsonl (None when there is none, e.g. a run made without a model): what a re-ask puts back
    into the conversation before the new request."""
    if not run.transcript_path.is_file():
        return None
    last: str | None = None
    accepted: str | None = None
    for entry in read_transcript(run.transcript_path):
        if entry.get("stage") != stage or entry.get("key") != key:
            continue
        if entry.get("kind") == "check":
            if entry.get("valid") and last is not None:
                accepted = last
        elif isinstance(entry.get("raw"), str):
            last = entry["raw"]
    return accepted[:MAX_ECHO_CHARS] if accepted is not None else None


def bullet_list(items: Sequence[str]) -> str:
    return "\n".join(f"- {item}" for item in items)


def correction_message(mistakes: list[str]) -> ChatMessage:
    return ChatMessage(role="user", content=render("correction.md", mistakes=bullet_list(mistakes)))


def converse(llm: LLM, messages: list[ChatMessage], schema: type[T], check: Callable[[T], list[str]], *,
             stage: str, key: str | None, recorder: Recorder, policy: Policy, grammar: str | None = None,
             max_tokens: int | None = None) -> Outcome[T]:
    """Ask until a reply passes `check`, re-querying with the mistakes and restarting per `policy`. A mistake caused
    by an earlier stage (`Upstream`) that comes back after this stage was told of it ends the conversation with
    UpstreamFailed: asking this stage again does not help (hospital_10, round 13: 12 answers, 2 restarts)."""
    last: list[str] = []
    attempts = 0
    told: set[str] = set()  # the Upstream causes this stage was told of
    if key is not None:
        recorder.set_status(stage, key, "running")
    for restart in range(policy.max_restarts + 1):
        history = list(messages)
        if restart:
            recorder.restart(stage, key)
            recorder.progress(ProgressEvent(stage, key, "restart", attempts, restart))
        for _ in range(policy.max_requeries + 1):
            attempts += 1
            recorder.progress(ProgressEvent(stage, key, "attempt", attempts, restart))
            history = fit_history(llm, history, len(messages), max_tokens or 0)
            reply = llm.chat(history, schema, stage=stage, key=key, grammar=grammar,
                             temperature=policy.temperature_for(restart), max_tokens=max_tokens)
            recorder.attempt(stage, key, reply.usage)
            if reply.value is None:
                mistakes = [reply.error or "the reply is not the JSON object that was asked for"]
            else:
                mistakes = check(reply.value)
            answer = ChatMessage(role="assistant", content=reply.raw[:MAX_ECHO_CHARS])
            recorder.checked(stage, key, attempts, mistakes)
            if not mistakes and reply.value is not None:  # a None value always has a mistake
                recorder.mistakes(stage, key, [])
                return Outcome(reply.value, [*history, answer])
            last = mistakes
            recorder.mistakes(stage, key, mistakes)
            causes = upstream_causes(mistakes, told)
            if causes:
                raise UpstreamFailed(f"stage '{stage}' cannot satisfy, within its own rules, what an earlier stage "
                                     f"asked:\n{bullet_list(causes)}", stage, causes,
                                     str(getattr(reply.value, "reasoning", "") or ""), file=recorder.run.root,
                                     hint="the earlier stage is asked to change it (generate does so itself)")
            told |= {m.key for m in mistakes if isinstance(m, Upstream)}
            recorder.progress(ProgressEvent(stage, key, "invalid", attempts, restart, "; ".join(mistakes)))
            history += [answer, correction_message(mistakes)]
    who = f"stage '{stage}'" + (f" for {key}" if key else "")
    raise StageFailed(f"{who} failed: no valid answer after {attempts} attempts ({policy.max_restarts} restarts). "
                      f"Last mistakes:\n{bullet_list(last)}",
                      file=recorder.run.root,
                      hint="the run folder keeps the transcript (transcript.jsonl); re-run to resume, or try "
                           "--max-restarts, another --llm, or --review")
