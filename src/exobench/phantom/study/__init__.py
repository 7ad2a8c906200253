"""The study's numbers: per-spring summaries, mean curves, Kruskal-Wallis and Dunn tests,
the comparison with seed 000."""
