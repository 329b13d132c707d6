"""The tasks a batch is made of: plain functions of plain specs (scene
names or files, targets, seeds, options: never live objects) that a worker
runs and that return rows. A simulation that fails (a failed step, a scene
a worker cannot read) is that row's failure, with its reason: ok False,
error the message. The TIMING columns are wall-clock times, the only ones
two runs of one task may differ in."""
import time

import numpy as np

TIMING = ("wall_s", "cost")  # [s] of the task; evsim's seconds per simulated second


def _failure(spec, error):
    return {"task": spec["task"], "ok": False, "error": f"{type(error).__name__}: {error}"}


def navigate(spec):
    """The autopilot to spec['target'] in spec['scene'] (evsim navigate's run)."""
    import endovascular_sim as evs
    start = time.perf_counter()
    try:
        model = evs.load_scene(spec["scene"])
        data = evs.make_data(model)
        r = evs.run_autopilot(model, data, spec["target"], spec.get("device", ""),
                              spec.get("timeout", 90.0))
    except Exception as error:  # noqa: BLE001 (the row's failure)
        return _failure(spec, error)
    return {"task": spec["task"], "ok": True, "error": "", "scene": spec["scene"],
            "target": spec["target"], "reached": r["reached"], "reason": r["reason"],
            "time_s": r["time"], "retries": r["retries"], "peak_wall_force_N": r["peak_wall_force"],
            "failed_steps": r["failed_steps"], "remaining_path_m": r["remaining_path"],
            "wall_s": time.perf_counter() - start}


navigate.columns = ("task", "ok", "error", "scene", "target", "reached", "reason", "time_s",
                    "retries", "peak_wall_force_N", "failed_steps", "remaining_path_m", "wall_s")


def rollout(spec):
    """spec['commands'] seeded random velocity commands (insertions mostly
    forward), each held spec['hold'] steps, from the scene's start: where
    every device's tip ends, the largest wall force."""
    import endovascular_sim as evs
    start = time.perf_counter()
    try:
        model = evs.load_scene(spec["scene"])
        data = evs.make_data(model)
        rng = np.random.default_rng(spec["seed"])
        limits = np.array([[d["max_insertion_speed"], d["max_rotation_speed"]]
                           for d in model.devices])
        u = rng.uniform(-1.0, 1.0, (1, spec["commands"], len(model.devices), 2))
        u[..., 0] = rng.uniform(-0.2, 1.0, u[..., 0].shape)
        out = evs.rollout(model, [data], (u * limits).reshape(1, spec["commands"], -1),
                          steps_per_command=spec["hold"])
    except Exception as error:  # noqa: BLE001
        return _failure(spec, error)
    tips = out["tip_position"][0, -1]
    return {"task": spec["task"], "ok": not bool(out["failed"].any()),
            "error": data.last_error if out["failed"].any() else "", "scene": spec["scene"],
            "seed": spec["seed"], "time_s": float(out["time"][0, -1]),
            "tips_m": " ".join(f"{x!r}" for x in tips.ravel()),
            "max_wall_force_N": float(out["max_wall_force"][0].max()),
            "wall_s": time.perf_counter() - start}


rollout.columns = ("task", "ok", "error", "scene", "seed", "time_s", "tips_m", "max_wall_force_N",
                   "wall_s")


def evaluate(spec):
    """An episode of a Stable-Baselines3 agent (spec['agent'], a saved .zip of
    the algorithm spec['algo'], "sac" or "ppo";
    spec['vecnormalize'] its observation statistics, optional) in the
    environment spec['env'] with spec['options'], to spec['target'], from
    the start state of spec['seed']."""
    import os

    import gymnasium
    import endovascular_sim  # noqa: F401  (registers the ids)
    start = time.perf_counter()
    try:
        import stable_baselines3
        algorithm = getattr(stable_baselines3, spec.get("algo", "ppo").upper())
        agent = algorithm.load(spec["agent"], device="cpu")
        env = gymnasium.make(spec["env"], **spec.get("options", {})).unwrapped
        norm = None
        if spec.get("vecnormalize") and os.path.exists(spec["vecnormalize"]):
            import pickle
            with open(spec["vecnormalize"], "rb") as f:
                norm = pickle.load(f)
        obs, info = env.reset(seed=spec["seed"], options={"target": spec["target"]})
        done = False
        while not done:
            o = norm.normalize_obs(obs[None])[0] if norm is not None else obs
            action, _ = agent.predict(o, deterministic=True)
            obs, _, terminated, truncated, info = env.step(action)
            done = terminated or truncated
    except Exception as error:  # noqa: BLE001
        return _failure(spec, error)
    return {"task": spec["task"], "ok": True, "error": info["failure"] if not info["success"] and
            info["failure"] not in ("", "time limit") else "", "target": spec["target"],
            "seed": spec["seed"], "success": info["success"], "safe_success": info["safe_success"],
            "time_s": info["time"], "path_ratio": info["path_ratio"],
            "peak_wall_force_N": info["peak_wall_force"], "wall_s": time.perf_counter() - start}


evaluate.columns = ("task", "ok", "error", "target", "seed", "success", "safe_success", "time_s",
                    "path_ratio", "peak_wall_force_N", "wall_s")


def autopilot_episode(spec):
    """The autopilot from the start state of an environment's episode
    (spec as for ``evaluate``, without the agent): its success within the
    episode's time limit, beside an agent's."""
    import gymnasium

    import endovascular_sim as evs
    start = time.perf_counter()
    try:
        options = dict(spec.get("options", {}))
        env = gymnasium.make(spec["env"], **options).unwrapped
        env.reset(seed=spec["seed"], options={"target": spec["target"]})
        r = evs.run_autopilot(env.model, env.data, spec["target"], "", env.time_limit)
    except Exception as error:  # noqa: BLE001
        return _failure(spec, error)
    return {"task": spec["task"], "ok": True, "error": "", "target": spec["target"],
            "seed": spec["seed"], "success": r["reached"], "reason": r["reason"],
            "time_s": r["time"], "peak_wall_force_N": r["peak_wall_force"],
            "wall_s": time.perf_counter() - start}


autopilot_episode.columns = ("task", "ok", "error", "target", "seed", "success", "reason",
                             "time_s", "peak_wall_force_N", "wall_s")


def accuracy(spec):
    """``evsim bench accuracy WHAT`` on a worker: its rows (knob, value, error,
    cost), each tagged with the task."""
    import csv
    import subprocess
    import tempfile

    import endovascular_sim as evs
    start = time.perf_counter()
    try:
        with tempfile.TemporaryDirectory() as folder:
            path = f"{folder}/rows.csv"
            command = [evs.evsim_binary(), "bench", "accuracy", spec["what"], "--csv", path]
            if spec.get("duration"):
                command += ["--duration", str(spec["duration"])]
            done = subprocess.run(command, capture_output=True, text=True)
            if done.returncode != 0:
                raise RuntimeError(done.stderr.strip() or f"exit {done.returncode}")
            with open(path, newline="") as f:
                rows = list(csv.DictReader(f))
    except Exception as error:  # noqa: BLE001
        return _failure(spec, error)
    wall = time.perf_counter() - start
    return [dict(row, task=spec["task"], ok=True, error="", what=spec["what"], wall_s=wall)
            for row in rows]


accuracy.columns = ("task", "ok", "error", "what", "knob", "setting", "cost", "cost_unit",
                    "error_m", "max_penetration_m", "max_residual", "rejected", "wall_s")
