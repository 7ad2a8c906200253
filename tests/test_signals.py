"""The chains' Butterworth filters against scipy.signal's (which the chains do not import)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from exobench import signals
from seeds import fixed


@pytest.mark.parametrize("order", [1, 2, 3, 4, 5, 8])
# a quarter of the rate puts an odd order's real pole at z = 0
@pytest.mark.parametrize("cutoff", [0.5, 6.0, 20.0, 150.0, 249.99, 250.0, 250.01, 450.0])
def test_the_design_has_scipys_response(order, cutoff):
    ours = signals.butterworth(order, cutoff, 1000.0)
    theirs = signal.butter(order, cutoff, fs=1000.0, output="sos")
    assert ours.shape == theirs.shape
    np.testing.assert_allclose(ours[:, 3], 1.0)
    _, expected = signal.sosfreqz(theirs, 256, fs=1000.0)
    _, got = signal.sosfreqz(ours, 256, fs=1000.0)
    np.testing.assert_allclose(got, expected, atol=1e-10)


@pytest.mark.parametrize("cutoff", [0.0, -1.0, 500.0, 700.0])
def test_a_cutoff_outside_the_band_is_refused(cutoff):
    with pytest.raises(ValueError, match="cut-off"):
        signals.butterworth(2, cutoff, 1000.0)


@pytest.mark.parametrize("order", [1, 2, 3, 4, 5, 6])
@pytest.mark.parametrize("share", [0.03, 0.25, 0.45])  # of the rate
def test_zero_phase_is_sosfiltfilt(order, share):
    rng = np.random.default_rng(fixed("zero phase"))
    x = np.cumsum(rng.normal(size=(2000, 3)), axis=0) + rng.normal(0.0, 5.0, 3)
    sos = signals.butterworth(order, share * 100.0, 100.0)
    theirs = signal.butter(order, share * 100.0, fs=100.0, output="sos")
    expected = signal.sosfiltfilt(theirs, x, axis=0)
    got = signals.zero_phase(sos, x)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-10 * np.abs(expected).max())
    np.testing.assert_allclose(signals.zero_phase(sos, x[:, 0]), got[:, 0], atol=1e-12)
    # scipy's own sections (the gain in the first): each later one settles on the level it gets
    np.testing.assert_allclose(signals.zero_phase(theirs, x), expected, rtol=0,
                               atol=1e-10 * np.abs(expected).max())  # fmt: skip
    # the shortest signal scipy filters, and one sample less
    pad = 3 * (2 * len(sos) + 1 - min((sos[:, 2] == 0).sum(), (sos[:, 5] == 0).sum()))
    shortest = x[: pad + 1]
    np.testing.assert_allclose(signals.zero_phase(sos, shortest),
                               signal.sosfiltfilt(theirs, shortest, axis=0), atol=1e-9)  # fmt: skip
    with pytest.raises(ValueError, match="zero-phase"):
        signals.zero_phase(sos, x[:pad])


def test_causal_sections_are_lfilter_from_rest_or_settled():
    rng = np.random.default_rng(fixed("causal"))
    x = np.cumsum(rng.normal(size=(1500, 4)), axis=0)
    sos = signals.butterworth(2, 20.0, 1000.0)
    b, a = signal.butter(2, 20.0, fs=1000.0)
    from_rest = signal.lfilter(b, a, x, axis=0)
    np.testing.assert_allclose(signals.cascade(sos, x), from_rest, atol=1e-10)
    settled = signal.lfilter(b, a, x, axis=0, zi=np.outer(signal.lfilter_zi(b, a), x[0]))[0]
    np.testing.assert_allclose(signals.cascade(sos, x, x[0]), settled, atol=1e-10)
    np.testing.assert_allclose(signals.settled_state(sos[0]), signal.lfilter_zi(b, a), atol=1e-14)
    # a constant passes a settled low-pass unchanged
    np.testing.assert_allclose(signals.cascade(sos, np.full(50, 2.5), 2.5), 2.5, rtol=1e-12)
