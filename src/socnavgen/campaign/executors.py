"""Where batches of episodes run: in this process, in local worker processes (default, all cores), or on a
Ray cluster. Every executor calls the same episode.run_batch, so the rows are identical; only the order in
which they arrive differs (the store sorts them)."""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Iterator
from typing import Any

from socnavgen.campaign.episode import Episode, EpisodeSettings, run_batch

Rows = list[dict[str, Any]]


def batches(episodes: list[Episode], size: int) -> list[list[Episode]]:
    """Consecutive slices (episodes are ordered by location and scenario, so a batch mostly shares a map)."""
    return [episodes[i:i + size] for i in range(0, len(episodes), size)]


class InlineExecutor:
    """Everything in the calling process (what `--workers 1` uses; also the benchmark's one-process number)."""

    name = "inline"

    def __init__(self, **_: Any) -> None:
        pass

    def run(self, work: list[list[Episode]], settings: EpisodeSettings) -> Iterator[Rows]:
        for batch in work:
            yield run_batch(batch, settings)

    def close(self) -> None:
        pass


def _warm_up() -> None:
    """Load the compiled kernels once in the parent so forked workers do not each compile them."""
    from socnavgen.sim import warm_up

    warm_up()


class LocalExecutor:
    """A pool of worker processes (default: one per core); each keeps its own location cache."""

    name = "local"

    def __init__(self, workers: int | None = None, **_: Any) -> None:
        self.workers = workers or os.cpu_count() or 1
        _warm_up()
        method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
        self.pool = multiprocessing.get_context(method).Pool(self.workers)

    def run(self, work: list[list[Episode]], settings: EpisodeSettings) -> Iterator[Rows]:
        args = [(batch, settings) for batch in work]
        yield from self.pool.imap_unordered(_star_batch, args)

    def close(self) -> None:
        self.pool.terminate()
        self.pool.join()


def _star_batch(args: tuple[list[Episode], EpisodeSettings]) -> Rows:
    return run_batch(*args)


class RayExecutor:
    """Ray tasks: `address` joins an existing cluster ("auto" or host:port), None starts a local one that ends
    with the campaign. Ray keeps its worker processes, so each keeps its location cache between tasks."""

    name = "ray"

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
        self.in_flight = 2 * int(ray.cluster_resources().get("CPU", 1))

    def run(self, work: list[list[Episode]], settings: EpisodeSettings) -> Iterator[Rows]:
        ray = self.ray
        settings_ref = ray.put(settings)
        todo = list(reversed(work))
        pending: list[Any] = []
        while todo or pending:
            while todo and len(pending) < self.in_flight:
                pending.append(self.remote.remote(todo.pop(), settings_ref))
            ready, pending = ray.wait(pending, num_returns=1)
            yield ray.get(ready[0])

    def close(self) -> None:
        if self.started:
            self.ray.shutdown()


EXECUTORS: dict[str, Callable[..., Any]] = {"inline": InlineExecutor, "local": LocalExecutor, "ray": RayExecutor}
