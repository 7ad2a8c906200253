# exobench: bench tests of lower-limb exoskeletons. Run: snakemake --cores 2
from snakemake.exceptions import WorkflowError
from snakemake.utils import min_version, validate

from exobench import config_checks, results_lock, runner

min_version("9.0")


# The environment is pip-only (environment.lock); this image documents the interpreter.
container: "docker://python:3.11-slim-bookworm"


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


try:
    validate(config, config_checks.SCHEMA)
except WorkflowError as error:
    runner.at_dag_build(config_checks.refuse_schema_violation, error)
runner.at_dag_build(config_checks.check, config)


include: "workflow/rules/common.smk"
include: "workflow/rules/phantom.smk"
include: "workflow/rules/sts.smk"
include: "workflow/rules/emulator.smk"
include: "workflow/rules/validation_emulator.smk"
include: "workflow/rules/validation.smk"


rule all:
    default_target: True
    input:
        rules.phantom.input,
        rules.sts.input,
        rules.emulator.input,


# One writer per results folder (not taken by dry runs, --lint or when nothing is to be done).
onstart:
    runner.at_dag_build(results_lock.acquire, RESULTS)


onsuccess:
    results_lock.release(RESULTS)


onerror:
    results_lock.release(RESULTS)
