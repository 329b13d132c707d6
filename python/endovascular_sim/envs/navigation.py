"""Navigation to a target vessel as a Gymnasium environment.

One episode: the scene's devices from their initial placement (a wire in a
catheter in the descending aorta for ``ArchNavigation-v0``), a target
vessel drawn per episode among the scene's targets (or fixed by the
``target`` argument or ``reset(options={"target": ...})``), the agent
driving each device's insertion and rotation velocity, one action per
control interval (default a fluoroscopy frame, 1/7.5 s, as stEVE steps).

Its parts are small and replaceable, as stEVE composes its environments:
the observation (``observation.TrackedPoints``), the reward
(``reward.PathProgress``), and the episode's end and metrics
(``episode.Episode``). docs/python.md documents every default.
"""
import math

import gymnasium
import numpy as np

import endovascular_sim as evs
from endovascular_sim.envs.episode import Episode
from endovascular_sim.envs.observation import TrackedPoints
from endovascular_sim.envs.registration import CONTROL_INTERVAL_FLUOROSCOPY
from endovascular_sim.envs.reward import PathProgress
from endovascular_sim.envs.scene_options import load_env_scene


OPTIONS = ("scene", "target", "targets", "device", "control_interval", "time_step", "time_limit",
           "observation", "pixels", "image_size", "reward", "safe_force", "reset_rotation",
           "nthread", "render_mode", "model")


class NavigationEnv(gymnasium.Env):
    """Drive a scene's devices to a target vessel.

    Args:
        scene: a shipped scene's name or a scene file (its vessels must be
            named and it must list targets, or ``targets`` must be given).
        target: a vessel name for every episode (None: drawn per episode).
        targets: the vessel names to draw from (None: the scene's targets),
            or a function of the model and the lead device's index that
            returns them (``targets.branch_targets``).
        device: the device whose tip must reach the target (None: the one
            the scene's targets name, else the innermost device).
        control_interval: [s] simulated per action.
        time_step: [s] of the physics (None: the scene's).
        time_limit: [s] simulated per episode before truncation.
        observation: "3d" (points in the scene frame [m], scaled) or "2d"
            (their pixels on the X-ray detector, scaled).
        pixels: also observe the X-ray image (a Dict observation).
        image_size: pixels per side of that image.
        reward: an object with ``reset(env)`` and ``__call__(env, outcome)``
            (default ``PathProgress()``).
        safe_force: [N] a success is safe when no wall force exceeded it.
        reset_rotation: [rad] each episode starts with every device turned
            by an angle drawn in [-reset_rotation, reset_rotation] (the
            drives turn them before the episode's clock starts), as a hand
            picks a device up at any angle; 0: the scene's placement.
        nthread: threads of the rollout a step runs (1: this one).
        render_mode: None or "rgb_array" (the X-ray image).
        model: a loaded SceneModel to share (then ``scene`` and ``time_step``
            are not read).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 7.5}

    def __init__(self, scene="arch_navigation", target=None, targets=None, device=None,
                 control_interval=CONTROL_INTERVAL_FLUOROSCOPY, time_step=None, time_limit=30.0,
                 observation="3d", pixels=False, image_size=128, reward=None, safe_force=1.0,
                 reset_rotation=0.0, nthread=1, render_mode=None, model=None, **unknown):
        if unknown:
            raise TypeError(f"unknown option(s) {', '.join(sorted(unknown))} of NavigationEnv: "
                            f"its options are {', '.join(OPTIONS)}")
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode {render_mode!r}: use None or 'rgb_array'")
        self.model = model if model is not None else load_env_scene(scene, time_step)
        self.lead = _lead_device(self.model, device)
        if callable(targets):
            targets = targets(self.model, self.lead)
        self.targets = _targets_of(self.model, targets, target)
        self.fixed_target = target
        if not (control_interval >= self.model.time_step and math.isfinite(control_interval)):
            raise ValueError(f"control_interval {control_interval!r} s must be at least the "
                             f"time step ({self.model.time_step} s)")
        self.steps_per_action = max(1, round(control_interval / self.model.time_step))
        self.control_interval = self.steps_per_action * self.model.time_step
        if not (time_limit > 0.0 and math.isfinite(time_limit)):
            raise ValueError(f"time_limit {time_limit!r} s must be positive")
        self.time_limit = time_limit
        if nthread < 1:
            raise ValueError("nthread must be at least 1")
        self.nthread = nthread
        self.render_mode = render_mode
        if not (0.0 <= reset_rotation <= math.pi):
            raise ValueError(f"reset_rotation {reset_rotation!r} rad must lie in [0, pi]")
        self.reset_rotation = reset_rotation
        self.data = evs.make_data(self.model)
        self.limits = np.array([[d["max_insertion_speed"], d["max_rotation_speed"]]
                                for d in self.model.devices]).ravel()
        n = len(self.model.devices)
        self.action_space = gymnasium.spaces.Box(-1.0, 1.0, (2 * n,), np.float32)
        self.xray = None
        if pixels or observation == "2d" or render_mode == "rgb_array":
            self.xray = evs.XrayRenderer(self.model, pixels=image_size)
        self.observer = TrackedPoints(self, observation, pixels)
        self.observation_space = self.observer.space
        self.reward = reward if reward is not None else PathProgress()
        self.episode = Episode(self, safe_force)
        self.target = self.targets[0]
        self.last_action = np.zeros(2 * n, np.float32)

    # -- the Gymnasium API ---------------------------------------------------
    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        options = dict(options or {})
        target = options.pop("target", None)
        if options:
            raise ValueError(f"unknown reset options {sorted(options)}: the one option is 'target'")
        if target is None:
            target = self.fixed_target or self.targets[self.np_random.integers(len(self.targets))]
        elif target not in self.model.vessel_names:
            raise ValueError(f"target {target!r} is not a vessel of scene '{self.model.name}' "
                             f"(its targets: {listed(self.targets)})")
        self.target = target
        evs.reset_data(self.model, self.data)
        if self.reset_rotation > 0.0:
            self._turn_devices()
        self.last_action[:] = 0.0
        self.episode.reset()
        self.reward.reset(self)
        return self.observer(), self.episode.info()

    def step(self, action):
        commands = self.commands_of(action)
        out = evs.rollout(self.model, [self.data], commands, self.steps_per_action, self.nthread)
        return self.after_step({k: v[0, -1] for k, v in out.items()})

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        return np.repeat(self.xray.render(self.data)[:, :, None], 3, axis=2)

    def _turn_devices(self):
        """Turns every device by a random angle, by its drive (position mode),
        then holds it (velocity 0)."""
        angles = self.np_random.uniform(-self.reset_rotation, self.reset_rotation,
                                        len(self.model.devices))
        for d, angle in enumerate(angles):
            inserted = self.data.devices[d].inserted_length
            evs.set_command(self.model, self.data, d, inserted, float(angle), mode="position")
        fastest = min(d["max_rotation_speed"] for d in self.model.devices)
        evs.step(self.model, self.data, int(math.ceil(self.reset_rotation / fastest
                                                      / self.model.time_step)) + 1)
        for d in range(len(self.model.devices)):
            evs.set_command(self.model, self.data, d, 0.0, 0.0)

    # -- the parts a vector environment shares --------------------------------
    def commands_of(self, action):
        """The (1 x 1 x 2·devices) velocity commands of an action in [-1, 1]."""
        a = np.asarray(action, dtype=np.float64)
        if a.shape != self.action_space.shape:
            raise ValueError(f"action of shape {a.shape}: expected {self.action_space.shape} "
                             f"(per device of {self.model.device_names}: insertion, rotation)")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"action {a.tolist()} is not finite")
        a = np.clip(a, -1.0, 1.0)
        self.last_action[:] = a
        return (a * self.limits)[None, None, :]

    def after_step(self, outcome):
        """Observation, reward, terminated, truncated and info after a rollout's
        last record (``outcome``: the rollout's arrays at this environment's
        index and its last command)."""
        self.episode.update(outcome)
        reward = float(self.reward(self, outcome))
        return (self.observer(), reward, self.episode.terminated, self.episode.truncated,
                self.episode.info())

    def remaining_path(self):
        """[m] along the centrelines from the lead tip to the target's depth."""
        return evs.remaining_path(self.model, self.data, self.lead, self.target,
                                  self.episode.depth)


def _targets_of(model, targets, target):
    names = model.vessel_names
    if not names:
        raise ValueError(f"scene '{model.name}' has no named vessels: a navigation "
                         "environment needs vessels and a target")
    if targets is None:
        targets = [t["vessel"] for t in model.targets if t["vessel"] is not None]
    if target is not None:
        targets = [target]
    if not targets:
        raise ValueError(f"scene '{model.name}' lists no target vessels: give target= or "
                         f"targets= (its vessels: {listed(names)})")
    for t in targets:
        if t not in names:
            raise ValueError(f"target {t!r} is not a vessel of scene '{model.name}' "
                             f"(its vessels: {listed(names)})")
    return list(targets)


def _lead_device(model, device):
    names = model.device_names
    if not names:
        raise ValueError(f"scene '{model.name}' has no device to drive")
    if device is not None:
        if device not in names:
            raise ValueError(f"device {device!r} is not in scene '{model.name}' "
                             f"(its devices: {', '.join(names)})")
        return names.index(device)
    for t in model.targets:
        if t["device"] is not None:
            return names.index(t["device"])
    inner = [i for i, d in enumerate(model.devices) if d["outer"] is not None]
    return inner[-1] if inner else len(names) - 1


def listed(names, most=12):
    """Names for a message: all of a short list, the first of a long one."""
    if len(names) <= most:
        return ", ".join(names)
    return ", ".join(names[:most]) + f", ... ({len(names)} in all)"
