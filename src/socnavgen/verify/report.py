"""Human-readable rendering of a VerifyReport (a rich table: one row per expectation, with its evidence)."""

from __future__ import annotations

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from socnavgen.text import printable
from socnavgen.verify.models import VerifyReport


def _t(text: object) -> str:
    """Text from the spec, the model or a file, shown as text: terminal escapes made visible, no rich markup."""
    return escape(printable(text))


def report_table(report: VerifyReport) -> Table:
    verdict = "[bold green]PASSED[/]" if report.passed else f"[bold red]FAILED[/] ({len(report.failures)} failing)"
    table = Table(title=f"verify {_t(report.run)}: {verdict}", caption=(
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
        table.add_row(mark, _t(f.name), _t(f.source),
                      "" if f.time is None else f"{f.time:.1f}", "" if f.distance is None else f"{f.distance:.2f}",
                      "" if f.robustness is None else f"{f.robustness:+.2f}", _t(f.evidence),
                      "" if f.passed or not f.blame else _t(f"{f.blame}{' ' + f.blame_human if f.blame_human else ''}: "
                                                            f"{f.blame_reason}"))
    return table


WIDE = 140  # columns below which the report is a list (eight table columns would fold word by word)


def _mark(f: object) -> str:
    return "[green]ok[/]" if f.passed else ("[red]FAIL[/]" if f.required else "[yellow]warn[/]")  # type: ignore[attr-defined]


def report_lines(report: VerifyReport) -> list[str]:
    """The report as a list for narrow terminals and pipes: one finding per paragraph, nothing folded."""
    verdict = "[bold green]PASSED[/]" if report.passed else f"[bold red]FAILED[/] ({len(report.failures)} failing)"
    lines = [f"verify {_t(report.run)}: {verdict}"]
    for f in report.findings:
        numbers = ", ".join(part for part in (
            "" if f.time is None else f"t={f.time:.1f} s", "" if f.distance is None else f"{f.distance:.2f} m",
            "" if f.robustness is None else f"robustness {f.robustness:+.2f}") if part)
        lines.append(f"{_mark(f)} {_t(f.name)} [dim]({_t(f.source)}{'; ' + numbers if numbers else ''})[/]")
        lines.append(f"     {_t(f.evidence)}")
        if not f.passed and f.blame:
            who = f" {f.blame_human}" if f.blame_human else ""
            lines.append(f"     fix: {_t(f'{f.blame}{who}: {f.blame_reason}')}")
    lines.append(f"{report.trace_seconds:.1f} s simulated, {report.trace_steps} steps, criteria from "
                 + ("spec.json" if report.spec else "paths, trees and card")
                 + (f", ended by {report.end_reason}" if report.end_reason else ""))
    return lines


def print_report(report: VerifyReport, console: Console) -> None:
    """A table on a wide terminal; a list otherwise (80 columns, pipes)."""
    if console.width >= WIDE:
        console.print(report_table(report))
    else:
        for line in report_lines(report):
            console.print(line, highlight=False)
