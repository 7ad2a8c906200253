"""A quiet, useful command line: Snakemake's console output trimmed to one line per job (in dry
runs with the reason it runs, shortened to one line, and the job table once; ``--verbose``
keeps the full reasons), a failed run ending with each failed job's error line and log, and one
line per rule group with its wall time at the end.

Installed from the Snakefile on Snakemake's own logger and console handler; Snakemake's log file
(``.snakemake/log/``) keeps the complete output.
"""

from __future__ import annotations

import logging
import re
from dataclasses import dataclass, field
from pathlib import Path

from snakemake_interface_logger_plugins.common import LogEvent

# Rule groups by the prefix of their rules' names, in the order the summary lists them.
GROUPS = {"phantom": "phantom", "sts": "sts", "emulator": "emulator", "validate": "validation"}
# Scheduler chatter a user does not act on (the log file keeps it).
CHATTER = re.compile(
    r"^(Select jobs to execute|Execute \d+ jobs|Assuming unrestricted shared filesystem"
    r"|Building DAG of jobs|Using shell:|Provided cores:|Rules claiming more threads"
    r"|Singularity containers:|Shutting down, this might take|Exiting because a job execution)"
)
# What Snakemake prints after the failure summary: it would bury the summary.
AFTER_FAILURE = re.compile(
    r"^(Complete log\(s\):|Elapsed time:)|At least one job did not complete successfully"
)
# A job's error line in its log (exobench.plumbing.runner writes it).
ERROR_LINE = re.compile(r"^ERROR exobench: (.*)$")
# The dry run's closing summary of reasons by rule (each job's own reason is shown with it).
REASONS = re.compile(r"^Reasons:\n")


def group_of(rule: str) -> str | None:
    """The rule group a rule belongs to (by its name), None for targets such as ``all``."""
    return GROUPS.get(rule.split("_")[0])


@dataclass
class Run:
    """What the console saw of this run: jobs started and finished (with times), jobs failed
    (with their logs) and the number of jobs planned."""

    dryrun: bool
    verbose: bool = False
    tables: int = 0  # job tables (RUN_INFO) Snakemake has logged: a dry run logs two
    started: dict = field(default_factory=dict)  # jobid -> (rule, time started)
    finished: dict = field(default_factory=dict)  # jobid -> time finished
    failed: list = field(default_factory=list)  # (rule, [log paths])
    total: int | None = None
    summarised: bool = False

    def observe(self, record: logging.LogRecord) -> None:
        """Note a job's start, end or failure, and the plan's size (fields Snakemake puts on its
        records; a record without them is ignored)."""
        event = getattr(record, "event", None)
        if event == LogEvent.JOB_INFO:
            self.started.setdefault(record.jobid, (record.rule_name, record.created))
        elif event == LogEvent.JOB_FINISHED and hasattr(record, "job_id"):
            self.finished[record.job_id] = record.created
        elif event == LogEvent.JOB_ERROR:
            self.failed.append((record.rule_name, list(record.log)))
        elif event == LogEvent.GROUP_ERROR:
            self.failed += [(i["rule_name"], list(i["log"])) for i in record.job_error_info]
        elif event == LogEvent.RUN_INFO and hasattr(record, "stats"):
            self.tables += 1
            self.total = record.stats.get("total") if self.total is None else self.total

    def group_times(self) -> list[str]:
        """One line per rule group: its jobs, its wall time (first start to last end) and its
        job time (the sum of its jobs' times), from this run's jobs."""
        spans: dict[str, list] = {}
        for jobid, (rule, start) in self.started.items():
            group = group_of(rule)
            if group is not None and jobid in self.finished:
                spans.setdefault(group, []).append((start, self.finished[jobid]))
        order = list(GROUPS.values())
        lines = []
        for group in sorted(spans, key=order.index):
            jobs = spans[group]
            wall = max(end for _, end in jobs) - min(start for start, _ in jobs)
            busy = sum(end - start for start, end in jobs)
            lines.append(
                f"{group}: {len(jobs)} jobs, {clock(wall)} wall time ({busy:.0f} s of job time)"
            )
        return lines

    def failure_lines(self) -> list[str]:
        """Per failed job: its rule, its error line (from its log) and the log's path."""
        lines = []
        for rule, logs in self.failed:
            lines.append(f"{rule} failed:")
            lines += [f"  {error}" for error in map(error_line, logs) if error]
            lines += [f"  log: {Path(log).resolve()}" for log in logs]
        return lines


def clock(seconds: float) -> str:
    """Seconds as m:ss."""
    minutes, rest = divmod(round(seconds), 60)
    return f"{minutes}:{rest:02d}"


def error_line(log: str) -> str | None:
    """The last error a job wrote to its log (``ERROR exobench: …``), else the log's last line."""
    path = Path(log)
    if not path.is_file():
        return None
    lines = [line.strip() for line in path.read_text(errors="replace").splitlines()]
    errors = [m.group(1) for m in map(ERROR_LINE.match, lines) if m]
    return errors[-1] if errors else next((line for line in reversed(lines) if line), None)


class Observer(logging.Filter):
    """A filter on Snakemake's logger that lets everything through and notes what it sees."""

    def __init__(self, run: Run):
        super().__init__()
        self.run = run

    def filter(self, record: logging.LogRecord) -> bool:
        self.run.observe(record)
        return True


class Quiet(logging.Filter):
    """The console handler's filter: drops scheduler chatter, the banner, finished-job notices
    and the script runner's CalledProcessError (the job's own error says more), a dry run's
    second job table and its summary of reasons by rule (unless verbose), and, once the failure
    summary is out, what Snakemake prints after it."""

    def __init__(self, run: Run):
        super().__init__()
        self.run = run

    def filter(self, record: logging.LogRecord) -> bool:
        event = getattr(record, "event", None)
        text = str(record.msg)
        if self.run.summarised and AFTER_FAILURE.search(text):
            return False
        if event in (LogEvent.WORKFLOW_STARTED, LogEvent.SHELLCMD):
            return False
        if event in (LogEvent.JOB_FINISHED, LogEvent.PROGRESS) and not self.run.dryrun:
            return False
        if "CalledProcessError" in text and ".snakemake/scripts/" in text:
            return False
        if self.run.dryrun and not self.run.verbose:
            if event == LogEvent.RUN_INFO and self.run.tables > 1:
                return False
            if REASONS.match(text):
                return False
        return not CHATTER.match(text)


class Compact(logging.Formatter):
    """The console's formatter: a job as one line (``[ 3/30] rule: message``; in a dry run the
    rule, its message and the reason it runs), a real run's plan as one line, a failed job as
    its rule and log; everything else as Snakemake formats it."""

    def __init__(self, base: logging.Formatter, run: Run):
        super().__init__()
        self.base, self.run = base, run

    def format(self, record: logging.LogRecord) -> str:
        event = getattr(record, "event", None)
        if event == LogEvent.JOB_INFO:
            return self.job(record)
        if event == LogEvent.RUN_INFO and hasattr(record, "stats") and not self.run.dryrun:
            return plan_line(record.stats)
        if event == LogEvent.JOB_ERROR:
            logs = ", ".join(str(Path(log).resolve()) for log in record.log)
            return f"Error in rule {record.rule_name} (job {record.jobid}); log: {logs}"
        return self.base.format(record)

    def job(self, record: logging.LogRecord) -> str:
        what = f"{record.rule_name}: {record.rule_msg}" if record.rule_msg else record.rule_name
        if self.run.dryrun:
            reason = record.reason if self.run.verbose else short_reason(str(record.reason))
            return f"{what}\n    reason: {reason}"
        total = self.run.total or len(self.run.started)
        return f"[{len(self.run.started):>{len(str(total))}}/{total}] {what}"


def short_reason(reason: str) -> str:
    """A job's reason on one readable line: each part's list of files as its count, the first
    part's with its first file (``Missing output files (18): a.parquet, …; Input files updated
    by another job (7)``)."""
    parts = []
    for part in " ".join(reason.split()).split("; "):
        label, colon, items = part.partition(": ")
        names = [item for item in items.split(", ") if item] if colon else []
        if parts and names:
            part = f"{label} ({len(names)})"
        elif len(names) > 1:
            part = f"{label} ({len(names)}): {names[0]}, …"
        parts.append(part)
    return "; ".join(parts)


def plan_line(stats: dict) -> str:
    """A real run's job table as one line: jobs per rule group."""
    groups: dict[str, int] = {}
    for rule, count in stats.items():
        if rule != "total":
            group = group_of(rule) or rule
            groups[group] = groups.get(group, 0) + count
    parts = ", ".join(f"{group} {count}" for group, count in groups.items())
    return f"{stats.get('total', sum(groups.values()))} jobs to run ({parts})"


def install(dryrun: bool, main: bool = True, verbose: bool = False) -> Run:
    """Put the observer on Snakemake's logger and the quiet filter and compact formatter on its
    console handler; returns the run the hooks below report on. A job's own Snakemake process
    (``main`` false: a cluster or group job) keeps Snakemake's output; ``verbose`` (Snakemake's
    ``--verbose``) keeps a dry run's full reasons."""
    run = Run(dryrun=dryrun, verbose=verbose)
    if not main:
        return run
    logger = logging.getLogger("snakemake.logging")
    logger.addFilter(Observer(run))
    for handler in logger.handlers:
        if handler.get_name() == "DefaultStreamHandler":
            handler.addFilter(Quiet(run))
            handler.setFormatter(Compact(handler.formatter, run))
    return run


def on_success(run: Run) -> None:
    """End of a successful run: one line per rule group with its wall time."""
    logger = logging.getLogger("snakemake.logging")
    for line in run.group_times():
        logger.info(line)


def on_error(run: Run, log: str | list | None = None) -> None:
    """End of a failed run: Snakemake's log, then per failed job its error line and its log (the
    last lines of the run: Snakemake's own closing lines are not printed after them)."""
    logs = [log] if isinstance(log, str) else list(log or [])
    lines = [f"The run stopped. Snakemake's log: {', '.join(logs) or 'none'}"]
    lines += run.failure_lines() or ["no job error was seen"]
    logging.getLogger("snakemake.logging").error("\n".join(lines))
    run.summarised = True
