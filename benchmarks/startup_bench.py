"""How long `socnavgen simulate` takes on a scenario card with a warm numba cache, and where the time goes
(issue 26's bar: under 1 s). One card (narrow-doorway on the warehouse by default), N fresh processes each.

"command": `socnavgen simulate CARD` as a user runs it - wall and CPU time of the whole process (median of N).
"phases": the same command in a process that times, without changing it, what it calls (exclusive time of each:
a phase nested in another is not counted twice): the interpreter's start, the CLI's start and argument parsing,
module imports (wherever they happen), numba loading compiled code from its cache (the number of functions
loaded is printed), reading the location, building the Simulation, the episode, the metrics, the figure, the
rest of writing the outputs, and the rest of the command (locks, digests, printing).

    python benchmarks/startup_bench.py [-n 7] [--card narrow-doorway] [--src /other/checkout/src]

`--src` measures another checkout's sources (e.g. main's, for a before/after table; its numba cache must be
warm, or the first run compiles for a minute and is left out like every first run).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
WAREHOUSE = REPO / "examples" / "locations" / "warehouse"

# (module, attribute path, phase): what the phase driver times, exclusive of phases nested inside
TIMED = (
    ("socnavgen.cli.sim_cmd", "simulate", "command (rest)"),
    ("socnavgen.run.folder", "RunFolder.location", "read location"),
    ("socnavgen.sim.engine.scenario", "load_simulation", "build simulation"),
    ("socnavgen.sim.engine.simulation", "Simulation.run", "episode"),
    ("socnavgen.sim.outputs.files", "save_run_outputs", "outputs (trace, json)"),
    ("socnavgen.sim.metrics", "compute_metrics", "metrics"),
    ("socnavgen.sim.metrics", "navigation_metrics", "metrics"),
    ("socnavgen.sim.social_metrics", "social_metrics", "metrics"),
    ("socnavgen.sim.outputs.plot", "plot_trajectories", "plot"),
    ("numba.core.dispatcher", "Dispatcher.compile", "numba cache load"),
)
CLI = [sys.executable, "-c", "import sys; from socnavgen.cli import main; sys.argv[0] = 'socnavgen'; sys.exit(main())"]
PHASES = ("interpreter", "cli start", "imports", "read location", "build simulation", "numba cache load", "episode",
          "metrics", "plot", "outputs (trace, json)", "command (rest)")

DRIVER = r'''
import json, sys, time
from collections import defaultdict
import _frozen_importlib as bootstrap

TIMED, out_file, argv = json.loads(sys.argv[1]), sys.argv[2], sys.argv[3:]
clock = lambda: (time.perf_counter(), time.process_time())
totals = defaultdict(lambda: [0.0, 0.0])
calls = defaultdict(int)
stack = [["cli start", *clock()]]

def enter(phase):
    wall, cpu = clock()
    top = stack[-1]
    totals[top[0]][0] += wall - top[1]
    totals[top[0]][1] += cpu - top[2]
    stack.append([phase, wall, cpu])
    calls[phase] += 1

def leave():
    wall, cpu = clock()
    top = stack.pop()
    totals[top[0]][0] += wall - top[1]
    totals[top[0]][1] += cpu - top[2]
    stack[-1][1:] = [wall, cpu]

def timed(fn, phase):
    def wrapper(*args, **kwargs):
        enter(phase)
        try:
            return fn(*args, **kwargs)
        finally:
            leave()
    wrapper.__wrapped__ = fn
    return wrapper

def patch(module):
    for name, attr, phase in TIMED:
        if name != module.__name__:
            continue
        owner, *rest = attr.split(".")
        if rest:
            cls = getattr(module, owner)
            setattr(cls, rest[0], timed(getattr(cls, rest[0]), phase))
        else:
            setattr(module, owner, timed(getattr(module, owner), phase))

find_and_load = bootstrap._find_and_load
WANTED = {t[0] for t in TIMED}

def timed_import(name, import_):
    nested = stack[-1][0] == "imports"
    if not nested:
        enter("imports")
    try:
        module = find_and_load(name, import_)
    finally:
        if not nested:
            leave()
    if name in WANTED:
        patch(module)
    return module

bootstrap._find_and_load = timed_import
sys.argv = ["socnavgen", *argv]
start = time.perf_counter()
try:
    from socnavgen.cli import main
    main()
except SystemExit:
    pass
finally:
    leave_all = clock()
    top = stack[-1]
    totals[top[0]][0] += leave_all[0] - top[1]
    totals[top[0]][1] += leave_all[1] - top[2]
    with open(out_file, "w") as f:
        json.dump({"phases": totals, "calls": calls, "inside": time.perf_counter() - start}, f)
'''


def _env(src: Path, bytecode: Path) -> dict[str, str]:
    """Python's compiled bytecode cached in `bytecode` (as an installed package has it; PYTHONDONTWRITEBYTECODE
    would compile every module of ours at each start, ~0.25 s), never written into the measured tree."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(src), str(src.parent)])
    env["PYTHONPYCACHEPREFIX"] = str(bytecode)
    for name in ("SOCNAVGEN_NO_NUMBA", "PYTHONDONTWRITEBYTECODE"):
        env.pop(name, None)
    return env


def _timed_run(cmd: list[str], env: dict[str, str]) -> tuple[float, float]:
    """Wall and CPU seconds (user + system, the child's) of one process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def _one(env: dict[str, str], card: Path, extra: list[str], out: Path) -> dict:
    """One plain run (wall, CPU) and one run in the timing driver (phases, numba loads)."""
    plain = _timed_run([*CLI, "simulate", str(card), *extra], env)
    wall, cpu = _timed_run([sys.executable, "-c", DRIVER, json.dumps(TIMED), str(out), "simulate", str(card), *extra],
                           env)
    got = json.loads(out.read_text())
    phases = {p: tuple(got["phases"].get(p, (0.0, 0.0))) for p in PHASES}
    phases["interpreter"] = (wall - sum(w for w, _ in got["phases"].values()),
                             cpu - sum(c for _, c in got["phases"].values()))
    return {"command": plain, "phases": phases, "loads": got["calls"].get("numba cache load", 0)}


def measure(trees: dict[str, dict[str, str]], card: Path, runs: int, modes: dict[str, list[str]]) -> dict:
    """Median wall/CPU of the plain command and of each phase, per source tree and mode; the trees' runs are
    interleaved (a machine shared with other jobs slows them alike)."""
    got: dict[tuple[str, str], list[dict]] = {(t, m): [] for t in trees for m in modes}
    with tempfile.TemporaryDirectory(prefix="startup-bench-") as tmp:
        for env in trees.values():  # warm: bytecode, numba's index, the OS's file cache
            subprocess.run([*CLI, "simulate", str(card)], env=env, check=True, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
        for _ in range(runs):
            for (tree, mode), results in got.items():
                results.append(_one(trees[tree], card, modes[mode], Path(tmp) / "phases.json"))
    med = statistics.median
    return {key: {"command": (med(r["command"][0] for r in rs), med(r["command"][1] for r in rs)),
                  "phases": {p: (med(r["phases"][p][0] for r in rs), med(r["phases"][p][1] for r in rs))
                             for p in PHASES},
                  "loads": med(r["loads"] for r in rs)} for key, rs in got.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-n", "--runs", type=int, default=7)
    parser.add_argument("--card", default="narrow-doorway")
    parser.add_argument("--location", type=Path, default=WAREHOUSE)
    parser.add_argument("--src", type=Path, action="append",
                        help="socnavgen sources to measure (repeat to compare; default: this tree's)")
    args = parser.parse_args()
    srcs = [p.resolve() for p in (args.src or [REPO / "src"])]
    modes = {"simulate": [], "--no-plot": ["--no-plot"]}
    with tempfile.TemporaryDirectory(prefix="startup-card-") as tmp:
        trees = {str(src.parent): _env(src, Path(tmp) / f"bytecode{k}") for k, src in enumerate(srcs)}
        card = Path(tmp) / "card"
        subprocess.run([*CLI, "cards", "generate", args.card, "--location", str(args.location), "-o", str(card)],
                       env=next(iter(trees.values())), check=True, stdout=subprocess.DEVNULL)
        results = measure(trees, card, args.runs, modes)
    print(f"`socnavgen simulate` on card {args.card} ({args.location.name}), warm numba cache, median of {args.runs} "
          "fresh processes each (seconds, wall / CPU = user + system)")
    for tree in trees:
        print(f"\n{tree}")
        print(f"| {'phase':<22} | " + " | ".join(f"{m + ' wall':>18} | {'CPU':>6}" for m in modes) + " |")
        print("|" + "---|" * (1 + 2 * len(modes)))
        rows = [("whole command", lambda r: r["command"])] + [(p, lambda r, p=p: r["phases"][p]) for p in PHASES]
        for label, pick in rows:
            cells = " | ".join(f"{pick(results[tree, m])[0]:>18.3f} | {pick(results[tree, m])[1]:>6.3f}" for m in modes)
            print(f"| {label:<22} | {cells} |")
        print("numba functions loaded from the cache: "
              + ", ".join(f"{m} {results[tree, m]['loads']:g}" for m in modes))


if __name__ == "__main__":
    main()
