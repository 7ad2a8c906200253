# Paths and helpers shared by every rule group. Locations come from the config so that
# --config raw_dir=... results_dir=... moves recordings and results anywhere.
from pathlib import Path

# no heavy imports here (scipy, the twins): every Snakemake call (each dry run, each cluster
# job) parses this file
from exobench.plumbing import codedeps, config_checks, runner, stamp

RAW = Path(config["raw_dir"])
RESULTS = Path(config["results_dir"])
REFERENCE = Path(config["reference_dir"])
# The digital twins write the recordings (else a lab's manifest names them).
SYNTHETIC = config["acquisition"] == "synthetic"


SCRIPTS = Path(workflow.basedir) / "workflow" / "scripts"


def logfile(rule_name, job="job"):
    """The rule's log: one folder per rule, one file per job."""
    return RESULTS / "logs" / rule_name / f"{job}.log"


def benchfile(rule_name, job="job"):
    """The rule's Snakemake benchmark file: one folder per rule, one file per job."""
    return RESULTS / "benchmarks" / rule_name / f"{job}.tsv"


def setting(path):
    """The config value at ``path`` ("group/block/key"), for a rule's params: a changed value
    reruns the rules that read it (plain dictionary steps; Snakemake's lookup(dpath=...) walks
    the whole config on every call, a fifth of a second per parse of the workflow)."""
    value = config
    for step in path.split("/"):
        if not isinstance(value, dict) or step not in value:
            raise KeyError(
                f"the config has no setting {path!r} (config/config.yaml lists them)"
            )
        value = value[step]
    return value


def code(script):
    """The package modules a rule's script imports, transitively, with their SHA-256 (its code
    param): editing one reruns exactly the rules that run it; computed at DAG build, so new
    modules are covered.
    """
    return codedeps.code_param(SCRIPTS / script)


def source_spec(group, twin_blocks, calibration=None):
    """Where a group's recordings come from, for the first line of its summary: the twin with
    its settings (and calibration file, relative to the summary) or the lab's manifest.
    """
    return {
        "acquisition": config["acquisition"],
        "group": group,
        "twin_blocks": twin_blocks,
        "manifest": f"<raw_dir>/{group}/manifest.csv",
        "calibration": calibration if SYNTHETIC else None,
        "engine": "discrepancy.json",
        "excluded": config[group].get("exclude_trials") or {},
    }


# The report's sections, by group.
CATEGORIES = {
    "phantom": "Phantom",
    "sts": "Sit-to-stand",
    "emulator": "Emulator",
    "workflow": "The run",
}


def in_report(path, group, caption, subcategory, **labels):
    """An output flagged for the HTML report in its group's section, captioned by
    workflow/report/<caption>.rst (labels: how the report names one of several files).
    """
    flagged = report(
        path,
        caption=f"../report/{caption}.rst",
        category=CATEGORIES[group],
        subcategory=subcategory,
        labels=labels or None,
    )
    return flagged


def figure_outputs(group, folder, names, subcategory="Figures"):
    """Each named figure's outputs: the PNG (in the report, captioned by
    workflow/report/<group>_figure_<name>.rst, which includes the caption file), the PDF and the
    caption file, keyed <name>_png, <name>_pdf and <name>_caption (figures.publish writes them).
    """
    outputs = {}
    for name in names:
        png = folder / f"{name}.png"
        outputs[f"{name}_png"] = in_report(
            png, group, f"{group}_figure_{name}", subcategory
        )
        outputs[f"{name}_pdf"] = folder / f"{name}.pdf"
        outputs[f"{name}_caption"] = folder / f"{name}.caption.md"
    return outputs
