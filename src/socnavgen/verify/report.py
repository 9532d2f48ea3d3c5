"""Human-readable rendering of a VerifyReport (a rich table: one row per expectation, with its evidence)."""

from __future__ import annotations

from rich.console import Console
from rich.table import Table

from socnavgen.verify.models import VerifyReport


def report_table(report: VerifyReport) -> Table:
    verdict = "[bold green]PASSED[/]" if report.passed else f"[bold red]FAILED[/] ({len(report.failures)} failing)"
    table = Table(title=f"verify {report.run}: {verdict}", caption=(
        f"{report.trace_seconds:.1f} s simulated, {report.trace_steps} steps, criteria from "
        + ("spec.json" if report.spec else "paths, trees and card")
        + (f", ended by {report.end_reason}" if report.end_reason else "")), show_lines=False, expand=False)
    table.add_column("", no_wrap=True)
    table.add_column("expectation", overflow="fold")
    table.add_column("from", no_wrap=True)
    table.add_column("t \\[s]", justify="right", no_wrap=True)
    table.add_column("dist \\[m]", justify="right", no_wrap=True)
    table.add_column("robustness", justify="right", no_wrap=True)
    table.add_column("evidence", overflow="fold")
    table.add_column("fix", overflow="fold")
    for f in report.findings:
        mark = "[green]ok[/]" if f.passed else ("[red]FAIL[/]" if f.required else "[yellow]warn[/]")
        table.add_row(mark, f.name, f.source,
                      "" if f.time is None else f"{f.time:.1f}", "" if f.distance is None else f"{f.distance:.2f}",
                      "" if f.robustness is None else f"{f.robustness:+.2f}", f.evidence,
                      "" if f.passed or not f.blame else f"{f.blame}{' ' + f.blame_human if f.blame_human else ''}: "
                                                         f"{f.blame_reason}")
    return table


def print_report(report: VerifyReport, console: Console) -> None:
    console.print(report_table(report))
