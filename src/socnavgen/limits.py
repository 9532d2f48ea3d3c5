"""Documented resource limits on what socnavgen accepts (README: Security and robustness).

Input that passes one of these is refused with one message before any work is done, so that every
command ends in bounded time and memory on hostile input. File-size and JSON limits live beside the
readers in safeio.py; the LLM reply limits in llm/deadline.py and llm/transcript.py.
"""

from __future__ import annotations

MAX_HUMANS = 64  # humans in one run (paths.json); SocRATES scenarios have 1-5
MAX_SIM_SECONDS = 3600.0  # simulated seconds of one `simulate`
MAX_SIM_STEPS = 200_000  # timeout / dt
MAX_SIM_PEOPLE = 2000  # people in one simulation (the benchmarks' largest crowd is 1000)
MAX_IMAGE_PIXELS = 50_000_000  # a map or scene-graph image (width x height), checked before decoding
MAX_COORDINATE = 1e7  # |pixels| or |metres| of a node or transform value; beyond is a typo or an attack
