#!/usr/bin/env python3
"""A baseline that learns: Stable-Baselines3's SAC (as CathSim's baselines)
or PPO on ArchNavigation-v0, to the right and left common carotids from the
descending aorta.

Trains on N worker processes (SubprocVecEnv) for at most --steps
environment steps and --minutes of wall time, saving the agent every 10
minutes, writes the learning curve (training episodes' success over steps
and wall time) as CSV and PNG, then evaluates the trained agent over the
evaluation episodes beside the autopilot from the same start states (each
episode's devices turned by its seed, reset_rotation), as batches on a
local cluster, and prints one JSON summary line.

    bash scripts/python.sh scripts/train_agent.py --minutes 55 --out build/agent
    bash scripts/python.sh scripts/train_agent.py --evaluate build/agent/model.zip --out build/agent
"""
import argparse
import csv
import json
import os
import pathlib
import time

import numpy as np

TARGETS = ("right_common_carotid", "left_common_carotid")


def make_env(seed, interval, time_limit, time_step):
    def thunk():
        import torch  # each worker: one thread, the machine's cores are the workers
        torch.set_num_threads(1)
        import gymnasium
        from stable_baselines3.common.monitor import Monitor

        import endovascular_sim  # noqa: F401  (registers the ids)
        env = gymnasium.make("endovascular_sim/ArchNavigation-v0", targets=list(TARGETS),
                             control_interval=interval, time_limit=time_limit, time_step=time_step)
        env = Monitor(env, info_keywords=("success", "target"))
        env.reset(seed=seed)
        return env
    return thunk


ALGORITHMS = {
    "sac": dict(learning_rate=3e-4, buffer_size=300000, learning_starts=2000, batch_size=256,
                gamma=0.99, tau=0.005, train_freq=1, gradient_steps=1,
                policy_kwargs=dict(net_arch=[256, 256])),
    "ppo": dict(n_steps=512, batch_size=128, n_epochs=10, gamma=0.99, gae_lambda=0.95,
                learning_rate=3e-4, ent_coef=0.0, policy_kwargs=dict(net_arch=[128, 128])),
}


class Curve:
    """Training episodes as they end: steps, wall time, success, target."""

    def __init__(self, path):
        self.rows, self.path, self.start = [], path, time.perf_counter()

    def callback(self, minutes, save):
        """Records the episodes; saves every 10 minutes; stops after `minutes`."""
        from stable_baselines3.common.callbacks import BaseCallback
        curve = self

        class Record(BaseCallback):
            saved = 0.0

            def _on_step(self):
                now = time.perf_counter() - curve.start
                for info in self.locals["infos"]:
                    if "episode" in info:
                        curve.rows.append((self.num_timesteps, now,
                                           float(info["episode"]["success"]), info["target"]))
                if now - self.saved > 600.0:
                    self.saved = now
                    save()
                    curve.write()
                return now < 60.0 * minutes
        return Record()

    def write(self):
        with open(self.path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["env_steps", "wall_s", "success", "target"])
            w.writerows(self.rows)


def plot(curve_csv, png, title, window=50):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = list(csv.DictReader(open(curve_csv)))
    steps = np.array([float(r["env_steps"]) for r in rows])
    wall = np.array([float(r["wall_s"]) for r in rows]) / 60.0
    success = np.array([float(r["success"]) for r in rows])
    k = np.ones(window) / window
    rate = np.convolve(success, k, mode="valid") if len(success) >= window else success
    fig, ax = plt.subplots(figsize=(7, 3.6))
    ax.plot(steps[len(steps) - len(rate):], 100 * rate, color="tab:blue")
    ax.set_xlabel("environment steps (1/7.5 s each)")
    ax.set_ylabel(f"success over the last {window} episodes [%]")
    ax.set_ylim(0, 100)
    ax.grid(alpha=0.3)
    top = ax.secondary_xaxis("top", functions=(
        lambda s: np.interp(s, steps, wall), lambda m: np.interp(m, wall, steps)))
    top.set_xlabel("wall time [min], 2 worker processes")
    ax.set_title(f"{title} on ArchNavigation-v0 (right and left common carotid)", fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def evaluation_tasks(algo, model_path, vecnorm_path, episodes, interval, time_limit, time_step):
    """Episodes alternating between the targets, each from its seed's start."""
    options = dict(targets=list(TARGETS), control_interval=interval, time_limit=time_limit,
                   time_step=time_step)
    return [{"task": f"{TARGETS[k % len(TARGETS)]}/{100000 + k}", "agent": model_path, "algo": algo,
             "vecnormalize": vecnorm_path, "env": "endovascular_sim/ArchNavigation-v0",
             "target": TARGETS[k % len(TARGETS)], "seed": 100000 + k, "options": options}
            for k in range(episodes)]


def evaluate(specs, workers):
    """The agent's episodes and the autopilot's from the same start states,
    as batches on a local cluster (endovascular_sim.batch)."""
    from endovascular_sim.batch import runner, tasks
    from endovascular_sim.batch.cluster import connect
    with connect(None, workers) as client:
        agent = runner.run(tasks.evaluate, specs, client=client)
        pilot = runner.run(tasks.autopilot_episode, specs, client=client)
    return [{"target": a["target"], "seed": a["seed"], "agent_success": a.get("success"),
             "agent_time": a.get("time_s"), "agent_peak_wall_force": a.get("peak_wall_force_N"),
             "agent_path_ratio": a.get("path_ratio"), "autopilot_success": p.get("success"),
             "autopilot_time": p.get("time_s"),
             "autopilot_peak_wall_force": p.get("peak_wall_force_N"),
             "error": a.get("error") or p.get("error")} for a, p in zip(agent, pilot)]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--algo", choices=sorted(ALGORITHMS), default="sac")
    p.add_argument("--steps", type=int, default=1000000, help="environment steps of training, at most")
    p.add_argument("--minutes", type=float, default=55.0, help="wall time of training, at most")
    p.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    p.add_argument("--interval", type=float, default=1.0 / 7.5, help="[s] per action")
    p.add_argument("--time-limit", type=float, default=20.0, help="[s] simulated per episode")
    p.add_argument("--time-step", type=float, default=0.002,
                   help="[s] of the physics (docs/performance.md: what it costs in accuracy)")
    p.add_argument("--episodes", type=int, default=100, help="evaluation episodes")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", default="build/agent", help="folder for the model, curve and results")
    p.add_argument("--evaluate", help="evaluate this saved model instead of training")
    a = p.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    model_path, vecnorm_path = a.evaluate or str(out / "model.zip"), str(out / "vecnormalize.pkl")
    train_s = trained_steps = None
    if not a.evaluate:
        import torch
        torch.set_num_threads(1)
        import stable_baselines3
        from stable_baselines3.common.vec_env import SubprocVecEnv, VecNormalize
        venv = SubprocVecEnv([make_env(a.seed + i, a.interval, a.time_limit, a.time_step)
                              for i in range(a.workers)], start_method="fork")
        venv = VecNormalize(venv, norm_obs=True, norm_reward=a.algo == "ppo", clip_obs=10.0)
        algorithm = getattr(stable_baselines3, a.algo.upper())
        agent = algorithm("MlpPolicy", venv, seed=a.seed, device="cpu", verbose=0,
                          **ALGORITHMS[a.algo])

        def save():
            agent.save(model_path)
            venv.save(vecnorm_path)

        curve = Curve(out / "curve.csv")
        start = time.perf_counter()
        agent.learn(total_timesteps=a.steps, callback=curve.callback(a.minutes, save))
        train_s = time.perf_counter() - start
        trained_steps = agent.num_timesteps
        save()
        venv.close()
        curve.write()
        plot(out / "curve.csv", out / "curve.png", a.algo.upper())
    results = evaluate(evaluation_tasks(a.algo, model_path, vecnorm_path, a.episodes, a.interval,
                                        a.time_limit, a.time_step), a.workers)
    with open(out / "evaluation.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(results[0]))
        w.writeheader()
        w.writerows(results)
    summary = {"algo": a.algo, "train_steps": trained_steps, "train_wall_s": train_s,
               "episodes": len(results), "time_step": a.time_step}
    for target in TARGETS:
        rows = [r for r in results if r["target"] == target]
        summary[target] = {
            "agent_success": float(np.mean([bool(r["agent_success"]) for r in rows])),
            "autopilot_success": float(np.mean([bool(r["autopilot_success"]) for r in rows])),
            "agent_median_time_s": _median([r["agent_time"] for r in rows]),
            "autopilot_median_time_s": _median([r["autopilot_time"] for r in rows]),
        }
    print(json.dumps(summary))


def _median(values):
    values = [float(v) for v in values if v is not None]
    return float(np.median(values)) if values else None


if __name__ == "__main__":
    main()
