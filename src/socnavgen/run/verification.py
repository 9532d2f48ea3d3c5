"""Whether a run was verified, passed, failed, or was changed since: read from RUN/sim/verify.json (written by
`socnavgen verify`) without the verifier itself, so that export and others can say it before they hand the
scenario on. A report is stale when the trace it judged is stale: the simulator's record of what the trace was
made from (sim/outputs.json, digests of the run and location files, the robot, the version) no longer matches;
the caller passes that reason (`trace_stale`, from socnavgen.sim.outputs.files.stale_reason). Only a trace made
without a record (by hand, or by an old socnavgen) falls back to file times: a judged file newer than the report."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from socnavgen.errors import SocnavgenError
from socnavgen.run.folder import RunFolder
from socnavgen.safeio import load_json_file

REPORT = "verify.json"
TRACE = "trace.npz"
RECORD = "outputs.json"  # the simulator's record of what the trace was made from (sim.outputs.files)
State = Literal["passed", "failed", "never", "stale", "unreadable"]


@dataclass(frozen=True)
class VerificationStatus:
    state: State
    message: str  # one sentence for a person, with what to do

    @property
    def ok(self) -> bool:
        return self.state == "passed"


def _inputs(folder: RunFolder) -> list:
    files = [folder.paths_path, folder.spec_path, folder.request_path, folder.sim_dir / TRACE]
    if folder.behaviors_dir.is_dir():
        files += sorted(folder.behaviors_dir.glob("human*.xml"))
    return [f for f in files if f.is_file()]


def verification_status(folder: RunFolder, trace_stale: str | None = None) -> VerificationStatus:
    report = folder.sim_dir / REPORT
    again = f"run `socnavgen verify {folder.root}`"
    if not report.is_file():
        return VerificationStatus("never", f"this run was never verified: nothing shows its scenario happens; {again}")
    if trace_stale:
        return VerificationStatus("stale", f"sim/verify.json judged a simulation that is out of date ({trace_stale}); "
                                           f"{again}")
    recorded = (folder.sim_dir / RECORD).is_file()
    newer = [] if recorded else [f for f in _inputs(folder) if f.stat().st_mtime > report.stat().st_mtime]
    if newer:
        names = ", ".join(str(f.relative_to(folder.root)) for f in newer[:4])
        return VerificationStatus("stale", f"sim/verify.json is older than {names}: its verdict is about an earlier "
                                           f"version of the run; {again}")
    try:
        data = load_json_file(report)
    except (SocnavgenError, OSError, ValueError) as exc:
        return VerificationStatus("unreadable", f"sim/verify.json cannot be read ({str(exc)[:120]}); {again}")
    if not isinstance(data, dict) or not isinstance(data.get("passed"), bool):
        return VerificationStatus("unreadable", f"sim/verify.json is not a verification report; {again}")
    if data["passed"]:
        return VerificationStatus("passed", "verified: every criterion held in the headless simulation")
    findings = got if isinstance(got := data.get("findings"), list) else []
    failing = [str(f.get("name", "?"))[:120] for f in findings
               if isinstance(f, dict) and f.get("passed") is False and f.get("required", True) is not False]
    listed = "; ".join(failing[:3]) + (f"; and {len(failing) - 3} more" if len(failing) > 3 else "")
    return VerificationStatus("failed", f"this run FAILED verification ({len(failing)} failing: {listed}); the "
                                        "exported scenario may not happen as described (see sim/verify.json)")
