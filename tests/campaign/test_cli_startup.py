"""The CLI starts without importing the heavy stack; `campaign` is one of its commands."""

from __future__ import annotations

import subprocess
import sys

CLI = "import sys; from socnavgen.cli import main; sys.argv = ['socnavgen', *sys.argv[1:]]; main()"


def test_help_imports_no_heavy_module() -> None:
    code = ("import sys; sys.argv = ['socnavgen', '--help']\nfrom socnavgen.cli import main\ntry:\n    main()\n"
            "except SystemExit:\n    pass\nheavy = [m for m in ('numpy', 'networkx', 'pydantic', 'socnavgen.sim', "
            "'matplotlib', 'pyarrow') if m in sys.modules]\nprint('HEAVY', heavy)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert "HEAVY []" in done.stdout, done.stdout[-500:]
    for command in ("location", "generate", "simulate", "verify", "campaign", "cards", "eval"):
        assert command in done.stdout


def test_campaign_subcommands_load_on_demand() -> None:
    done = subprocess.run([sys.executable, "-c", CLI, "campaign", "metrics"], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0
    assert "path_efficiency" in done.stdout and "static_obstacle_collisions" in done.stdout
