"""What the phantom's summary says of W.S.B. et al.'s statistics and numbers reproduced: the
statistics' own verdict (the paired analysis of the design run beside the study's unpaired one,
the one-trial confound, the genuine predictions counted), the effect sizes, the slope values
the validity rule left out, the outlying strides, the study's significance statements against
the reproduced tests, the reproduction by role and the method checking itself (the twin's
prediction against the chain's measurement of its own recordings), each with the table that
holds it."""

from __future__ import annotations

import pandas as pd

from exobench import roles
from exobench.phantom.study import comparison as numbers
from exobench.phantom.study import significance as statements
from exobench.phantom.study.kept import at_spring
from exobench.phantom.study.paired import P_FLOOR
from exobench.selection.summary import number

SHOWN = 3  # outliers and misses named in the summary (the tables hold every one)


def effects(kruskal: pd.DataFrame) -> str:
    """Kruskal–Wallis ε² = H/(n − 1) over the metrics, with its untied maximum for the sizes."""
    rows = kruskal[kruskal["analysis"] == "as_study"].sort_values("epsilon2")
    low, high = rows.iloc[0], rows.iloc[-1]
    significant = int((rows["p"] < 0.05).sum())
    return (
        f"**Effect sizes** ([stats/kruskal.csv](stats/kruskal.csv)): Kruskal–Wallis across the "
        f"springs is significant (p < 0.05) for {significant} of {len(rows)} metrics; "
        f"ε² = H/(n − 1) (0 for alike springs; for untied data at most "
        f"{number(high['epsilon2_max'])}, springs that do not overlap, not 1) runs from "
        f"{number(low['epsilon2'])} [{number(low['epsilon2_ci_low'])}, "
        f"{number(low['epsilon2_ci_high'])}] ({low['metric']}) to {number(high['epsilon2'])} "
        f"[{number(high['epsilon2_ci_low'])}, {number(high['epsilon2_ci_high'])}] "
        f"({high['metric']}); every Dunn pair has z, p unadjusted and Bonferroni-adjusted and "
        "Cliff's δ with its interval at the Bonferroni level, like its test "
        "([stats/dunn/](stats/dunn/))."
    )


def paired_design(omnibus: pd.DataFrame, pairs: pd.DataFrame, alpha: float) -> str:
    """Friedman, Wilcoxon and mixed-model counts (p < α), σ²_traj share, and the trial as a unit."""
    friedman = int((omnibus["friedman_p"] < alpha).sum())
    mixed = int((omnibus["mixed_p"] < alpha).sum())
    every = pairs.groupby("metric")["p_adjusted"].apply(lambda p: bool((p < alpha).all()))
    count = int(pairs.groupby("metric").size().max())
    share = omnibus.set_index("metric")["trajectory_share"].dropna().sort_values()
    bound = omnibus.set_index("metric")["trajectory_share_at_bound"].astype(bool)
    low = (
        f"at its bound 0 in {', '.join(bound.index[bound])}: no trajectory variance estimable"
        if bound.any()
        else f"from {number(share.iloc[0])}, {share.index[0]}"
    )
    floor = omnibus.loc[omnibus["mixed_p_at_floor"].astype(bool), "metric"]
    under = (f" The mixed model's p lies below the smallest float ({P_FLOOR:.2g}, written "
             f"at that floor) in {len(floor)} metrics." if len(floor) else "")  # fmt: skip
    text = (
        f"**The design run, analysed as run** ([stats/paired.csv](stats/paired.csv), "
        f"[stats/wilcoxon.csv](stats/wilcoxon.csv)): the same trajectories at every spring make "
        f"the strides paired ({int(omnibus['n_trajectories'].min())}–"
        f"{int(omnibus['n_trajectories'].max())} trajectories complete at every spring). "
        f"Friedman's test finds the springs differ in {friedman} of {len(omnibus)} metrics, the "
        f"mixed model y ~ spring + (1 | trajectory) in {mixed}; the paired Wilcoxon tests "
        f"(Bonferroni) separate every one of the {count} pairs in {int(every.sum())} metrics. The "
        f"trajectory holds a median {number(share.median())} of a metric's variance ({low}; "
        f"up to {number(share.iloc[-1])}, {share.index[-1]}).{under}"
    )
    trials = int(omnibus["trials_per_spring"].min())
    if trials < 2:
        return text + (
            " **One trial per spring**: every spring was one mounting, recorded once, in one "
            "place of the test order, so no p-value here tests the springs against "
            "trial-to-trial variation (re-mounting, order, the interface's state): a spring "
            "effect and a trial effect cannot be told apart."
        )
    tested = int((omnibus["trial_p"] < alpha).sum())
    return text + (
        f" **{trials} trials per spring**, re-mounted: the between-trial variance is "
        f"{number(omnibus['trial_variance'].min())}–{number(omnibus['trial_variance'].max())} "
        f"(in each metric's unit²), and tested against it (F on the trial means, df "
        f"{int(omnibus['trial_df'].max())} and {int(omnibus['trial_df_denominator'].max())}) the "
        f"springs differ in {tested} of {len(omnibus)} metrics."
    )


def validity_text(summary: pd.DataFrame, threshold_deg: float) -> str:
    """Slope values the validity rule (excursion < Δθ) left out, per metric and spring."""
    rows = summary[summary["invalid"] > 0]
    if rows.empty:
        listed = "none"
    else:
        listed = "; ".join(
            f"{metric}: "
            + ", ".join(f"{int(r.invalid)}{at_spring(r.spring_stiffness_N_per_m)}"
                        for r in group.itertuples())
            for metric, group in rows.groupby("metric", sort=False)
        )  # fmt: skip
    return (
        f"**Validity before outliers** ([summary.csv](summary.csv), column `invalid`): a stride's "
        f"stiffness exists only when its loading excursion reaches {threshold_deg:.2g}° (derived "
        "from the marker noise, config phantom.statistics.slope_validity); left out before any "
        f"outlier is looked for: {listed}."
    )


def outliers(found: pd.DataFrame, kruskal: pd.DataFrame, threshold: float) -> str:
    """Strides beyond the robust-z threshold, the most extreme, and any changed H decision."""
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
    """Statements and pairs each analysis agrees with, those resting on unpairing, TOST, causes."""
    count = statements.counts(table)
    compared = table[table["agree"].notna()]
    causes = compared.loc[compared["cause"].fillna("") != "", "cause"].value_counts()
    because = "; ".join(f"{n} {cause}" for cause, n in causes.items())
    return (
        f"**The study's significance statements** "
        f"([significance_comparison.csv](significance_comparison.csv)): "
        f"{count['statements_agree']} of {count['statements']} statements agree with the "
        f"reproduced unpaired Dunn tests in every pair they name ({count['pairs_agree']} of "
        f"{count['pairs']} pairs), {count['statements_paired_agree']} with the paired Wilcoxon "
        f"tests ({count['pairs_paired_agree']} of {count['pairs']} pairs). "
        f"{_n(count['statements_pairing'], 'statement holds', 'statements hold')} only when the "
        "pairing is ignored (the unpaired test gives the study's decision in every pair named, "
        "the paired test not in at least one); pair by pair, "
        f"{count['pairs_pairing']} pairs get the study's decision from the unpaired test alone. "
        f"Of the {count['alike_pairs']} pairs the study calls not different, paired two "
        "one-sided tests within the metric's margin (each at "
        f"α, not adjusted over the pairs) show {count['equivalent']} equivalent, "
        f"{count['different_but_equivalent']} of them different but equivalent (the paired "
        "test separates them by less than the margin). "
        f"{count['not_compared']} statements state no test and are not compared."
        + (f" Causes where the study's decision is not the design's: {because}." if because else "")
    )


def reproduction(table: pd.DataFrame) -> str:
    """The reproduced numbers by role (exobench.roles): predictions out of sample, and misses."""
    measured, count = numbers.rate(table, ["measured"])
    tally = roles.counts(table["role"], table["within_tolerance"])
    if count:
        head = f"{measured} of {count} numbers measured reproduced within their tolerance"
    else:
        total, got = tally.get("prediction", (0, 0))
        fare = f", {got} reproduced within tolerance" if total else ""
        parts = [f"{n} {role}{'s' if n != 1 else ''} ({k} within tolerance)"
                 for role, (n, k) in tally.items() if role != "prediction"]  # fmt: skip
        derived = int((table["role"] == "derived").sum())
        head = (f"{total or 'no'} number{'s' if total != 1 else ''} out of sample (predictions: "
                f"nothing fitted or chosen determines {'them' if total != 1 else 'it'}){fare}; "
                f"beside them {', '.join(parts)}, and {derived} derived from other rows (not "
                "counted)")  # fmt: skip
    kinds = ["measured"] if count else ["prediction"]
    missed = table[table["role"].isin(kinds) & ~table["within_tolerance"]]
    listed = "; ".join(f"{r.metric}{at_spring(r.spring_stiffness_N_per_m)}: {r.reason}"
                       for r in missed.head(SHOWN).itertuples())  # fmt: skip
    more = f" (and {len(missed) - SHOWN} more)" if len(missed) > SHOWN else ""
    return (
        f"**The study's numbers** ([paper_comparison.csv](paper_comparison.csv), columns `role`, "
        f"`role_basis` and `reason`): {head}." + (f" Missed: {listed}{more}." if listed else "")
    )


def _n(count: int, one: str, many: str) -> str:
    """'1 statement holds' or 'n statements hold'."""
    return f"{count} {one if count == 1 else many}"


def verdict(omnibus: pd.DataFrame, agreed: pd.DataFrame | None, compared: pd.DataFrame | None,
            alpha: float) -> str:  # fmt: skip
    """The statistics' verdict: paired result beside the study's, confound, predictions counted."""
    friedman = int((omnibus["friedman_p"] < alpha).sum())
    mixed = int((omnibus["mixed_p"] < alpha).sum())
    text = (
        f"The study tested its springs as independent samples (Kruskal–Wallis, Dunn); the "
        f"design it ran is paired (the same trajectories at every spring), and analysed so "
        f"the springs differ in {friedman} of {len(omnibus)} metrics by Friedman's test and in "
        f"{mixed} by the mixed model y ~ spring + (1 | trajectory)."
    )
    if agreed is not None:
        count = statements.counts(agreed)
        shown = (f"{count['equivalent']} of its {count['alike_pairs']}" if count["equivalent"]
                 else "none of its")  # fmt: skip
        text += (
            f" Of the study's {count['statements']} tested statements, "
            f"{count['statements_agree']} are reproduced in every pair by its own unpaired test "
            f"(Dunn) and {count['statements_paired_agree']} by the paired one (Wilcoxon); "
            f"{count['statements_pairing']} of them "
            f"{'holds' if count['statements_pairing'] == 1 else 'hold'} only by ignoring the "
            "pairing, and "
            f'{shown} "not different" pairs are shown equivalent (paired two one-sided tests), '
            f"{count['different_but_equivalent']} of them different but equivalent."
        )
    if int(omnibus["trials_per_spring"].min()) < 2:
        text += (
            " With one trial per spring the spring is confounded with the trial, so none of "
            "these tests, the study's or ours, separates a spring effect from a mounting effect."
        )
    if compared is not None and not (compared["role"] == "measured").any():
        tally = roles.counts(compared["role"], compared["within_tolerance"])
        total, got = tally.get("prediction", (0, 0))
        fare = f"; {got} reproduced within tolerance" if total else ""
        text += (
            f" Of the {len(compared)} numbers it reports, {total} "
            f"{'is a genuine prediction' if total == 1 else 'are genuine predictions'} (out of "
            f"sample, by the role rule{fare}); the rest are settings, calibration targets or "
            "derived from other numbers (paper_comparison.csv)."
        )
    return f"**What the study's statistics get wrong**: {text}"


def method(table: pd.DataFrame) -> str:
    """Twin predictions against the chain's measurement of the twin: how many differ, which side."""
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
    """One bullet per method-check finding, then the chain's departures from the same truth."""
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
            paired: tuple[pd.DataFrame, pd.DataFrame, float],
            validity: tuple[pd.DataFrame, float],
            compared: pd.DataFrame | None = None, agreed: pd.DataFrame | None = None,
            checked: pd.DataFrame | None = None) -> list[str]:  # fmt: skip
    """The statistics section; ``paired`` = (omnibus, pairs, α), ``validity`` = (table, Δθ)."""
    omnibus, pairs, alpha = paired
    lines = ["## The study's statistics and numbers, reproduced", ""]
    lines += [verdict(omnibus, agreed, compared, alpha), ""]
    lines += [
        f"- {paired_design(omnibus, pairs, alpha)}",
        f"- {effects(kruskal)}",
        f"- {validity_text(*validity)}",
        f"- {outliers(found, kruskal, threshold)}",
    ]
    if agreed is not None:
        lines.append(f"- {significance(agreed)}")
    if compared is not None:
        lines.append(f"- {reproduction(compared)}")
    if checked is not None:
        lines += [f"- {method(checked)}", *findings(checked)]
    return [*lines, ""]
