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

from importlib import import_module

# The engine's API by the module that defines it, imported on first use (PEP 562): a verdict or
# summary that only formats a report then does not load the fitting machinery (scipy, sklearn).
_API = {
    "fit": "fitting",
    **dict.fromkeys(("bootstrap_intervals", "earned", "estimate", "expansion",
                     "resample_counts", "resolved", "systematic_ratio"), "intervals"),
    **dict.fromkeys(("Data", "Effect", "Parameter", "Problem", "Settings", "parameters",
                     "predict", "residuals"), "model"),
    "analyse": "report",
    "block_folds": "search",
    **dict.fromkeys(("detection_limit", "drawn_change", "drawn_effects", "stability_summary",
                     "validation_rows"), "validation"),
}  # fmt: skip


def __getattr__(name: str):
    """An API name, from its module (imported once, on first use)."""
    if name not in _API:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(import_module(f"{__name__}.{_API[name]}"), name)


def __dir__() -> list[str]:
    """The engine's API names."""
    return sorted(_API)
