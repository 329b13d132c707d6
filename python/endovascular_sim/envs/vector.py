"""A native vector environment: N copies of a navigation environment whose
steps run together in the core's thread pool (``endovascular_sim.rollout``),
with the GIL released, as ``gymnasium.make_vec(id, num_envs=N)`` makes it.

It autoresets as Gymnasium's own vector environments do (next step): the
step after a copy's episode ended resets that copy, ignoring its action.
"""
import os

import gymnasium
import numpy as np
from gymnasium.vector.utils import batch_space, concatenate, create_empty_array

import endovascular_sim as evs
from endovascular_sim.envs.navigation import NavigationEnv


class NavigationVectorEnv(gymnasium.vector.VectorEnv):
    """``num_envs`` NavigationEnv copies of one scene (its model shared),
    stepped on ``nthread`` threads (default: the machine's cores, at most
    num_envs). Other arguments: NavigationEnv's."""

    def __init__(self, num_envs=2, nthread=None, **kwargs):
        if num_envs < 1:
            raise ValueError("num_envs must be at least 1")
        first = NavigationEnv(**kwargs)
        kwargs.pop("model", None)
        self.envs = [first] + [NavigationEnv(model=first.model, **kwargs)
                               for _ in range(num_envs - 1)]
        self.num_envs = num_envs
        self.nthread = nthread or min(num_envs, os.cpu_count() or 1)
        self.metadata = dict(first.metadata, autoreset_mode="NextStep")
        self.render_mode = first.render_mode
        self.single_observation_space = first.observation_space
        self.single_action_space = first.action_space
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self._observations = create_empty_array(self.single_observation_space, num_envs)
        self._autoreset = np.zeros(num_envs, dtype=np.bool_)

    def reset(self, *, seed=None, options=None):
        seeds = seed if isinstance(seed, (list, tuple)) else (
            [None] * self.num_envs if seed is None else [seed + i for i in range(self.num_envs)])
        observations, infos = [], {}
        for i, env in enumerate(self.envs):
            obs, info = env.reset(seed=seeds[i], options=options)
            observations.append(obs)
            infos = self._add_info(infos, info, i)
        self._autoreset[:] = False
        self._observations = concatenate(self.single_observation_space, observations,
                                         self._observations)
        return self._observations, infos

    def step(self, actions):
        actions = np.asarray(actions)
        if actions.shape != self.action_space.shape:
            raise ValueError(f"actions of shape {actions.shape}: expected {self.action_space.shape}")
        stepping = [i for i in range(self.num_envs) if not self._autoreset[i]]
        outcome = None
        if stepping:
            commands = np.concatenate([self.envs[i].commands_of(actions[i]) for i in stepping])
            outcome = evs.rollout(self.envs[0].model, [self.envs[i].data for i in stepping],
                                  commands, self.envs[0].steps_per_action, self.nthread)
        rewards = np.zeros(self.num_envs)
        terminated = np.zeros(self.num_envs, dtype=np.bool_)
        truncated = np.zeros(self.num_envs, dtype=np.bool_)
        observations, infos = [], {}
        for i, env in enumerate(self.envs):
            if self._autoreset[i]:
                obs, info = env.reset()
            else:
                k = stepping.index(i)
                obs, rewards[i], terminated[i], truncated[i], info = env.after_step(
                    {key: value[k, -1] for key, value in outcome.items()})
            observations.append(obs)
            infos = self._add_info(infos, info, i)
        self._autoreset = np.logical_or(terminated, truncated)
        self._observations = concatenate(self.single_observation_space, observations,
                                         self._observations)
        return self._observations, rewards, terminated, truncated, infos

    def render(self):
        return tuple(env.render() for env in self.envs)
