"""Where batches of episodes run: in this process, in local worker processes (default, all cores), or on a
Ray cluster. Every executor calls the same episode.run_batch, so the rows are identical; only the order in
which they arrive differs (the store sorts them).

One driver (`run_work`) feeds every executor and survives what kills a worker: a batch whose worker died
(os._exit, the OOM killer, a signal) or was stopped at its hard limit comes back as an exception; its
episodes are then run again one per task, and an episode that loses its worker on its own fails with the
reason, while the executor replaces the worker. The hard limit of a batch is its episodes' wall-clock
limits plus a grace: the episode's own deadline (SIGALRM in the worker) ends an ordinary overrun well
before, the hard limit ends a policy that swallows even that."""

from __future__ import annotations

import multiprocessing
import os
import signal
import time
from collections import deque
from collections.abc import Callable, Iterator
from concurrent import futures
from typing import Any

from socnavgen.campaign.episode import Episode, EpisodeSettings, failed_row, run_batch, warm_up_compiled

Rows = list[dict[str, Any]]
POLL_SECONDS = 0.5  # how often the driver looks for tasks past their hard limit


def batches(episodes: list[Episode], size: int) -> list[list[Episode]]:
    """Consecutive slices (episodes are ordered by location and scenario, so a batch mostly shares a map)."""
    return [episodes[i:i + size] for i in range(0, len(episodes), size)]


def grace_seconds(settings: EpisodeSettings) -> float:
    """How long past its wall-clock limit an episode may take before its worker is stopped."""
    return max(2.0, settings.wall_timeout / 2)


def timeout_reason(settings: EpisodeSettings) -> str:
    return (f"timeout: episode exceeded its wall-clock limit of {settings.wall_timeout:g} s and did not stop "
            "(its worker was stopped)")


def died_reason(exitcode: int | None) -> str:
    """Why a worker process ended, from its exit code (negative: the signal that killed it)."""
    if exitcode is None:
        return "crash: worker died"
    if exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = f"signal {-exitcode}"
        oom = " (as the kernel's out-of-memory killer does)" if -exitcode == signal.SIGKILL else ""
        return f"crash: worker died: killed by {name}{oom}"
    return f"crash: worker died (exit code {exitcode}: os._exit or a crash in native code)"


def run_work(executor: Any, work: list[list[Episode]], settings: EpisodeSettings) -> Iterator[Rows]:
    """Rows of every batch of `work`, as they finish. A batch that comes back without rows (its worker died or
    was stopped) is run again one episode per task; a single episode that does fails with the reason."""
    queue = deque(work)
    pending: dict[futures.Future, tuple[list[Episode], float]] = {}
    try:
        while queue or pending:
            while queue and len(pending) < executor.capacity:
                batch = queue.popleft()
                limit = len(batch) * settings.wall_timeout + grace_seconds(settings) + executor.slack
                pending[executor.submit(batch, settings, limit)] = (batch, time.monotonic())
            done, _ = futures.wait(pending, timeout=POLL_SECONDS, return_when=futures.FIRST_COMPLETED)
            executor.expire()
            for future in done:
                batch, started = pending.pop(future)
                try:
                    rows = future.result()
                except Exception as exc:  # noqa: BLE001 - the batch's worker is gone; its episodes are not
                    if len(batch) > 1:
                        queue.extendleft([ep] for ep in reversed(batch))
                        continue
                    rows = [failed_row(batch[0], executor.reason(exc, settings), time.monotonic() - started)]
                yield rows
    finally:
        for future in pending:
            future.cancel()


class InlineExecutor:
    """Everything in the calling process (debugging, profiling; the benchmark's one-process number). The
    episode's deadline stops a policy stuck in act(); one that swallows every exception, or ends the process,
    ends the campaign: use the local executor for untrusted policies."""

    name = "inline"
    capacity = 1
    slack = 0.0

    def __init__(self, **_: Any) -> None:
        pass

    def submit(self, batch: list[Episode], settings: EpisodeSettings, limit: float) -> futures.Future:  # noqa: ARG002
        future: futures.Future = futures.Future()
        future.set_result(run_batch(batch, settings))
        return future

    def expire(self) -> None:
        pass

    def reason(self, exc: BaseException, settings: EpisodeSettings) -> str:  # noqa: ARG002
        return f"crash: {type(exc).__name__}: {exc}"

    def close(self) -> None:
        pass


def _worker_start() -> None:
    """In each new local worker: the terminal's hang-up is the parent's to handle (the CLI's handler would
    print a traceback here), and the compiled simulator is ready before the first episode's clock starts."""
    signal.signal(signal.SIGHUP, signal.SIG_DFL)
    warm_up_compiled()


class LocalExecutor:
    """A pool of worker processes (default: one per core; pebble), each keeping its own location cache. A
    worker that dies or passes a batch's hard limit is stopped and replaced; its batch comes back as an
    exception (pebble's ProcessExpired / TimeoutError)."""

    name = "local"
    slack = 0.0  # the pool starts a task's clock when a worker takes it

    def __init__(self, workers: int | None = None, **_: Any) -> None:
        from pebble import ProcessPool

        self.workers = workers or os.cpu_count() or 1
        self.capacity = 2 * self.workers
        method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
        self.pool = ProcessPool(max_workers=self.workers, initializer=_worker_start,
                                context=multiprocessing.get_context(method))

    def submit(self, batch: list[Episode], settings: EpisodeSettings, limit: float) -> futures.Future:
        return self.pool.schedule(run_batch, args=(batch, settings), timeout=limit)

    def expire(self) -> None:
        pass  # the pool stops tasks past their timeout itself

    def reason(self, exc: BaseException, settings: EpisodeSettings) -> str:
        from pebble import ProcessExpired

        if isinstance(exc, TimeoutError):
            return timeout_reason(settings)
        if isinstance(exc, ProcessExpired):
            return died_reason(exc.exitcode)
        return f"crash: {type(exc).__name__}: {exc}"

    def close(self) -> None:
        self.pool.stop()  # every task is done (or abandoned on an interrupt): stop the workers now
        self.pool.join()


class RayExecutor:
    """Ray tasks: `address` joins an existing cluster ("auto" or host:port), None starts a local one that ends
    with the campaign. Ray keeps its worker processes, so each keeps its location cache between tasks. As many
    tasks are in flight as the cluster has CPUs, so a task starts when submitted; one past its hard limit is
    cancelled with its worker process (ray.cancel(force=True))."""

    name = "ray"
    slack = 30.0  # a task's clock starts at submission: Ray may still be starting its worker process

    def __init__(self, address: str | None = None, workers: int | None = None, **_: Any) -> None:
        import ray

        self.ray = ray
        self.started = not ray.is_initialized()
        if self.started:
            kwargs: dict[str, Any] = {"address": address, "include_dashboard": False, "log_to_driver": False,
                                      "configure_logging": False}
            if address is None:  # a private cluster on this machine, reachable only locally
                kwargs.update(num_cpus=workers or os.cpu_count() or 1, _node_ip_address="127.0.0.1")
            ray.init(**kwargs)
        self.remote = ray.remote(num_cpus=1, max_retries=0)(run_batch)
        self.capacity = max(1, int(ray.cluster_resources().get("CPU", 1)))
        self._settings: tuple[EpisodeSettings, Any] | None = None
        self._deadlines: dict[futures.Future, tuple[Any, float]] = {}

    def submit(self, batch: list[Episode], settings: EpisodeSettings, limit: float) -> futures.Future:
        if self._settings is None or self._settings[0] != settings:
            self._settings = (settings, self.ray.put(settings))
        ref = self.remote.remote(batch, self._settings[1])
        future = ref.future()
        self._deadlines[future] = (ref, time.monotonic() + limit)
        return future

    def expire(self) -> None:
        now = time.monotonic()
        for future, (ref, end) in list(self._deadlines.items()):
            if future.done():
                del self._deadlines[future]
            elif now > end:
                self.ray.cancel(ref, force=True)
                del self._deadlines[future]

    def reason(self, exc: BaseException, settings: EpisodeSettings) -> str:
        from ray import exceptions

        if isinstance(exc, exceptions.TaskCancelledError):
            return timeout_reason(settings)
        if isinstance(exc, exceptions.OutOfMemoryError):
            return "crash: worker died: killed by Ray's out-of-memory monitor"
        if isinstance(exc, exceptions.WorkerCrashedError | exceptions.NodeDiedError):
            return "crash: worker died (its process ended: os._exit, out of memory or a signal)"
        return f"crash: {type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"

    def close(self) -> None:
        if self.started:
            self.ray.shutdown()


EXECUTORS: dict[str, Callable[..., Any]] = {"inline": InlineExecutor, "local": LocalExecutor, "ray": RayExecutor}
