"""How the simulator is compiled: with numba when it is installed, as plain Python otherwise.

Every function of the episode (trees, leaves, pacing, the robot's script and policies, physics) is written
once, in the subset of Python that numba compiles, and decorated here. `SOCNAVGEN_NO_NUMBA=1` (or numba
missing) turns the decorators into nothing: the same code then runs as ordinary Python, slowly, and can be
stepped through in a debugger.

numba caches compiled code beside the sources, but keys each function on its own file only, while a
compiled function takes in code and constants of other modules. So the whole cache is dropped whenever any
source it may depend on changed: every module that uses the decorators below and every socnavgen module
they import, found by reading their imports (a digest computed at import; no list of files to keep).
"""

from __future__ import annotations

import functools
import hashlib
import os
import re
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

_SIM = Path(__file__).resolve().parent
_PACKAGE = _SIM.parent
_STAMP = _SIM / "__pycache__" / "numba-sources.sha256"

try:  # pragma: no cover - depends on the environment
    if os.environ.get("SOCNAVGEN_NO_NUMBA"):
        raise ImportError("disabled by SOCNAVGEN_NO_NUMBA")
    import numba
    from numba.extending import overload

    AVAILABLE = True
except ImportError:  # pragma: no cover
    AVAILABLE = False


def jit(fn: Callable | None = None, *, inline: bool = False, alloc: bool = False) -> Any:
    """Compile `fn` (cached), without reference counting unless `alloc` (the function creates arrays):
    numba counts a reference for every record it takes out of an array, which costs more than the work in
    the tree interpreter's and the physics' loops (a tree tick: 0.24 -> 0.06 us). `inline`: numba inlines the
    function into its callers."""
    if fn is None:
        return lambda f: jit(f, inline=inline, alloc=alloc)
    if not AVAILABLE:
        return fn
    options: dict[str, Any] = {"cache": True}
    if inline:
        options["inline"] = "always"
    options["_nrt"] = alloc  # said either way: a callee left unsaid inherits its caller's
    return numba.njit(**options)(fn)


def generator(fn: Callable) -> Any:
    """Compile a generator function (cached): resuming it from Python costs ~0.5 us, and it keeps the
    state it was started with, so nothing is unpacked again between two resumptions."""
    return numba.njit(cache=True)(fn) if AVAILABLE else fn


def dispatcher(name: str, functions: Sequence[Callable], arity: int) -> Callable:
    """`name(code, a0, ..)` = functions[code](a0, ..), written out as a chain of `if code == k` (numba cannot
    index a list of functions at run time and still cache its callers): a function added to `functions` is
    dispatched without writing its branch anywhere."""
    args = ", ".join(f"a{j}" for j in range(arity))
    lines = [f"def {name}(code, {args}):"]
    lines += [f"    if code == {k}:\n        return f{k}({args})" for k in range(len(functions))]
    lines.append(f"    return f0({args})  # not reached: codes come from the table")
    lines.append(f"def implement(code, {args}):\n    return {name}")
    env: dict[str, Any] = {f"f{k}": f for k, f in enumerate(functions)}
    exec("\n".join(lines), env)  # noqa: S102 - our own generated source, no user input
    if AVAILABLE:
        # _nrt (no reference-counted runtime) is numba's own option, missing from its _JITOptions TypedDict
        overload(env[name], jit_options={"_nrt": False}, inline="always")(env["implement"])  # type: ignore[typeddict-unknown-key]
    return env[name]


# `from socnavgen import a, b` on one line, or a parenthesised list over lines (the names of a one-line import
# must not run on into the next line: `from socnavgen import proxemics` was read as "proxemics from socnavgen")
_IMPORT = re.compile(r"^\s*(?:from\s+(socnavgen[\w.]*)\s+import\s+(?:\(([\w\s,]+)\)|([\w \t,]+))"
                     r"|import\s+(socnavgen[\w.]*))", re.M)


_COMPILED = re.compile(r"^@(jit|generator)\b|= dispatcher\(", re.M)  # a module that defines compiled code


@functools.cache  # the same few names are imported by most modules: ~750 look-ups, ~370 names
def _module_file(name: str) -> Path | None:
    path = _PACKAGE.parent.joinpath(*name.split("."))
    for candidate in (path.with_suffix(".py"), path / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _sources() -> list[Path]:
    """The files compiled code may depend on: every module that defines compiled functions, and every
    socnavgen module they import, transitively."""
    todo = [p for p in _SIM.rglob("*.py") if _COMPILED.search(p.read_text(encoding="utf-8"))]
    seen: set[Path] = set()
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        for module, listed, names, plain in _IMPORT.findall(path.read_text(encoding="utf-8")):
            names = listed or names
            targets = [plain] if plain else [module, *(f"{module}.{n.strip()}" for n in names.split(",") if n.strip())]
            todo += [f for f in map(_module_file, targets) if f is not None]
    return sorted(seen)


def _drop_stale_cache() -> None:
    """Drop numba's cache of the sim package when a source changed since it was written (best effort: an
    unwritable folder keeps numba's own per-file behaviour)."""
    try:
        digest = hashlib.sha256(b"".join(p.read_bytes() for p in _sources())).hexdigest()
        if _STAMP.is_file() and _STAMP.read_text() == digest:
            return
        for cache in _SIM.rglob("__pycache__"):
            for path in [*cache.glob("*.nbi"), *cache.glob("*.nbc")]:
                path.unlink(missing_ok=True)
        _STAMP.parent.mkdir(exist_ok=True)
        tmp = _STAMP.with_name(f".stamp-{os.getpid()}")
        tmp.write_text(digest)
        tmp.replace(_STAMP)
    except OSError:
        pass


def cache_ready() -> bool:
    """Whether this machine has the compiled episode cached (numba compiles it on first use: ~1 min)."""
    return not AVAILABLE or any((_SIM / "engine" / "__pycache__").glob("step.episode-*.nbi"))


COMPILING_NOTE = ("first compiled run on this machine: numba compiles the simulator once (about a minute per "
                  "process that starts at the same time); later runs start at once")

if AVAILABLE:
    _drop_stale_cache()
