"""Glue between Snakemake ``script:`` files and the package's plain functions."""

from __future__ import annotations

import logging
import sys
from collections.abc import Callable
from typing import Any

from exobench.errors import InputError
from exobench.plumbing import provenance

LOG = logging.getLogger("exobench")


def run(smk: Any, stage: Callable[[Any, dict], None], hashed: bool = True) -> None:
    """Run ``stage(snakemake, provenance)`` with logging to the rule's log and clear errors.

    The provenance covers the rule's data inputs (unless ``hashed`` is False: a rule whose
    inputs only order it, as the results index, whose content is the files' names), its
    ``params`` (the config it uses, :func:`settings`) and its ``code`` param (the package modules
    its script imports, declared by the workflow, with their SHA-256 when Snakemake planned the
    job: a job whose modules changed since then stops before any work, exit status 2, rather
    than record code it was not planned with; a cluster job plans again when it starts).

    The console (stderr) gets warnings and errors only; the rule's log gets everything.
    Bad input (:class:`InputError`) ends the job with its message and exit status 2, so
    Snakemake removes the job's outputs and stops; any other error ends it with its traceback
    (in the log too) and exit status 1.
    """
    console = logging.StreamHandler(sys.stderr)
    console.setLevel(logging.WARNING)
    handlers: list[logging.Handler] = [console]
    if smk.log:
        handlers.append(logging.FileHandler(smk.log[0], mode="w", encoding="utf-8"))
    logging.basicConfig(
        level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s", handlers=handlers
    )
    LOG.setLevel(logging.INFO)
    planned = smk.params.code
    try:
        code = provenance.code_sha256(provenance.PACKAGE_ROOT.parent / f for f in planned["files"])
    except OSError:  # a module deleted or renamed since
        code = None
    if code != planned["sha256"]:
        expected = ("the package modules Snakemake planned this job with (edited since: run "
                    "Snakemake again, so that every output records the code it ran)")  # fmt: skip
        changed = InputError(provenance.PACKAGE_ROOT, "code", expected)
        LOG.error("bad input: %s", changed)
        sys.exit(2)
    data = list(smk.input) if hashed else []
    record = provenance.build(smk.rule, data, settings(smk), code, smk.config)
    LOG.info(
        "rule %s, config %s, code %s",
        smk.rule,
        record["config_sha256"][:12],
        record["code_sha256"][:12],
    )
    try:
        stage(smk, record)
    except InputError as error:
        LOG.error("bad input: %s", error)
        sys.exit(2)
    except Exception as error:
        LOG.exception("%s: %s", type(error).__name__, error)
        sys.exit(1)


def settings(smk: Any) -> dict:
    """A job's params but its ``code`` param: the config it uses."""
    return {key: value for key, value in smk.params.items() if key != "code"}


def at_dag_build(function: Callable[..., Any], *args: Any) -> Any:
    """Call ``function(*args)`` while Snakemake builds the DAG; bad input ends the run.

    An :class:`InputError` is printed as one line and ends Snakemake with exit status 2, before
    any job, without a traceback.
    """
    try:
        return function(*args)
    except InputError as error:
        print(f"bad input: {error}", file=sys.stderr)
        raise SystemExit(2) from None
