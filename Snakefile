# exobench: bench tests of lower-limb exoskeletons. Run: snakemake --cores 2
import mimetypes

from snakemake.utils import min_version

from exobench.emulator import config_rules as emulator_rules
from exobench.phantom import config_rules as phantom_rules
from exobench.plumbing import config_checks, console, results_lock, runner
from exobench.sts import config_rules as sts_rules

min_version("9.0")

# A quiet console: one line per job, short reasons in dry runs (--verbose: in full), failures and
# group times at the end (the complete output stays in .snakemake/log/).
CONSOLE = console.install(
    workflow.output_settings.dryrun,
    workflow.is_main_process,
    workflow.output_settings.verbose,
)
# Parquet results are attached to the HTML report as Parquet, not as text.
mimetypes.add_type("application/vnd.apache.parquet", ".parquet")


# The environment is pip-only (environment.lock); this image documents the interpreter.
container: "docker://python:3.11-slim-bookworm"


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


# Nested --config values arrive as text: read them as the booleans and numbers the schema asks.
SCHEMA = config_checks.load_schema(workflow.basedir)
config_checks.coerce(config, SCHEMA)
runner.at_dag_build(config_checks.validate, config, SCHEMA)
# each group's cross-field checks, in its own package
SETTINGS_CHECKS = (phantom_rules.check, sts_rules.check, emulator_rules.check)
runner.at_dag_build(config_checks.check, config, SETTINGS_CHECKS)
if workflow.is_main_process:
    config_checks.warn_not_applying(config, workflow.basedir)


include: "workflow/rules/common.smk"
include: "workflow/rules/phantom.smk"
include: "workflow/rules/sts.smk"
include: "workflow/rules/sts_strength.smk"
include: "workflow/rules/emulator.smk"
include: "workflow/rules/validation_emulator.smk"
include: "workflow/rules/validation.smk"
include: "workflow/rules/validation_stability.smk"
include: "workflow/rules/results_index.smk"


rule all:
    default_target: True
    input:
        rules.phantom.input,
        rules.sts.input,
        rules.emulator.input,
        rules.results_index.output,
    message:
        "every group's results are up to date"


# One writer per results folder (not taken by dry runs, --lint or when nothing is to be done).
onstart:
    runner.at_dag_build(results_lock.acquire, RESULTS)


onsuccess:
    results_lock.release(RESULTS)
    console.on_success(CONSOLE)


onerror:
    results_lock.release(RESULTS)
    console.on_error(CONSOLE, log)
