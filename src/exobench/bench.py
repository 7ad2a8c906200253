"""Command line: ``python -m exobench.bench [results/benchmarks]`` sums rule run times.

Every rule writes a Snakemake ``benchmark:`` file; this groups them by rule (wildcard jobs
such as ``phantom_filter_k03400`` count under ``phantom_filter``) and prints wall-clock seconds,
peak memory and the number of jobs.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import pandas as pd

WILDCARD_SUFFIX = re.compile(r"_k\d{5}$")


def summary(folder: str | Path) -> pd.DataFrame:
    """Seconds (sum and max), peak RSS and job count per rule from Snakemake benchmark files."""
    rows = []
    for path in sorted(Path(folder).glob("*.tsv")):
        record = pd.read_csv(path, sep="\t").iloc[-1]
        rows.append(
            {
                "rule": WILDCARD_SUFFIX.sub("", path.stem),
                "s": record["s"],
                "max_rss_MB": record["max_rss"],
            }
        )
    table = pd.DataFrame(rows)
    if table.empty:
        return table
    return table.groupby("rule").agg(
        jobs=("s", "size"),
        total_s=("s", "sum"),
        max_job_s=("s", "max"),
        max_rss_MB=("max_rss_MB", "max"),
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("folder", nargs="?", default="results/benchmarks")
    args = parser.parse_args(argv)
    table = summary(args.folder)
    print(table.round(2).to_string())
    if not table.empty:
        print(f"all rules: {table['total_s'].sum():.1f} s of job time")
    return 0


if __name__ == "__main__":
    sys.exit(main())
