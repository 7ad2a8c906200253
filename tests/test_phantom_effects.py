"""The phantom model's series chain: its laws hold sample by sample, its steps converge, its
geometry holds, and it agrees with the independent twin."""

from __future__ import annotations

import numpy as np
import pytest

from exobench import selection
from exobench.phantom.chain.filtering import butterworth_zero_phase
from exobench.phantom.model import discrepancy, effects
from exobench.phantom.rig import Rig


def window_data(units: int = 4, samples: int = 120, dt: float = 0.005) -> selection.Data:
    t = (np.arange(samples) - 20) * dt
    rng = np.random.default_rng(5)
    theta = 0.2 + np.outer(rng.uniform(0.1, 0.2, units), np.sin(np.pi * np.clip(t, 0, None) / 0.5))
    springs = np.array([3400.0, 9200.0, 13600.0, 21700.0])[:units]
    arrays = {
        "phantom_rad": theta,
        "swing_phantom_rad": np.zeros((units, 10)),
        "k_spring_N_per_m": springs,
        "pretension_N": np.full(units, 3.0),
        "time_s": 30.0 * np.arange(units)[:, None] + t[None, :],
    }
    constants = {"t_s": t, "dt_s": dt, "rig": Rig(), "zero": 20,
                 "thigh_m": Rig().thigh_length_m, "shank_m": Rig().shank_length_m}  # fmt: skip
    return selection.Data(arrays, np.zeros(units, int), np.arange(units), constants)


def chain_of(**values):
    state = effects.baseline(window_data())
    return {**state["chain"], **values}


def solution(data, **values):
    """The chain's moment, deflections and the spring side's driving moment, engaged at 0."""
    u, engaged = effects.engagement_rotation(data.arrays["phantom_rad"], data.constants["t_s"], 0.0)
    return effects.chain_solution(u, engaged, data, chain_of(**values)), u, engaged


def test_elastic_elements_in_series_share_one_moment():
    # M = u / (1/k_i + 1/k_f + 1/k_θ) while the spring is taut (seed 000 eq. 2.2 in series)
    data = window_data()
    (moment, delta, frame, side, _), u, engaged = solution(
        data, k_interface_Nm_per_rad=60.0, k_frame_Nm_per_rad=900.0)  # fmt: skip
    k_theta = Rig().joint_stiffness(data.arrays["k_spring_N_per_m"])[:, None]
    taut = engaged & (u > 0.01)
    series = u / (1 / 60.0 + 1 / 900.0 + 1 / k_theta)
    np.testing.assert_allclose(moment[taut], series[taut], rtol=1e-9)
    np.testing.assert_allclose((delta + frame + side)[engaged], u[engaged], atol=1e-12)
    np.testing.assert_allclose(delta[taut], moment[taut] / 60.0, rtol=1e-9)


@pytest.mark.parametrize("where", ["spring side", "interface"])
def test_friction_holds_its_element_within_tau_and_slides_at_tau(where):
    data = window_data()
    tau = 0.6
    values = {"k_interface_Nm_per_rad": 60.0, "k_frame_Nm_per_rad": 900.0}
    values["friction_Nm" if where == "spring side" else "interface.friction_Nm"] = tau
    (moment, delta, _, side, _), _, engaged = solution(data, **values)
    k_theta = Rig().joint_stiffness(data.arrays["k_spring_N_per_m"])[:, None]
    position, elastic = (side, k_theta * side) if where == "spring side" else (delta, 60 * delta)
    taut = (engaged & (side > 0))[:, 2:]
    excess = (moment - elastic)[:, 2:][taut]
    step = np.diff(position, axis=1)
    # sliding through a whole step the same way as the step before (a step may stick part-way)
    moving = ((np.abs(step[:, 1:]) > 1e-12) & (step[:, 1:] * step[:, :-1] > 0))[taut]
    assert np.all(np.abs(excess) <= tau + 1e-9)
    np.testing.assert_allclose(np.abs(excess[moving]), tau, atol=1e-9)
    assert moving.mean() > 0.5 and (~moving).sum() > 0  # it slides and it sticks


def test_a_drifting_element_is_stiffer_in_later_strides():
    data = window_data()
    (moment, *_), _, _ = solution(data, k_interface_Nm_per_rad=60.0,
                                  **{"interface.drift_per_s": 0.01})  # fmt: skip
    (still, *_), _, _ = solution(data, k_interface_Nm_per_rad=60.0)
    gain = moment.max(axis=1) / still.max(axis=1)
    assert gain[0] == pytest.approx(1.0, abs=0.02)  # the first stride starts the trial
    assert np.all(np.diff(gain) > 0)


@pytest.mark.parametrize("where", ["interface", "frame"])
def test_damping_lags_the_element_by_its_kelvin_voigt_law(where):
    data = window_data()
    if where == "interface":
        values = {"k_interface_Nm_per_rad": 60.0, "c_interface_Nms_per_rad": 1.5}
    else:
        values = {"k_frame_Nm_per_rad": 60.0, "frame.c_frame_Nms_per_rad": 1.5}
    (moment, delta, frame, _, _), _, engaged = solution(data, **values)
    deflection = delta if where == "interface" else frame
    # Kelvin–Voigt: M − k·δ = c·δ̇ (checked with the trapezoid mean of the step)
    rate = np.diff(deflection, axis=1) / 0.005
    viscous = 0.5 * (moment - 60.0 * deflection)[:, 1:] + 0.5 * (moment - 60.0 * deflection)[:, :-1]
    on = engaged[0, 1:] & engaged[0, :-1]
    np.testing.assert_allclose(viscous[:, on], 1.5 * rate[:, on], atol=2e-3 * np.abs(moment).max())


def test_a_damped_spring_records_its_viscous_force():
    # F = F₀ + k·x + c·ẋ while taut: the force exceeds the elastic one while the spring stretches
    data = window_data()
    values = {"k_interface_Nm_per_rad": 60.0, "spring.c_spring_Ns_per_m": 60.0}
    state = effects.solve({**effects.baseline(data), "chain": chain_of(**values)}, data)
    (_, _, _, side, _), _, engaged = solution(data, **values)
    travel = Rig().spring_travel_m_per_rad
    elastic = 3.0 + data.arrays["k_spring_N_per_m"][:, None] * travel * side
    rate = np.gradient(travel * side, 0.005, axis=1)
    stretching = engaged & (rate > 0.05) & (side > 0)
    np.testing.assert_allclose((state["force"] - elastic)[stretching], 60.0 * rate[stretching],
                               rtol=0.1)  # fmt: skip


def test_an_extending_knee_slackens_the_spring_to_the_tensioner():
    data = window_data()
    data.arrays["phantom_rad"][:] = 0.5 - np.clip(data.constants["t_s"], 0.0, None)
    state = effects.solve({**effects.baseline(data), "chain": chain_of()}, data)
    late = data.constants["t_s"] > 0.2
    assert np.all(state["force"][:, late] == 0.0)
    assert np.all(np.abs(state["moment"][:, late]) < 3.0)  # tensioner, not k_θ·Δθ


def test_play_leaves_no_moment_until_the_slack_is_taken_up():
    data = window_data()
    state = effects.solve({**effects.baseline(data), "chain": chain_of(play_rad=0.05)}, data)
    u, _ = effects.engagement_rotation(data.arrays["phantom_rad"], data.constants["t_s"], 0.0)
    assert np.all(state["moment"][u <= 0.05] <= 1e-12)
    assert state["moment"][u > 0.06].min() > 0


def test_interface_play_leaves_the_bars_standing_until_half_the_play_is_taken_up():
    # the bars stand (the exoskeleton's angle holds) while the phantom turns p/2 from where the
    # engagement found them; beyond, the chain carries u − p/2 as it would carry u without play
    data = window_data()
    play = 0.04
    values = {"k_interface_Nm_per_rad": 60.0, "k_frame_Nm_per_rad": 900.0}
    state = effects.solve(
        {**effects.baseline(data), "chain": chain_of(**values, **{"interface.play_rad": play})},
        data,
    )
    u, engaged = effects.engagement_rotation(data.arrays["phantom_rad"], data.constants["t_s"], 0.0)
    slack = engaged & (u <= play / 2)
    assert slack.sum() > 0 and np.all(np.abs(state["moment"][slack]) <= 1e-12)
    theta = data.arrays["phantom_rad"]
    np.testing.assert_allclose((theta - state["exo"])[slack], u[slack], atol=1e-12)
    taken_up = theta - u + effects.dead_band(u, play / 2, play / 2)
    driven = selection.Data({**data.arrays, "phantom_rad": taken_up}, data.trial, data.order,
                            data.constants)  # fmt: skip
    without = effects.solve({**effects.baseline(driven), "chain": chain_of(**values)}, driven)
    # beyond, the chain carries what passes the slack, and the bars turn with it
    for obs in ("moment", "exo", "force"):
        np.testing.assert_allclose(state[obs], without[obs], atol=1e-12)


def test_units_engaged_at_their_own_instants_solve_as_each_alone():
    data = window_data()
    delays = np.array([0.0, 0.012, 0.031, 0.047])
    values = {"k_interface_Nm_per_rad": 60.0, "c_interface_Nms_per_rad": 0.6,
              "k_frame_Nm_per_rad": 900.0}  # fmt: skip
    state = effects.solve({**effects.baseline(data),
                           "chain": chain_of(**values, delay_s=delays)}, data)  # fmt: skip
    for unit, delay in enumerate(delays):
        alone = data.take(np.array([unit]))
        one = effects.solve({**effects.baseline(alone),
                             "chain": chain_of(**values, delay_s=float(delay))}, alone)  # fmt: skip
        for obs in ("moment", "exo", "spring", "force"):
            np.testing.assert_allclose(state[obs][unit], one[obs][0], rtol=1e-12, atol=1e-12)


def test_lags_add_up_and_a_lag_per_unit_is_each_units_own_lag():
    data = window_data()
    data.arrays.update({f"{w}{k}": np.random.default_rng(3).normal(size=(4, n))
                        for w, n in (("", 120), ("swing_", 10))
                        for k in ("ankle_force_N", "moment_per_ankle_force_m")})  # fmt: skip
    base = {**effects.baseline(data), "chain": chain_of(k_interface_Nm_per_rad=60.0)}
    once = effects.solved(effects.lagged(base, 0.03, data), data)
    twice = effects.solved(effects.lagged(effects.lagged(base, 0.01, data), 0.02, data), data)
    for key in ("moment", "exo", "spring", "force"):
        np.testing.assert_allclose(twice[key], once[key], atol=1e-9)
    for obs in ("moment", "swing"):
        np.testing.assert_allclose(twice["recorded_extra"][obs], once["recorded_extra"][obs],
                                   atol=1e-9)  # fmt: skip
    lags = np.array([0.0, 0.01, 0.02, 0.03])
    each = effects.solved(effects.lagged(base, lags, data), data)
    third = effects.solved(effects.lagged(base, 0.02, data), data)
    np.testing.assert_allclose(each["force"][2], third["force"][2], atol=1e-9)
    np.testing.assert_allclose(each["recorded_extra"]["moment"][2],
                               third["recorded_extra"]["moment"][2], atol=1e-12)  # fmt: skip


def test_knee_markers_on_the_joint_see_the_true_angle():
    theta = np.linspace(0.0, 1.2, 50)
    seen = effects.knee_marker_angle(theta, 0.0, 0.299, 0.304)
    np.testing.assert_allclose(seen, theta, atol=1e-12)
    assert np.all(np.diff(effects.knee_marker_angle(theta, 0.02, 0.299, 0.304)) > 0)


def test_filter_matrices_are_the_chains_filters():
    rng = np.random.default_rng(2)
    x = rng.normal(size=(3, 100))
    analog, markers = discrepancy.filter_matrices(100, 5, {"filter_cutoff_Hz": 6.0,
                                                            "filter_order": 4})  # fmt: skip
    np.testing.assert_allclose(x @ analog, butterworth_zero_phase(x.T, 200.0, 6.0, 4).T, atol=1e-12)
    frames = butterworth_zero_phase(x[:, ::2].T, 100.0, 6.0, 4).T
    np.testing.assert_allclose((x @ markers)[:, ::2], frames, atol=1e-9)


def test_every_entry_documents_a_detectable_range_inside_its_bounds():
    for name, effect in effects.REGISTRY.items():
        assert effect.observables and effect.description, name
        for p in effect.parameters:
            low, high = sorted(abs(v) for v in p.detectable)
            assert 0 < low < high, name
            assert p.low < p.value_at(float(min(p.strength(p.detectable))), 1.0) < p.high, name


@pytest.mark.parametrize(
    "hidden",
    [
        {"interface_compliance": {"k_interface_Nm_per_rad": 60.0},
         "frame_compliance": {"k_frame_Nm_per_rad": 900.0}},
        {"interface_compliance": {"k_interface_Nm_per_rad": 60.0},
         "interface_damping": {"c_interface_Nms_per_rad": 0.9},
         "frame_friction": {"friction_Nm": 0.8}},
        {"transmission_play": {"play_rad": 0.03}, "clutch_timing": {"delay_s": 0.04}},
    ],
)  # fmt: skip
def test_engine_predictions_agree_with_the_independent_twin(hidden):
    """The twin (time-domain bodies) and the engine (series predictions) share no mechanics code;
    driven by the twin's true phantom angle, the engine must give the twin's true moment."""
    from exobench.phantom.twin import twin
    from exobench.phantom.validation import recordings
    from phantom_helpers import mean_cycle, settings, workflow_config

    config = recordings.twin_config(workflow_config(), hidden, strides=4, seed=3)
    for block in ("marker_noise", "load_cell_noise", "occlusion"):
        config["phantom"]["twin"]["effects"][block]["enabled"] = False
    trials = twin.simulate_trials(mean_cycle(), Rig(), settings(config), {})
    step, samples = 5, 90  # 200 Hz, 0.45 s of engagement
    angle, moment, springs = [], [], []
    for trial in trials:
        truth = trial.truth
        for stride in range(1, 5):
            rows = truth[truth["stride"] == stride].iloc[: samples * step : step]
            angle.append(rows["phantom_knee_angle_rad"].to_numpy())
            moment.append(rows["knee_moment_Nm"].to_numpy())
            springs.append(trial.spring_stiffness_N_per_m)
    springs = np.asarray(springs)
    rig = Rig()
    data = selection.Data(
        {
            "phantom_rad": np.array(angle),
            "swing_phantom_rad": np.zeros((springs.size, 10)),
            "k_spring_N_per_m": springs,
            "pretension_N": np.full(springs.size, 3.0),
            "time_s": np.zeros((springs.size, samples)),
        },
        np.zeros(springs.size, int),
        np.arange(springs.size),
        {"t_s": np.arange(samples) * step / 1000.0, "dt_s": step / 1000.0, "rig": rig,
         "zero": 0},
    )  # fmt: skip
    values = {k: v for entry in hidden.values() for k, v in entry.items()}
    state = effects.baseline(data)
    for name in effects.REGISTRY:
        if name in hidden:
            state = effects.REGISTRY[name].transform(state, values, data)
    predicted = effects.solved(state, data)["moment"]
    truth = np.array(moment)
    error = np.sqrt(np.mean((predicted - truth) ** 2)) / np.abs(truth).max()
    print(f"RMS difference {error:.2%} of the peak moment")
    assert error < 0.02


@pytest.mark.parametrize("damping", [0.0, 0.8])
def test_a_progressive_spring_holds_the_moment_its_stretch_law_gives(damping):
    # F = F0 + k·x·(1 + a·x), x = r·(T/t)·s: along the chain the moment equals the spring side's
    # (taut, no friction), M = k_θ·s + k·a·(r·T/t)³·s², and the recorded force follows the law
    rng = np.random.default_rng(17)
    data = window_data()
    quadratic = float(rng.uniform(5.0, 30.0))
    chain = chain_of(k_interface_Nm_per_rad=60.0, k_frame_Nm_per_rad=900.0,
                     c_interface_Nms_per_rad=damping,
                     **{"spring.quadratic_per_m": quadratic})  # fmt: skip
    state = effects.solve({**effects.baseline(data), "chain": chain}, data)
    u, engaged = effects.engagement_rotation(data.arrays["phantom_rad"], data.constants["t_s"], 0.0)
    side = effects.chain_solution(u, engaged, data, chain)[3]
    rig = Rig()
    springs = data.arrays["k_spring_N_per_m"][:, None]
    travel = rig.spring_travel_m_per_rad
    taut = engaged & (side > 0.0)
    spring_moment = rig.joint_stiffness(springs) * side + springs * quadratic * travel**3 * side**2
    np.testing.assert_allclose(state["moment"][taut], spring_moment[taut], rtol=1e-6, atol=1e-6)
    stretch = travel * side
    force = 3.0 + springs * stretch * (1.0 + quadratic * stretch)
    np.testing.assert_allclose(state["force"][taut], force[taut], rtol=1e-9)
    linear = effects.solve(
        {**effects.baseline(data), "chain": {**chain, "spring.quadratic_per_m": 0.0}}, data
    )
    assert np.all(state["moment"].max(axis=1) > linear["moment"].max(axis=1))


def _sine_window(dt: float) -> selection.Data:
    """One stride's window sampled every dt: a smooth flexion from the programmed instant."""
    t = np.arange(round(-0.1 / dt), round(0.4 / dt) + 1) * dt
    theta = 0.3 + 0.15 * np.sin(np.pi * np.clip(t, 0.0, None) / 0.5)
    arrays = {"phantom_rad": theta[None, :], "swing_phantom_rad": np.zeros((1, 10)),
              "k_spring_N_per_m": np.array([9200.0]), "pretension_N": np.array([3.0])}  # fmt: skip
    constants = {"t_s": t, "dt_s": dt, "rig": Rig(), "thigh_m": Rig().thigh_length_m,
                 "shank_m": Rig().shank_length_m, "zero": int(np.argmin(np.abs(t)))}  # fmt: skip
    arrays["time_s"] = t[None, :]
    return selection.Data(arrays, np.zeros(1, int), np.arange(1), constants)


def _on_both_grids(values) -> list[tuple[np.ndarray, np.ndarray]]:
    """(time, moment) of the chain with ``values`` on the engine's 10 ms grid and on 1 ms."""
    out = []
    for dt in (0.01, 0.001):
        data = _sine_window(dt)
        state = effects.solve({**effects.baseline(data), "chain": chain_of(**values)}, data)
        out.append((data.constants["t_s"], state["moment"][0]))
    return out


@pytest.mark.parametrize("delay_s", [0.025, 0.043])
def test_a_late_clutch_between_samples_loads_a_damped_interface_from_its_instant(delay_s):
    """The damped chain on the engine's 10 ms grid equals the same chain on a 1 ms grid when
    the clutch locks between two coarse samples (the first step is the partial one)."""
    values = {"k_interface_Nm_per_rad": 60.0, "c_interface_Nms_per_rad": 0.6,
              "k_frame_Nm_per_rad": 1200.0, "delay_s": delay_s}  # fmt: skip
    (coarse_t, coarse), (fine_t, fine) = _on_both_grids(values)
    on = coarse_t > delay_s
    np.testing.assert_allclose(coarse[on], np.interp(coarse_t[on], fine_t, fine),
                               atol=2e-3 * np.abs(fine).max())  # fmt: skip


@pytest.mark.parametrize("where", ["stiffening_per_rad2", "frame.stiffening_per_rad2"])
def test_a_stiffening_damped_chain_converges_with_its_step(where):
    """Newton on the cubic law within each step: the 10 ms grid keeps to the 1 ms one."""
    values = {"k_interface_Nm_per_rad": 60.0, "c_interface_Nms_per_rad": 0.6,
              "k_frame_Nm_per_rad": 400.0, "frame.c_frame_Nms_per_rad": 4.0,
              where: 400.0 if where == "stiffening_per_rad2" else 4000.0}  # fmt: skip
    (coarse_t, coarse), (fine_t, fine) = _on_both_grids(values)
    on = coarse_t > 0.0
    np.testing.assert_allclose(coarse[on], np.interp(coarse_t[on], fine_t, fine),
                               atol=0.02 * np.abs(fine).max())  # fmt: skip
