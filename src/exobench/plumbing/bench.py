"""Command line: run times, peak memory and scaling of the workflow's rules.

``python -m exobench.plumbing.bench [results/benchmarks]`` sums the Snakemake ``benchmark:`` files,
one folder per rule (``<benchmarks>/<rule>/<job>.tsv``), and prints wall-clock seconds, peak RSS and
the number of jobs per rule.

``python -m exobench.plumbing.bench priorities [results/benchmarks]`` prints the ``priority`` each
rule should carry (the rule files' values): its remaining critical path (its own seconds and the
longest chain of rules after it, from the benchmarks and ``snakemake --rulegraph``) in steps of
:data:`PRIORITY_STEP_S`, so that a free core always takes the ready job with the longest road
ahead.

``python -m exobench.plumbing.bench disk [results] [raw]`` prints the bytes of the results folder
against those of the recordings the manifests list (the phantom's C3D files, the emulator's
brace and motion-capture CSV files; the twins' truth files left out) and their ratio.

``python -m exobench.plumbing.bench scale`` runs the phantom chain (twin to per-stride metrics)
in fresh copies of the workflow at 1×, 2× and 4× the trials per spring (the twin's repeated,
re-mounted trials) and at 4× the strides per trial, and prints per run and rule the jobs, the
mean and largest job time, the largest peak RSS, and each against the 1× run: a per-trial job
whose cost stays flat as trials are added scales out.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pandas as pd
import yaml

from exobench.errors import InputError

REPO = Path(__file__).resolve().parents[3]
# One priority level per this many seconds of remaining critical path (finer levels did not
# shorten a simulated two-core schedule of the default run).
PRIORITY_STEP_S = 5.0
RULE_NODE = re.compile(r'^\s*(\d+)\[label = "(\w+)"', re.MULTILINE)
RULE_EDGE = re.compile(r"^\s*(\d+) -> (\d+)", re.MULTILINE)
WORKFLOW_PARTS = ("Snakefile", "workflow", "config", "raw/reference")
# Scaling runs: name -> the settings the run overrides (phantom chain up to its metrics).
SCALE_TARGET = "phantom_metrics"
SCALE_RUNS = {
    "1x trials": {},
    "2x trials": {"phantom": {"protocol": {"trials": {"repeats": 2}}}},
    "4x trials": {"phantom": {"protocol": {"trials": {"repeats": 4}}}},
    "4x strides": {"phantom": {"protocol": {"strides": 600}}},
}


def summary(folder: str | Path) -> pd.DataFrame:
    """Seconds (sum, mean and max), peak RSS (MB) and job count per rule from the benchmarks."""
    rows = []
    for path in sorted(Path(folder).glob("*/*.tsv")):
        try:
            record = pd.read_csv(path, sep="\t").iloc[-1]
            seconds, rss = record["s"], record["max_rss"]
        except (pd.errors.ParserError, pd.errors.EmptyDataError, IndexError, KeyError) as error:
            expected = "a Snakemake benchmark record"
            raise InputError(path, "s, max_rss", expected, repr(error)) from None
        rows.append({"rule": path.parent.name, "s": seconds, "max_rss_MB": rss})
    table = pd.DataFrame(rows)
    if table.empty:
        return table
    return table.groupby("rule").agg(
        jobs=("s", "size"),
        total_s=("s", "sum"),
        mean_job_s=("s", "mean"),
        max_job_s=("s", "max"),
        max_rss_MB=("max_rss_MB", "max"),
    )


# The recordings of each group's manifest: the columns that name a file.
RECORDING_COLUMNS = {"phantom": ("file",), "emulator": ("file", "mocap_file")}


def disk(results: str | Path, raw: str | Path) -> dict[str, float]:
    """Bytes of ``results`` and of the recordings the manifests under ``raw`` list, and the
    ratio results / recordings."""
    stored = sum(p.stat().st_size for p in Path(results).rglob("*") if p.is_file())
    recorded = 0
    for group, columns in RECORDING_COLUMNS.items():
        manifest = Path(raw) / group / "manifest.csv"
        if manifest.is_file():
            names = pd.read_csv(manifest)[list(columns)].to_numpy().ravel()
            recorded += sum((manifest.parent / name).stat().st_size for name in names)
    ratio = stored / recorded if recorded else float("nan")
    return {"results_MB": stored / 1e6, "recordings_MB": recorded / 1e6, "ratio": ratio}


def copy_workflow(root: Path, repo: Path = REPO) -> Path:
    """Copy the workflow's code, config and reference data into ``root``."""
    for part in WORKFLOW_PARTS:
        source, target = repo / part, root / part
        target.parent.mkdir(parents=True, exist_ok=True)
        if source.is_dir():
            shutil.copytree(source, target, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy2(source, target)
    return root


def run_scaled(settings: dict, cores: int) -> pd.DataFrame:
    """The phantom chain in a fresh copy of the workflow with ``settings`` on top of the
    config; its benchmark summary per rule."""
    with tempfile.TemporaryDirectory(prefix="exobench-scale-") as tmp:
        root = copy_workflow(Path(tmp))
        (root / "scale.yaml").write_text(yaml.safe_dump(settings))
        snakemake = Path(sys.executable).with_name("snakemake")
        command = [str(snakemake), "--cores", str(cores), SCALE_TARGET]
        subprocess.run([*command, "--configfile", "scale.yaml"], cwd=root, check=True,
                       capture_output=True, text=True)  # fmt: skip
        return summary(root / "results" / "benchmarks")


def scaling(cores: int = 2, runs: dict = SCALE_RUNS) -> pd.DataFrame:
    """Per run and rule: jobs, mean and largest job seconds, peak RSS, and the mean job time
    and peak RSS as ratios to the first run's (1.0: a job costs the same)."""
    tables = {name: run_scaled(settings, cores) for name, settings in runs.items()}
    base = next(iter(tables.values()))
    parts = []
    for name, table in tables.items():
        part = table[["jobs", "mean_job_s", "max_job_s", "max_rss_MB"]].copy()
        part["job_s_ratio"] = part["mean_job_s"] / base["mean_job_s"]
        part["rss_ratio"] = part["max_rss_MB"] / base["max_rss_MB"]
        parts.append(part.assign(run=name).reset_index())
    return pd.concat(parts, ignore_index=True).set_index(["run", "rule"])


def rule_edges(dot: str) -> list[tuple[str, str]]:
    """(rule, rule reading its outputs) pairs of a ``snakemake --rulegraph`` DOT text."""
    names = dict(RULE_NODE.findall(dot))
    return [(names[a], names[b]) for a, b in RULE_EDGE.findall(dot)]


def remaining_path(seconds: dict[str, float], edges: list[tuple[str, str]]) -> dict[str, float]:
    """Remaining critical path of each rule: r(u) = t(u) + max r(v) over the rules v after u."""
    after: dict[str, list[str]] = {}
    for a, b in edges:
        after.setdefault(a, []).append(b)
    rules = set(seconds) | {r for edge in edges for r in edge}
    path: dict[str, float] = {}
    for rule in sorted(rules):
        _fill(rule, seconds, after, path)
    return path


def _fill(rule, seconds, after, path) -> float:
    """r(rule) of :func:`remaining_path`, the rules after it first (memoised in ``path``)."""
    if rule not in path:
        later = [_fill(r, seconds, after, path) for r in after.get(rule, [])]
        path[rule] = float(seconds.get(rule, 0.0)) + max(later, default=0.0)
    return path[rule]


def priorities(path: dict[str, float], step: float = PRIORITY_STEP_S) -> dict[str, int]:
    """Snakemake priority of each rule: ⌊remaining critical path / step⌋."""
    return {rule: int(value // step) for rule, value in path.items()}


def print_priorities(table: pd.DataFrame) -> int:
    """Print each rule's remaining critical path and priority (longest first), the rule graph
    being this workflow's (``snakemake --rulegraph`` in the repository)."""
    snakemake = Path(sys.executable).with_name("snakemake")
    dot = subprocess.run([str(snakemake), "--rulegraph", "-q"], cwd=REPO, check=True,
                         capture_output=True, text=True).stdout  # fmt: skip
    path = remaining_path(table["total_s"].to_dict(), rule_edges(dot))
    for rule, level in sorted(priorities(path).items(), key=lambda item: -path[item[0]]):
        print(f"{rule:32s} {path[rule]:6.1f} s  priority {level}")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("folder", nargs="?", default="results/benchmarks")
    parser.add_argument("extra", nargs="?", help="priorities: the benchmarks folder")
    parser.add_argument("--cores", type=int, default=2, help="cores of the scale runs")
    parser.add_argument("--raw", default="raw", help="disk: the recordings' folder")
    args = parser.parse_args(argv)
    if args.folder == "disk":
        found = disk(args.extra or "results", args.raw)
        print(", ".join(f"{key} {value:.2f}" for key, value in found.items()))
        return 0
    if args.folder == "scale":
        print(scaling(args.cores).round(3).to_string())
        return 0
    folder = (args.extra or "results/benchmarks") if args.folder == "priorities" else args.folder
    try:
        table = summary(folder)
    except InputError as error:
        print(f"exobench.plumbing.bench: {error}", file=sys.stderr)
        return 2
    if table.empty:
        print(f"exobench.plumbing.bench: no <rule>/<job>.tsv benchmark files in {folder}",
              file=sys.stderr)  # fmt: skip
        return 2
    if args.folder == "priorities":
        return print_priorities(table)
    print(table.round(2).to_string())
    print(f"all rules: {table['total_s'].sum():.1f} s of job time")
    return 0


if __name__ == "__main__":
    sys.exit(main())
