"""A walk on the scene graph is checked the same on the stored graph as on its networkx view: `simulate`
checks paths.json on the former and never imports networkx (~0.1 s of its start)."""

from __future__ import annotations

import itertools
import random
import subprocess
import sys
from pathlib import Path

from socnavgen.location import load_location
from socnavgen.location.scene_graph import path_mistakes, to_networkx

REPO = Path(__file__).resolve().parents[2]
CLI = "import sys; from socnavgen.cli import main; sys.argv = ['socnavgen', *sys.argv[1:]]; main()"


def test_path_mistakes_on_the_stored_graph_match_its_networkx_view() -> None:
    rng = random.Random(5)
    for name in ("warehouse", "home", "hospital"):
        graph = load_location(REPO / "examples" / "locations" / name).scene_graph
        ids = graph.node_ids()
        pool = [*ids, "zz", "q1"]  # two ids the graph does not have
        walks = [[a, b] for a, b in itertools.product(ids, repeat=2)]  # every pair: edges, non-edges, repeats
        walks += [[rng.choice(pool) for _ in range(rng.randint(0, 6))] for _ in range(300)]
        view = to_networkx(graph)
        found = [path_mistakes(graph, "walk", w) for w in walks]
        assert found == [path_mistakes(view, "walk", w) for w in walks]
        assert any(found) and not all(found)  # both kinds of walk were tried


def test_simulate_does_not_import_networkx(tmp_path: Path) -> None:
    run = tmp_path / "card"
    subprocess.run([sys.executable, "-c", CLI, "cards", "generate", "frontal-approach", "--location",
                    str(REPO / "examples" / "locations" / "warehouse"), "-o", str(run)], check=True, timeout=120,
                   capture_output=True)
    code = (f"import sys\nsys.argv = ['socnavgen', 'simulate', {str(run)!r}, '--no-plot']\n"
            "from socnavgen.cli import main\ntry:\n    main()\nexcept SystemExit:\n    pass\n"
            "print('NETWORKX', 'networkx' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert (run / "sim" / "trace.npz").is_file(), done.stderr[-800:]
    assert "NETWORKX False" in done.stdout, done.stdout[-500:]
