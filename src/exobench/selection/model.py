"""The engine's types and the forward model of a candidate: a group's effect registry, its
observations, the settings; predictions and residuals of a set of effects."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np


@dataclass(frozen=True)
class Parameter:
    """A fitted constant: name with unit suffix, unit, bounds, physical meaning, fit scale;
    ``resolution`` the finest step in which the data can show it (a 95 % interval is never
    narrower than ± half of it); ``shape`` for a parameter at whose neutral value the effect
    does not vanish (a settling time: a cuff without lag is still compliant), which therefore
    does not decide whether the data earn the effect."""

    name: str
    unit: str
    low: float
    high: float
    meaning: str
    log: bool = True
    start: float | None = None
    neutral: float = 0.0
    detectable: tuple[float, float] = (0.0, 0.0)
    negligible: float | None = None
    resolution: float = 0.0
    shape: bool = False

    def strength(self, value):
        """Size of the effect at a value: distance from the neutral value (its inverse for a
        stiffness, whose neutral value is infinite)."""
        value = np.asarray(value, float)
        return 1.0 / value if np.isinf(self.neutral) else np.abs(value - self.neutral)

    def value_at(self, strength: float, sign: float = 1.0) -> float:
        """The parameter value of an effect of a given size (and sign, where it has one)."""
        if np.isinf(self.neutral):
            return 1.0 / strength
        return float(self.neutral + sign * strength)

    def initial(self) -> float:
        """Start value: the given one, else the geometric (log) or arithmetic middle."""
        if self.start is not None:
            return self.start
        return float(np.sqrt(self.low * self.high)) if self.log else 0.5 * (self.low + self.high)


@dataclass(frozen=True)
class Effect:
    """One registry entry: a physical effect and its forward transformation of a prediction.

    ``transform(state, values, data)`` returns the state (a dict of arrays) with the effect
    applied; ``values`` holds every parameter of the candidate. ``observables`` says where it
    shows; ``requires`` names effects it only makes sense on top of. A discovered term (an entry
    of a problem's ``terms``) with ``early`` set changes the model's constants rather than its
    output, so its transformation applies before the registry's. ``alternatives``: rows or
    relaxations (term keys) of the group's table that would read in the data as this entry does.
    ``any_size``: the data earn the entry where any one of its sizing parameters is earned (one
    shift per trial of a constant that moved: the trials that did not move keep the session's).
    """

    name: str
    description: str
    parameters: tuple[Parameter, ...]
    observables: tuple[str, ...]
    transform: Callable[[dict, Mapping[str, float], Data], dict]
    requires: tuple[str, ...] = ()
    early: bool = False
    alternatives: tuple[str, ...] = ()
    any_size: bool = False


@dataclass(frozen=True)
class Data:
    """Observations of one group: every array's first axis is a unit (stride or step)."""

    arrays: Mapping[str, np.ndarray]
    trial: np.ndarray
    order: np.ndarray
    constants: Mapping[str, object] = field(default_factory=dict)

    @property
    def units(self) -> int:
        return int(self.trial.size)

    def take(self, rows: np.ndarray) -> Data:
        """The observations of a subset of units (in the given order; rows may repeat)."""
        return Data(
            {k: v[rows] for k, v in self.arrays.items()},
            self.trial[rows],
            self.order[rows],
            self.constants,
        )


@dataclass(frozen=True)
class Constant:
    """A constant of the rig that must hold between trials: the table's row (key, in words),
    the registry effect or library term whose parameter sizes it, that parameter, the smallest
    departure that counts (on the parameter's fit scale: relative for a log-scale parameter)
    and whether it exists only where the model holds its effect (a compliance; an offset is
    tested from its neutral value where the model lacks it); ``alike``: the rows or relaxations
    (term keys) whose violation reads as this constant's change."""

    row: str
    name: str
    effect: str
    parameter: str
    floor: float
    needs_effect: bool
    alike: tuple[str, ...] = ()


@dataclass(frozen=True)
class Problem:
    """What a rule group supplies to the engine.

    - ``registry``: effects in the order their transformations apply;
    - ``baseline(data)``: the state of the baseline model (must hold every observable);
    - ``measured``: observable -> name of its measured array in ``data.arrays``; an array named
      ``mask_<observable>`` (bool), where present, selects the samples that count;
    - ``scales``: observable -> noise scale (its unit) that normalises residuals;
    - ``features(data)``: observable -> {name: array shaped like it}, what the residual-structure
      tests bin its residuals by;
    - ``noise(data)``: observable -> (noise-only residuals, their features), the null;
    - ``units``: observable -> unit string; ``names``: observable -> its name in words;
      ``baseline_name``: the baseline as one noun phrase (no article; the report's sentences
      open with "The <baseline_name>");
    - ``recorded(state, data)``: the observables as the recording and its processing make them
      of the predicted state (e.g. the analysis chain's filter), after every transformation;
    - ``relative``: observables measured as changes since the first counted sample (their
      noise-only windows are referenced the same way);
    - ``exact``: observables the recording determines without noise (a controller's own
      output), their scale the recording's resolution: no noise-only null, their held-out RMS
      is tested against the goodness-of-fit floor, and they do not enter the model-form ratio B;
    - ``terms``: the library of correction terms built from what the recording holds, without a
      physical story (a channel's gain, offset or drift, a scale on a nominal rig constant, a
      rate term of a joint): searched only when the registry leaves structure unexplained, and
      reported as hypotheses for the lab to check;
    - ``trend(data)``: each unit's time in its trial, along which the residuals are tested for
      a slow drift (a sensor drifting over the trial looks like an offset within each unit);
    - ``sized_by``: observable -> the observable whose spread sizes its structure (a window
      where a quantity should be constant is sized by the window where it varies);
    - ``located``: registry effects a check of the recordings finds before any fit (a count
      drop the QC located, which the effect only sizes): beside unexplained structure they are
      claimed as the structural effects are, when their estimates hold;
    - ``constants``: the constants of the rig that must hold between trials
      (:class:`Constant`, from the assumption table's ``between``
      rows), each estimated per trial by the parameter stability;
    - ``trials(data)``: each unit's trial, where ``data.trial`` splits one (the segments
      between an encoder's count drops): what the parameter stability compares;
    - ``per_unit``: the linear registry parameters the forward model also takes as one value
      per unit (an array shaped (units, 1)), each set by its effect's transformation (a later
      call replaces it): a constant the stability finds moved is refitted per trial where its
      parameter is one of them (:mod:`.between`).
    """

    group: str
    registry: Mapping[str, Effect]
    baseline: Callable[[Data], dict]
    measured: Mapping[str, str]
    units: Mapping[str, str]
    baseline_name: str
    features: Callable[[Data], dict] | None = None
    noise: Callable[[Data], dict] | None = None
    recorded: Callable[[dict, Data], dict] | None = None
    relative: tuple[str, ...] = ()
    exact: tuple[str, ...] = ()
    terms: Mapping[str, Effect] = field(default_factory=dict)
    names: Mapping[str, str] = field(default_factory=dict)
    trend: Callable[[Data], np.ndarray] | None = None
    sized_by: Mapping[str, str] = field(default_factory=dict)
    located: tuple[str, ...] = ()
    constants: tuple[Constant, ...] = ()
    trials: Callable[[Data], np.ndarray] | None = None
    per_unit: tuple[str, ...] = ()

    @cached_property
    def entries(self) -> dict[str, Effect]:
        """Registry effects and discovered terms in the order their transformations apply: the
        early terms, the registry, the other terms."""
        early = {n: e for n, e in self.terms.items() if e.early}
        late = {n: e for n, e in self.terms.items() if not e.early}
        return {**early, **self.registry, **late}


@dataclass(frozen=True)
class Settings:
    """Engine settings: folds, bootstrap draws, seed, the most effects a model may add (and the
    most discovered terms), the goodness-of-fit floor (held-out RMS residual in noise units) and
    the structure test's false-alarm level; the terms the linear screen passes on
    (``screen_terms``) and how alike two terms' linearised effects must be (their cosine) to be
    weighed as alternatives (``alike``); the share of the held-out error a term must remove to be
    offered as a hypothesis while structure remains (``propose_share``) and to stay in a model
    at all (``min_gain``); the parameter stability's false-alarm level over the constants it
    tests (``stability_alpha``) and the fewest units a trial needs to be compared
    (``stability_min_units``); the half-width of a located effect's interval in resolution
    steps (``located_steps``, :func:`beside.located_sizes`); ``workers`` processes share
    independent fits (same results for any number)."""

    folds: int = 5
    bootstrap: int = 200
    seed: int = 0
    max_effects: int = 4
    screen: int = 3
    fit_floor: float = 3.0
    min_share: float = 0.02
    alpha: float = 0.01
    null_draws: int = 400
    min_units_cv: int = 10
    max_terms: int = 3
    screen_terms: int = 10
    alike: float = 0.8
    propose_share: float = 0.8
    min_gain: float = 0.05
    stability_alpha: float = 0.01
    stability_min_units: int = 4
    located_steps: float = 2.0
    workers: int = 1

    @classmethod
    def from_config(cls, block: Mapping, seed: int) -> Settings:
        """Settings from a config block (keys as the fields), with the workflow seed."""
        known = {k: block[k] for k in cls.__dataclass_fields__ if k in block and k != "seed"}
        return cls(seed=int(seed), **known)


def trial_labels(problem: Problem, data: Data) -> np.ndarray:
    """Each unit's trial as the trials are compared: ``problem.trials(data)``, else
    ``data.trial``."""
    return np.asarray(problem.trials(data) if problem.trials else data.trial)


def parameters(problem: Problem, effects: Sequence[str]) -> list[Parameter]:
    """Every parameter of a candidate, in the order of transformation."""
    return [p for name in ordered(problem, effects) for p in problem.entries[name].parameters]


def ordered(problem: Problem, effects: Sequence[str]) -> list[str]:
    """The effects (and terms) of a candidate in their order of transformation."""
    return [name for name in problem.entries if name in effects]


def predict(problem: Problem, data: Data, effects: Sequence[str], values) -> dict:
    """Observables of a candidate: the baseline state transformed by each effect in turn."""
    state = problem.baseline(data)
    for name in ordered(problem, effects):
        state = problem.entries[name].transform(state, values, data)
    if problem.recorded:
        return problem.recorded(state, data)
    return {o: state[o] for o in problem.measured}


# The residual, in noise scales, of a sample a candidate cannot predict (its law undefined there,
# e.g. a stiffness driven below zero): far off, so that no fit settles there.
UNDEFINED = 1e3


def residuals(problem: Problem, data: Data, effects, values, scales) -> dict[str, np.ndarray]:
    """Prediction − measurement of every observable in noise units, NaN where masked out,
    ``UNDEFINED`` where the candidate predicts no number."""
    pred = predict(problem, data, effects, values)
    out = {}
    for obs, name in problem.measured.items():
        with np.errstate(invalid="ignore"):
            r = (pred[obs] - data.arrays[name]) / scales[obs]
        predicted = np.isfinite(pred[obs])
        if not predicted.all():
            r = np.where(predicted | ~np.isfinite(data.arrays[name]), r, UNDEFINED)
        mask = data.arrays.get(f"mask_{obs}")
        out[obs] = np.where(mask, r, np.nan) if mask is not None else r
    return out


def unit_loss(res: Mapping[str, np.ndarray]) -> np.ndarray:
    """Per-unit loss: mean over observables of each one's mean squared normalised residual."""
    per = []
    for r in res.values():
        flat = r.reshape(r.shape[0], -1)
        per.append(np.nanmean(flat**2, axis=1) if flat.shape[1] else np.zeros(flat.shape[0]))
    return np.nanmean(np.vstack(per), axis=0)


def observable_weight(counted):
    """Weight 1/n of an observable's squared residuals, n its counted samples (at least 1): every
    observable counts equally in the least-squares loss."""
    return 1.0 / np.maximum(counted, 1.0)
