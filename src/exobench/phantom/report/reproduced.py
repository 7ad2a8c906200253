"""What the phantom's summary says of W.S.B. et al.'s statistics and numbers reproduced: the
effect sizes, the outlying strides, the study's significance statements against the reproduced
tests, the reproduction rate of the predictions alone (the calibration targets apart) and the
method checking itself (the twin's prediction against the chain's measurement of its own
recordings), each with the table that holds it."""

from __future__ import annotations

import pandas as pd

from exobench.phantom.study import comparison as numbers
from exobench.phantom.study import significance as statements
from exobench.phantom.study.kept import at_spring
from exobench.selection.summary import number

SHOWN = 3  # outliers and misses named in the summary (the tables hold every one)


def effects(kruskal: pd.DataFrame) -> str:
    """The Kruskal–Wallis effect sizes' range over the metrics, as the study tested them."""
    rows = kruskal[kruskal["analysis"] == "as_study"].sort_values("epsilon2")
    low, high = rows.iloc[0], rows.iloc[-1]
    significant = int((rows["p"] < 0.05).sum())
    return (
        f"**Effect sizes** ([stats/kruskal.csv](stats/kruskal.csv)): Kruskal–Wallis across the "
        f"springs is significant (p < 0.05) for {significant} of {len(rows)} metrics; ε² runs "
        f"from {number(low['epsilon2'])} [{number(low['epsilon2_ci_low'])}, "
        f"{number(low['epsilon2_ci_high'])}] ({low['metric']}) to {number(high['epsilon2'])} "
        f"[{number(high['epsilon2_ci_low'])}, {number(high['epsilon2_ci_high'])}] "
        f"({high['metric']}); every Dunn pair has z, p unadjusted and Bonferroni-adjusted and "
        "Cliff's δ with its 95 % interval ([stats/dunn/](stats/dunn/))."
    )


def outliers(found: pd.DataFrame, kruskal: pd.DataFrame, threshold: float) -> str:
    """How many strides are flagged, the most extreme with their reasons, and whether leaving
    them out changes any Kruskal–Wallis decision."""
    if found.empty:
        return (f"**Outliers** ([outliers.csv](outliers.csv)): no stride lies beyond "
                f"{threshold:g} robust SD of its spring's median in any metric.")  # fmt: skip
    strides = found.groupby(["trial", "stride"]).ngroups
    worst = found.reindex(found["robust_z"].abs().sort_values(ascending=False).index)
    named = "; ".join(f"{r.trial} stride {r.stride}: {r.reason}"
                      for r in worst.head(SHOWN).itertuples())  # fmt: skip
    study = kruskal[kruskal["analysis"] == "as_study"].set_index("metric")["p"] < 0.05
    plain = kruskal[kruskal["analysis"] == "without_outliers"].set_index("metric")["p"] < 0.05
    changed = [m for m in plain.index if plain[m] != study[m]]
    change = (f"changes the Kruskal–Wallis decision of {', '.join(changed)}" if changed
              else "changes no Kruskal–Wallis decision")  # fmt: skip
    return (
        f"**Outliers** ([outliers.csv](outliers.csv), column `outlier_reason` of "
        f"metrics.parquet): {len(found)} values in {strides} strides lie beyond {threshold:g} "
        f"robust SD of their spring's median; the most extreme: {named}. They are drawn (×) "
        "in figures 5–7 and 10 and kept in every statistic, as the study kept every included "
        f"stride; leaving them out (the `without_outliers` rows of stats/) {change}."
    )


def significance(table: pd.DataFrame) -> str:
    """How many of the study's significance statements the reproduced tests agree with, and the
    causes of the disagreements."""
    count = statements.counts(table)
    causes = table.loc[table["agree"].notna() & ~table["agree"].fillna(True).astype(bool),
                       "cause"].value_counts()  # fmt: skip
    because = "; ".join(f"{n} {cause}" for cause, n in causes.items())
    return (
        f"**The study's significance statements** "
        f"([significance_comparison.csv](significance_comparison.csv)): "
        f"{count['statements_agree']} of {count['statements']} statements agree with the "
        f"reproduced Dunn tests in every pair they name ({count['pairs_agree']} of "
        f"{count['pairs']} pairs); {count['not_compared']} state no test and are not compared."
        + (f" Causes of the pairs that disagree: {because}." if because else "")
    )


def reproduction(table: pd.DataFrame) -> str:
    """The reproduction rate of the predictions alone, the calibration targets apart, and the
    predictions missed with their reasons."""
    got, total = numbers.rate(table, ["prediction"])
    fitted, targets = numbers.rate(table, ["calibration target"])
    measured, count = numbers.rate(table, ["measurement"])
    if count:
        head = f"{measured} of {count} numbers measured reproduced within their tolerance"
    else:
        head = (f"{got} of {total} predictions reproduced within their tolerance (rounding and "
                f"sampling error); the {targets} calibration targets are the twin's fit, not a "
                f"reproduction ({fitted} of them within tolerance)")  # fmt: skip
    roles = ["measurement"] if count else ["prediction"]
    missed = table[table["role"].isin(roles) & ~table["within_tolerance"]]
    listed = "; ".join(f"{r.metric}{at_spring(r.spring_stiffness_N_per_m)}: {r.reason}"
                       for r in missed.head(SHOWN).itertuples())  # fmt: skip
    more = f" (and {len(missed) - SHOWN} more)" if len(missed) > SHOWN else ""
    return (
        f"**The study's numbers** ([paper_comparison.csv](paper_comparison.csv), columns `role` "
        f"and `reason`): {head}." + (f" Missed: {listed}{more}." if listed else "")
    )


def method(table: pd.DataFrame) -> str:
    """The twin's predictions against the chain's measurement of its own recordings: how many
    differ beyond their uncertainty, and each finding with the side that is wrong."""
    differ = table[table["beyond"]]
    head = (
        f"**The method checking itself** ([method_check.csv](method_check.csv)): of "
        f"{len(table)} numbers the twin predicts, the chain's measurement of the twin's own "
        f"recordings differs from the prediction beyond their uncertainty (bootstrap errors of "
        f"both medians, Bonferroni over the numbers) in {len(differ)}"
    )
    if differ.empty:
        return head + "."
    sides = differ["side"].value_counts()
    tally = ", ".join(f"{n} the {side}" for side, n in sides.items())
    return head + f" (wrong side, from the twin's true values of the same strides: {tally}):"


def findings(table: pd.DataFrame) -> list[str]:
    """One bullet per finding of the method check, then the chain's departures from the truth
    of the same strides that the comparison with the prediction does not resolve."""
    lines = [f"  - {text}" for text in table.loc[table["beyond"], "finding"]]
    paired = table[table["chain_departs"] & ~table["beyond"]]
    if not paired.empty:
        listed = "; ".join(
            f"{r.metric}{at_spring(r.spring_stiffness_N_per_m)} {r.chain_minus_truth:+.3g} ± "
            f"{r.chain_minus_truth_se:.2g} {r.unit}"
            for r in paired.itertuples()
        )
        lines.append(
            f"  - Paired on the same strides, the chain also departs from the twin's true "
            f"values, within the prediction's uncertainty, in {len(paired)} more: {listed}."
        )
    return lines


def section(kruskal: pd.DataFrame, found: pd.DataFrame, threshold: float,
            compared: pd.DataFrame | None = None, agreed: pd.DataFrame | None = None,
            checked: pd.DataFrame | None = None) -> list[str]:  # fmt: skip
    """The summary's section: effect sizes, outliers, and with W.S.B. et al.'s numbers the
    significance statements, the reproduction and the method check."""
    lines = ["## The study's statistics and numbers, reproduced", ""]
    lines += [f"- {effects(kruskal)}", f"- {outliers(found, kruskal, threshold)}"]
    if agreed is not None:
        lines.append(f"- {significance(agreed)}")
    if compared is not None:
        lines.append(f"- {reproduction(compared)}")
    if checked is not None:
        lines += [f"- {method(checked)}", *findings(checked)]
    return [*lines, ""]
