"""One model-selection engine for every rule group: which physical effects the data earn.

A group supplies a :class:`Problem`: its effect registry (each :class:`Effect` a forward
transformation of the baseline prediction), the baseline, the measured observables and the
noise-only samples of its own data. The engine does the rest, the same way everywhere, one
module per stage:

- :mod:`.model`: the types, and the prediction and residuals of a set of effects;
- :mod:`.fitting`: least-squares fits of a candidate's parameters (log or linear scale, bounded);
- :mod:`.search`: blocked cross-validation (contiguous blocks of units within every trial,
  every parameter fitted on the training blocks only), forward selection (at most n·(n+1)/2
  candidates) and the one-standard-error rule on the paired held-out losses;
- :mod:`.intervals`: block bootstrap over units, each resample refitted by one Gauss–Newton step
  from the full-data fit, for 95 % percentile intervals (Wald intervals from the Jacobian when
  there are too few units to resample), and whether an effect is earned;
- :mod:`.structure`: the "unexplained structure" verdict on the held-out residuals;
- :mod:`.stability`: whether the constants that must hold between trials do (each refitted per
  trial, Welch's test across trials, Holm over the constants);
- :mod:`.report`: one report with the same keys for every group;
- :mod:`.workers`: worker processes sharing the independent fits;
- :mod:`.validation`: drawing hidden effects and scoring reports against the truth.
"""

from exobench.selection.fitting import fit
from exobench.selection.intervals import (
    bootstrap_intervals,
    earned,
    estimate,
    expansion,
    resample_counts,
    resolved,
    systematic_ratio,
)
from exobench.selection.model import (
    Data,
    Effect,
    Parameter,
    Problem,
    Settings,
    parameters,
    predict,
    residuals,
)
from exobench.selection.report import analyse
from exobench.selection.search import block_folds
from exobench.selection.validation import (
    detection_limit,
    drawn_change,
    drawn_effects,
    stability_summary,
    validation_rows,
)

__all__ = [
    "Data",
    "Effect",
    "Parameter",
    "Problem",
    "Settings",
    "analyse",
    "block_folds",
    "bootstrap_intervals",
    "detection_limit",
    "drawn_change",
    "drawn_effects",
    "earned",
    "estimate",
    "expansion",
    "fit",
    "parameters",
    "predict",
    "resample_counts",
    "residuals",
    "resolved",
    "stability_summary",
    "systematic_ratio",
    "validation_rows",
]
