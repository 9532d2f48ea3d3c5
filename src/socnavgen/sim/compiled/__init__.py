"""The whole episode in one compiled call (numba): behavior trees, interaction pacing, the robot's script,
the built-in robot policies, physics and the trace, with no Python between two steps.

Campaigns run thousands of episodes; in Python a 5-person step costs ~40 us (five trees, the robot policy,
pacing, bookkeeping) against ~3 us of arithmetic. This package is the compiled twin of `sim.engine`,
`sim.bt_runtime`, `sim.nodes`, `sim.nodes_hunav2`, `sim.interaction`, `sim.gestures` and the built-in
policies of `sim.robot`: those modules stay the readable reference (and the only path for a user's own
robot policy); every constant is imported from them, and tests/sim/test_compiled.py checks that both paths
give the same trace on every scenario card and robot.

`Simulation.run()` takes this path by itself when it can (`episode.run_compiled`; otherwise the trace's
meta["compiled_skipped"] says why: a policy class of the user's, a tree whose blackboard holds text...); a
tree that fails while running (a port reading an unset key) makes the compiled run give up and the
reference run raises the error with its file and line.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

_HERE = Path(__file__).resolve().parent
# the package's own files, and those whose functions or constants its compiled code takes in
_SOURCES = [*sorted(_HERE.glob("*.py")), *(_HERE.parent / f"{name}.py" for name in
                                          ("kernels", "nodes", "robot", "gestures", "agents", "interaction")),
            _HERE.parents[1] / "bt" / "library.py", _HERE.parents[1] / "bt" / "hunav2_facts.py"]


def _drop_stale_cache() -> None:
    """numba keys a cached function on its own file only, and a function here links code from the other
    files of this package and from sim.kernels, and freezes constants of the reference modules: when any of
    them changed since the cache was written, the cached episode would run old code. So the package's cache goes whenever their sources differ from the
    stamp it was written with (best effort: an unwritable folder just keeps numba's own behaviour)."""
    cache = _HERE / "__pycache__"
    try:
        digest = hashlib.sha256(b"".join(p.read_bytes() for p in _SOURCES)).hexdigest()
        stamp = cache / "compiled-sources.sha256"
        if stamp.is_file() and stamp.read_text() == digest:
            return
        cache.mkdir(exist_ok=True)
        for path in list(cache.glob("*.nbi")) + list(cache.glob("*.nbc")):
            path.unlink(missing_ok=True)
        tmp = cache / f".stamp-{os.getpid()}"
        tmp.write_text(digest)
        tmp.replace(stamp)
    except OSError:
        pass


def cache_ready() -> bool:
    """Whether this machine has the compiled episode cached (numba compiles it on first use: ~40 s)."""
    return any((_HERE / "__pycache__").glob("loop.run_episode-*.nbi"))


COMPILING_NOTE = ("first compiled run on this machine: numba compiles the simulator once (about 40 s per "
                  "process that starts at the same time); later runs start at once")

_drop_stale_cache()
