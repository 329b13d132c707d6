"""The Gymnasium environments against Gymnasium's and Stable-Baselines3's
own checkers, against themselves (a seed reproduces an episode; the native
vector env equals its copies stepped one by one) and against bad input."""
import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import endovascular_sim as evs  # registers the ids
from endovascular_sim.envs.navigation import NavigationEnv
from endovascular_sim.envs.registration import ARCH_VARIETY, ENVIRONMENTS

IDS = sorted(ENVIRONMENTS) + [ARCH_VARIETY]
SHORT = dict(control_interval=0.012)  # CathSim's interval: short episodes for the checkers


def make(env_id, **kwargs):
    if env_id.endswith("/Navigation-v0"):
        kwargs.setdefault("scene", "arch_navigation")
    return gymnasium.make(env_id, **{**SHORT, **kwargs})


@pytest.mark.filterwarnings("ignore:.*Box observation space (minimum|maximum) value is")
@pytest.mark.parametrize("env_id", IDS)
def test_gymnasium_check_env_passes(env_id):
    check_env(make(env_id).unwrapped, skip_render_check=False)


@pytest.mark.filterwarnings("ignore:.*Box observation space (minimum|maximum) value is")
@pytest.mark.parametrize("options", [dict(observation="2d"), dict(pixels=True, image_size=64),
                                     dict(render_mode="rgb_array", image_size=64)])
def test_check_env_passes_with_each_observation(options):
    check_env(make("endovascular_sim/ArchNavigation-v0", **options).unwrapped)


def test_stable_baselines3_check_env_passes():
    from stable_baselines3.common.env_checker import check_env as sb3_check_env
    sb3_check_env(make("endovascular_sim/ArchNavigation-v0").unwrapped, warn=True)


def episode(env, seed, actions):
    observations, rewards = [], []
    obs, info = env.reset(seed=seed)
    observations.append(obs)
    for a in actions:
        obs, r, terminated, truncated, info = env.step(a)
        observations.append(obs)
        rewards.append(r)
        if terminated or truncated:
            break
    return np.array(observations), np.array(rewards), info


def test_a_seed_reproduces_an_episode():
    actions = np.random.default_rng(3).uniform(-0.5, 1.0, (12, 4)).astype(np.float32)
    first = episode(make("endovascular_sim/ArchNavigation-v0"), 11, actions)
    again = episode(make("endovascular_sim/ArchNavigation-v0"), 11, actions)
    assert np.array_equal(first[0], again[0]) and np.array_equal(first[1], again[1])
    assert first[2] == again[2]
    targets = {make("endovascular_sim/ArchNavigation-v0").reset(seed=s)[1]["target"]
               for s in range(12)}
    assert len(targets) > 1  # the seed draws the target


def test_the_native_vector_env_equals_its_copies_stepped_one_by_one():
    n, steps = 3, 8
    vec = gymnasium.make_vec("endovascular_sim/ArchNavigation-v0", num_envs=n, nthread=2, **SHORT)
    assert type(vec).__name__ == "NavigationVectorEnv"
    singles = [make("endovascular_sim/ArchNavigation-v0") for _ in range(n)]
    obs, infos = vec.reset(seed=5)
    for i, env in enumerate(singles):
        o, info = env.reset(seed=5 + i)
        assert np.array_equal(obs[i], o) and infos["target"][i] == info["target"]
    rng = np.random.default_rng(0)
    for _ in range(steps):
        actions = rng.uniform(-1, 1, (n, 4)).astype(np.float32)
        obs, rewards, terminated, truncated, infos = vec.step(actions)
        for i, env in enumerate(singles):
            o, r, te, tr, info = env.step(actions[i])
            assert np.array_equal(obs[i], o) and rewards[i] == r
            assert (terminated[i], truncated[i]) == (te, tr)
            assert infos["peak_wall_force"][i] == info["peak_wall_force"]


def test_the_async_vector_env_of_gymnasium_runs_it():
    vec = gymnasium.vector.AsyncVectorEnv(
        [lambda: make("endovascular_sim/ArchNavigation-v0") for _ in range(2)])
    try:
        obs, info = vec.reset(seed=1)
        assert obs.shape == (2,) + vec.single_observation_space.shape
        obs, rewards, terminated, truncated, info = vec.step(vec.action_space.sample())
        assert np.all(np.isfinite(obs)) and rewards.shape == (2,)
    finally:
        vec.close()


def test_reaching_the_target_terminates_with_the_benchmark_metrics():
    env = NavigationEnv(target="left_subclavian", **SHORT)
    env.reset(seed=0)
    # The autopilot drives; the env judges: its metrics, from the same state.
    pilot = evs.Autopilot(env.model, env.data, "left_subclavian")
    terminated = False
    for _ in range(8000):
        pilot.control(env.model, env.data)
        evs.step(env.model, env.data)
        pilot.observe(env.data)
        if env.remaining_path() == 0.0:
            terminated = True
            break
    assert terminated
    env.episode.update({"max_wall_force": 0.0, "peak_drive_force": np.zeros(2), "failed": False})
    info = env.episode.info()
    assert env.episode.terminated and info["success"] and info["path_ratio"] == 1.0
    assert info["tip_vessel"] == "left_subclavian"


def test_bad_input_names_what_is_wrong_and_what_exists():
    with pytest.raises(TypeError, match="unknown option.*frame_skip.*its options are scene"):
        make("endovascular_sim/ArchNavigation-v0", frame_skip=4)
    env = make("endovascular_sim/ArchNavigation-v0")
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"shape \(3,\): expected \(4,\)"):
        env.step(np.zeros(3, np.float32))
    with pytest.raises(ValueError, match="not finite"):
        env.step(np.array([0, np.nan, 0, 0], np.float32))
    with pytest.raises(ValueError, match="its targets: left_common_carotid"):
        env.reset(options={"target": "left_femoral"})
    with pytest.raises(ValueError, match="unknown reset options"):
        env.reset(options={"targt": "left_subclavian"})
    with pytest.raises(ValueError, match="no named vessels"):
        make("endovascular_sim/Navigation-v0", scene="free_insertion")
    with pytest.raises(ValueError, match="lists no target vessels.*its vessels: ascending_aorta"):
        make("endovascular_sim/Navigation-v0", scene="carotid")
    with pytest.raises(ValueError, match="control_interval"):
        make("endovascular_sim/ArchNavigation-v0", control_interval=1e-6)
    with pytest.raises(evs.LoadError, match="no such scene"):
        make("endovascular_sim/Navigation-v0", scene="no_such_scene")
    obs, *_ = env.step(np.zeros(4, np.float32))  # and it steps on
    assert np.all(np.isfinite(obs))


def test_arch_variety_draws_a_reproducible_arch_per_episode(tmp_path):
    env = make(ARCH_VARIETY, folder=str(tmp_path)).unwrapped
    first, info = env.reset(seed=11)
    arches = {info["arch"]}
    for _ in range(3):
        arches.add(env.reset()[1]["arch"])
    assert len(arches) > 1  # a new arch per episode
    again, info_again = env.reset(seed=11)
    assert info_again["arch"] == info["arch"]
    assert np.array_equal(first, again)
    # The files of one arch at a time stay.
    assert len(list(tmp_path.glob("*.vtp"))) == 1
