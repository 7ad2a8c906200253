"""Command line: run times, peak memory and scaling of the workflow's rules.

``python -m exobench.plumbing.bench [results/benchmarks]`` sums the Snakemake ``benchmark:`` files,
one folder per rule (``<benchmarks>/<rule>/<job>.tsv``), and prints wall-clock seconds, peak RSS and
the number of jobs per rule.

``python -m exobench.plumbing.bench priorities [results/benchmarks]`` prints the ``priority`` each
rule should carry (the rule files' values): its remaining critical path (its own seconds and the
longest chain of rules after it, from the benchmarks and ``snakemake --rulegraph``) in steps of
:data:`PRIORITY_STEP_S`, so that a free core always takes the ready job with the longest road
ahead.

``python -m exobench.plumbing.bench scale`` runs the phantom group at two protocol sizes (strides
per trial) and the emulator group at two recording durations, two trials each, in fresh copies of
the workflow, and prints per rule the time per unit of data (stride or recorded second, per trial)
at both sizes, their ratio (1.0 = linear) and the peak RSS.
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
# Scaling runs: group -> (target, protocol key to override, small and large size, data unit).
# The phantom run stops at the per-stride metrics (the chain); the emulator runs whole.
SCALES = {
    "phantom": ("phantom_metrics", "strides", (150, 1500), "stride"),
    "emulator": ("emulator", "duration_s", (30.0, 300.0), "recording_s"),
}
# Time per unit is per trial, so the scaling runs use two trials per group (the softest and
# the stiffest spring; two stiffnesses at 1.2 m/s, the encoder-drop trial among them).
TRIALS = {
    "phantom": {"springs_N_per_m": [3400, 21700], "test_order_N_per_m": [21700, 3400]},
    "emulator": {"speeds_m_per_s": [1.2], "stiffnesses_Nm_per_rad": [1.0, 3.5]},
}


def summary(folder: str | Path) -> pd.DataFrame:
    """Seconds (sum and max), peak RSS (MB) and job count per rule from the benchmark files."""
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
        max_job_s=("s", "max"),
        max_rss_MB=("max_rss_MB", "max"),
    )


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


def run_size(group: str, size: float, cores: int) -> pd.DataFrame:
    """Run one group at one size in a fresh copy of the workflow; its benchmark summary."""
    target, key, _, _ = SCALES[group]
    with tempfile.TemporaryDirectory(prefix=f"exobench-scale-{group}-") as tmp:
        root = copy_workflow(Path(tmp))
        protocol = {**TRIALS[group], key: size}
        # every job its own process (no job server), so that its benchmark measures its memory
        settings = {group: {"protocol": protocol}, "job_server": {"min_jobs": 0}}
        (root / "scale.yaml").write_text(yaml.safe_dump(settings))
        snakemake = Path(sys.executable).with_name("snakemake")
        command = [str(snakemake), "--cores", str(cores), target, "--configfile", "scale.yaml"]
        subprocess.run(command, cwd=root, check=True, capture_output=True, text=True)
        return summary(root / "results" / "benchmarks")


def scaling(group: str, cores: int = 2) -> pd.DataFrame:
    """Per rule: seconds and seconds per unit at the small and the large size, ratio, peak RSS."""
    _, _, (small, large), unit = SCALES[group]
    runs = {size: run_size(group, size, cores) for size in (small, large)}
    table = pd.DataFrame(
        {
            "s_small": runs[small]["total_s"],
            "s_large": runs[large]["total_s"],
            f"s_per_{unit}_small": runs[small]["total_s"] / small,
            f"s_per_{unit}_large": runs[large]["total_s"] / large,
        }
    )
    table["ratio"] = table[f"s_per_{unit}_large"] / table[f"s_per_{unit}_small"]
    rss = pd.concat([runs[small]["max_rss_MB"], runs[large]["max_rss_MB"]], axis=1)
    table["max_rss_MB"] = rss.max(axis=1)
    total = table[["s_small", "s_large"]].sum()
    table.loc["all rules"] = {
        "s_small": total["s_small"],
        "s_large": total["s_large"],
        f"s_per_{unit}_small": total["s_small"] / small,
        f"s_per_{unit}_large": total["s_large"] / large,
        "ratio": (total["s_large"] / large) / (total["s_small"] / small),
        "max_rss_MB": table["max_rss_MB"].max(),
    }
    return table


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
    parser.add_argument("--groups", nargs="+", default=list(SCALES), choices=list(SCALES))
    args = parser.parse_args(argv)
    if args.folder == "scale":
        for group in args.groups:
            print(f"{group}:")
            print(scaling(group, args.cores).round(4).to_string())
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
    print("(a job run through the job server shows its waiting process's memory in max_rss_MB: "
          "measure memory with --config 'job_server={min_jobs: 0}')")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
