"""Effect sizes of seed 000's rank tests (§2.5), each with an interval: ε² of the Kruskal–Wallis
test (η²_H beside it), Cliff's δ of a pair of springs.

ε² = H·(n + 1)/(n² − 1) = H/(n − 1) and η²_H = (H − k + 1)/(n − k) (k groups; Tomczak &
Tomczak 2014). ε² is 0 when the groups are alike (in expectation about (k − 1)/(n − 1), the bias
η²_H removes) and at most (n³ − Σnᵢ³)/(n(n² − 1)) when they do not overlap (H's largest value
over n − 1): for k equal groups about 1 − 1/k², 0.972 for the six springs, never 1. The interval
of ε² is a stratified bootstrap (strides resampled within each group) of ε² itself whose
percentile interval is moved back by the bootstrap's own bias (a resample adds its noise on top
of the data's), clipped to [0, its largest value]. Cliff's δ = P(B > A) − P(B < A) = 2θ − 1,
θ = P(B > A) + ½P(B = A) the Mann–Whitney parameter; its interval is θ's score interval at the
level the test is judged at (1 − α/m with m pairs under Bonferroni): the θ whose Hanley–McNeil
variance puts θ̂ on the boundary, (θ̂ − θ)² = z²·V(θ) (Hanley & McNeil 1982; solved for θ as
Newcombe 2006 does), which keeps a width when the springs do not overlap (θ̂ = 1).
``tests/test_phantom_statistics.py`` checks both intervals' coverage on simulated data.
"""

from __future__ import annotations

import numpy as np

# scipy.stats is imported where it is used: the rules that read only the statistics' constants
# start faster.

LEVEL = 0.95


def epsilon_squared(h: np.ndarray | float, n: int) -> np.ndarray | float:
    """ε² = H·(n + 1)/(n² − 1) of a Kruskal–Wallis H over n observations."""
    return np.asarray(h) * (n + 1) / (n**2 - 1.0)


def epsilon_squared_max(sizes: np.ndarray) -> float:
    """Largest ε² of groups of these sizes (no overlap, no ties): (n³ − Σnᵢ³)/(n(n² − 1))."""
    sizes = np.asarray(sizes, float)
    n = sizes.sum()
    return float((n**3 - np.sum(sizes**3)) / (n * (n**2 - 1.0)))


def eta_squared_h(h: np.ndarray | float, k: int, n: int) -> np.ndarray | float:
    """η²_H = (H − k + 1)/(n − k) of a Kruskal–Wallis H over k groups and n observations."""
    return (np.asarray(h) - k + 1) / (n - k)


def weighted_h(values: np.ndarray, codes: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Tie-corrected Kruskal–Wallis H of the samples that take observation j ``counts[:, j]``
    times (one row per sample; ``values`` sorted ascending, ``codes`` their groups):
    H = 12/(n(n+1))·Σ Rᵢ²/nᵢ − 3(n+1) over 1 − Σ(t³ − t)/(n³ − n), from the midranks of the
    distinct values, with no sort per sample."""
    new = np.r_[True, values[1:] != values[:-1]]
    ties = counts if new.all() else np.add.reduceat(counts, np.flatnonzero(new), axis=1)
    midrank = np.cumsum(ties, axis=1) - (ties - 1) / 2.0
    if not new.all():
        midrank = midrank[:, np.cumsum(new) - 1]
    groups = np.unique(codes)
    members = (codes[:, None] == groups[None, :]).astype(float)
    rank_sums = (counts * midrank) @ members
    sizes = counts[0] @ members
    n = float(counts[0].sum())
    h = 12.0 / (n * (n + 1)) * np.sum(rank_sums**2 / sizes, axis=1) - 3.0 * (n + 1)
    correction = 1.0 - np.sum(ties * (ties * ties - 1), axis=1) / (n**3 - n)
    return h / correction


def stratified_counts(codes: np.ndarray, draws: int, rng: np.random.Generator) -> np.ndarray:
    """How often each observation enters each of ``draws`` resamples drawn with replacement
    within its group (group sizes kept)."""
    picked = np.empty((draws, codes.size), dtype=np.int64)
    for group in np.unique(codes):
        members = np.flatnonzero(codes == group)
        picked[:, members] = members[rng.integers(0, members.size, size=(draws, members.size))]
    picked += (np.arange(draws) * codes.size)[:, None]
    return np.bincount(picked.ravel(), minlength=draws * codes.size).reshape(draws, codes.size)


def effect_interval(values: np.ndarray, codes: np.ndarray, draws: int,
                    rng: np.random.Generator) -> tuple[float, float]:  # fmt: skip
    """95 % bootstrap interval of ε²: percentiles − (mean* − ε̂²), clipped to [0, ε²_max]."""
    order = np.argsort(values, kind="stable")
    values, codes = np.asarray(values, float)[order], np.asarray(codes)[order]
    n = codes.size
    top = epsilon_squared_max(np.unique(codes, return_counts=True)[1])
    data = epsilon_squared(weighted_h(values, codes, np.ones((1, n))), n)[0]
    drawn = epsilon_squared(weighted_h(values, codes, stratified_counts(codes, draws, rng)), n)
    low, high = np.quantile(drawn, [(1 - LEVEL) / 2, (1 + LEVEL) / 2]) - (drawn.mean() - data)
    return float(np.clip(low, 0.0, top)), float(np.clip(high, 0.0, top))


def mann_whitney_theta(a: np.ndarray, b: np.ndarray) -> float:
    """θ = P(B > A) + ½P(B = A) from the midranks of the two samples pooled: (R_B − n_B(n_B + 1)/2)
    / (n_A·n_B)."""
    from scipy.stats import rankdata

    ranks = rankdata(np.concatenate([a, b]))
    rank_sum = ranks[a.size :].sum()
    return float((rank_sum - b.size * (b.size + 1) / 2.0) / (a.size * b.size))


def hanley_mcneil_variance(theta, n_a: int, n_b: int):
    """V(θ) = [θ(1−θ) + (n_B − 1)(θ/(2−θ) − θ²) + (n_A − 1)(2θ²/(1+θ) − θ²)] / (n_A·n_B)."""
    theta = np.asarray(theta, float)
    q1, q2 = theta / (2.0 - theta), 2.0 * theta**2 / (1.0 + theta)
    return (theta * (1 - theta) + (n_b - 1) * (q1 - theta**2) + (n_a - 1) * (q2 - theta**2)) / (
        n_a * n_b
    )


def theta_interval(theta, n_a: int, n_b: int, level: float = LEVEL,
                   steps: int = 60) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Score interval of θ: roots of (θ̂ − θ)² = z²·V(θ) around θ̂, z = z((1 + level)/2)."""
    from scipy.stats import norm

    theta = np.asarray(theta, float)
    z2 = norm.ppf((1 + level) / 2) ** 2

    def outside(t):
        return (theta - t) ** 2 > z2 * hanley_mcneil_variance(t, n_a, n_b)

    low = [np.zeros_like(theta), theta.copy()]  # outside at 0 (unless θ̂ = 0), inside at θ̂
    high = [theta.copy(), np.ones_like(theta)]
    for _ in range(steps):
        mid = (low[0] + low[1]) / 2
        out = outside(mid)
        low = [np.where(out, mid, low[0]), np.where(out, low[1], mid)]
        mid = (high[0] + high[1]) / 2
        out = outside(mid)
        high = [np.where(out, high[0], mid), np.where(out, mid, high[1])]
    return (low[0] + low[1]) / 2, (high[0] + high[1]) / 2


def cliffs_delta(theta, n_a, n_b, level: float = LEVEL):
    """Cliff's δ = 2θ − 1 of B over A with its interval at ``level`` (θ's score interval)."""
    low, high = theta_interval(theta, n_a, n_b, level)
    return 2 * np.asarray(theta, float) - 1, 2 * low - 1, 2 * high - 1
