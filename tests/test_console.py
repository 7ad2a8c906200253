"""The quiet command line: what the console keeps, how a job and a failure read, the group times."""

from __future__ import annotations

import logging

import pytest
from snakemake_interface_logger_plugins.common import LogEvent

from exobench.plumbing import console


def record(msg: str = "", created: float = 0.0, **extra) -> logging.LogRecord:
    """A record as Snakemake logs it: a message and its extra fields."""
    item = logging.LogRecord("snakemake.logging", logging.INFO, __file__, 1, msg, None, None)
    item.__dict__.update(extra)
    item.created = created
    return item


def job(jobid: int, rule: str, created: float, message: str | None = "what it does"):
    return record(
        f" Rule: {rule}, Jobid: {jobid}",
        created,
        event=LogEvent.JOB_INFO,
        jobid=jobid,
        rule_name=rule,
        rule_msg=message,
        reason="Missing output files: x",
    )


def finished(jobid: int, created: float):
    return record(f"Finished jobid: {jobid}", created, event=LogEvent.JOB_FINISHED, job_id=jobid)


@pytest.mark.parametrize(
    "text",
    [
        "Select jobs to execute...",
        "Execute 2 jobs...",
        "Building DAG of jobs...",
        "Provided cores: 2",
        "Assuming unrestricted shared filesystem usage.",
    ],
)
def test_scheduler_chatter_is_dropped_and_the_rest_kept(text):
    quiet = console.Quiet(console.Run(dryrun=False))
    assert not quiet.filter(record(text))
    assert quiet.filter(record("Config file config/config.yaml is extended"))
    assert not quiet.filter(record("", event=LogEvent.WORKFLOW_STARTED))
    script = "CalledProcessError in …: Command 'python .snakemake/scripts/tmpab.x.py' returned 2"
    assert not quiet.filter(record(script))


def test_a_real_run_shows_one_line_a_job_and_a_dry_run_its_reason():
    run = console.Run(dryrun=False)
    compact = console.Compact(logging.Formatter(), run)
    run.observe(
        record(
            "Job stats", event=LogEvent.RUN_INFO, stats={"phantom_filter": 1, "all": 1, "total": 12}
        )
    )
    first = job(3, "phantom_filter", 1.0)
    run.observe(first)
    assert compact.format(first) == "[ 1/12] phantom_filter: what it does"
    assert "\n" not in compact.format(job(4, "sts_beam", 2.0, message=None))
    assert console.Quiet(run).filter(first)
    assert not console.Quiet(run).filter(finished(3, 2.0))
    dry = console.Compact(logging.Formatter(), console.Run(dryrun=True))
    assert dry.format(first) == "phantom_filter: what it does\n    reason: Missing output files: x"


def test_the_plan_reads_as_jobs_per_group():
    stats = {"phantom_filter": 1, "phantom_twin": 1, "sts_beam": 1, "all": 1, "total": 4}
    assert console.plan_line(stats) == "4 jobs to run (phantom 2, sts 1, all 1)"


def test_each_group_gets_its_wall_time_and_job_time():
    run = console.Run(dryrun=False)
    for jobid, rule, start, end in [
        (1, "phantom_twin", 0.0, 10.0),
        (2, "phantom_filter", 10.0, 25.0),
        (3, "sts_beam", 5.0, 7.0),
        (4, "all", 25.0, 25.0),
    ]:
        run.observe(job(jobid, rule, start))
        run.observe(finished(jobid, end))
    assert run.group_times() == [
        "phantom: 2 jobs, 0:25 wall time (25 s of job time)",
        "sts: 1 jobs, 0:02 wall time (2 s of job time)",
    ]


def test_a_failed_run_ends_with_the_bad_input_and_the_log(tmp_path, caplog):
    log = tmp_path / "logs" / "emulator_trial" / "job.log"
    log.parent.mkdir(parents=True)
    bad = "bad input: raw/emulator/v08_brace.csv: field 'brace_torque_Nm': expected columns"
    log.write_text(f"INFO exobench: rule emulator_trial\nERROR exobench: {bad}\n")
    run = console.Run(dryrun=False)
    run.observe(
        record(
            "Error in rule emulator_trial",
            event=LogEvent.JOB_ERROR,
            rule_name="emulator_trial",
            jobid=1,
            log=[str(log)],
        )
    )
    with caplog.at_level(logging.INFO, logger="snakemake.logging"):
        console.on_error(run, [".snakemake/log/run.log"])
    lines = caplog.records[-1].getMessage().splitlines()
    assert lines[-2:] == [f"  {bad}", f"  log: {log}"]
    assert ".snakemake/log/run.log" in lines[0]
    # Snakemake's own closing lines do not follow it on the console
    quiet = console.Quiet(run)
    assert not quiet.filter(
        record("WorkflowError:\nAt least one job did not complete successfully.")
    )
    assert not quiet.filter(record("Complete log(s): .snakemake/log/run.log"))


def test_an_error_without_an_error_line_shows_the_log_s_last_line(tmp_path):
    log = tmp_path / "job.log"
    log.write_text("Traceback (most recent call last):\n  …\nKeyError: 'x'\n\n")
    assert console.error_line(str(log)) == "KeyError: 'x'"
    assert console.error_line(str(tmp_path / "missing.log")) is None


def test_a_dry_run_reason_is_one_short_line_and_verbose_keeps_it_whole():
    files = ", ".join(f"results/phantom/acquired/k{i:05d}_markers.parquet" for i in range(18))
    reason = f"Missing output files: {files}; Input files updated by another job: a.c3d, b.c3d"
    short = console.short_reason(reason)
    assert short == (
        "Missing output files (18): results/phantom/acquired/k00000_markers.parquet, …; "
        "Input files updated by another job (2)"
    )
    assert console.short_reason("Params have changed since last execution") == (
        "Params have changed since last execution"
    )
    item = job(3, "phantom_acquire_trial", 1.0)
    item.reason = reason
    dry = console.Compact(logging.Formatter(), console.Run(dryrun=True))
    assert dry.format(item).splitlines()[1] == f"    reason: {short}"
    verbose = console.Compact(logging.Formatter(), console.Run(dryrun=True, verbose=True))
    assert verbose.format(item).endswith(reason)


def test_a_dry_run_shows_the_job_table_once_and_no_reasons_by_rule():
    run = console.Run(dryrun=True)
    quiet, observer = console.Quiet(run), console.Observer(run)
    table = {"phantom_filter": 1, "total": 1}
    shown = []
    for item in (
        record("Job stats:", event=LogEvent.RUN_INFO, stats=table),
        record("Job stats:", event=LogEvent.RUN_INFO, stats=table),
        record("Reasons:\n    (check individual jobs above for details)\n    params: x"),
        record("This was a dry-run (flag -n)."),
    ):
        observer.filter(item)
        shown.append(quiet.filter(item))
    assert shown == [True, False, False, True]
    verbose = console.Run(dryrun=True, verbose=True)
    verbose.tables = 2
    assert console.Quiet(verbose).filter(record("Reasons:\n    params: x"))
