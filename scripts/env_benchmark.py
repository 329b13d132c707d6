#!/usr/bin/env python3
"""How fast the Gymnasium environments step, and what a larger physics time
step costs in accuracy.

For each control interval (a fluoroscopy frame, 1/7.5 s, as stEVE, here
132 ms; 12 ms, as CathSim) and physics time step, the same seeded actions drive
ArchNavigation-v0 (to the right common carotid, its devices turned by the
seed) for `--seconds` of simulated time:
- env steps/s in one process (one environment, stepped on this thread),
- env steps/s on all cores (the native vector environment, one copy per
  core, stepped by the core's thread pool), in all and per core,
- the lead tip's distance [mm] from where the finest time step's run put
  it after the same actions (median and largest over the actions).
Then `evs.rollout` of a batch (--batch copies of the scene, their own
seeded random commands, 2 s simulated each) on 1 thread and on every core:
simulated seconds per wall second.
Prints Markdown tables (docs/performance.md quotes them).

    bash scripts/python.sh scripts/env_benchmark.py
"""
import argparse
import os
import time

import numpy as np

import endovascular_sim  # noqa: F401  (registers the ids)
from endovascular_sim.envs.navigation import NavigationEnv
from endovascular_sim.envs.vector import NavigationVectorEnv

OPTIONS = dict(scene="arch_navigation", target="right_common_carotid", reset_rotation=np.pi,
               time_limit=3600.0)


def actions_for(count, seed):
    rng = np.random.default_rng(seed)
    a = rng.uniform(-1.0, 1.0, (count, 4))
    a[:, 0::2] = rng.uniform(-0.2, 1.0, (count, 2))  # insertions mostly forward
    return a.astype(np.float32)


def single(interval, time_step, actions, seed):
    env = NavigationEnv(control_interval=interval, time_step=time_step, **OPTIONS)
    env.reset(seed=seed)
    tips = []
    start = time.perf_counter()
    for a in actions:
        env.step(a)
        tips.append(np.array(env.data.devices[env.lead].position[-1]))
    return len(actions) / (time.perf_counter() - start), np.array(tips)


def vector(interval, time_step, actions, seed, copies):
    vec = NavigationVectorEnv(num_envs=copies, nthread=copies, control_interval=interval,
                              time_step=time_step, **OPTIONS)
    vec.reset(seed=seed)
    start = time.perf_counter()
    for a in actions:
        vec.step(np.tile(a, (copies, 1)))
    return copies * len(actions) / (time.perf_counter() - start)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--seconds", type=float, default=8.0, help="[s] simulated per run")
    p.add_argument("--time-steps", default="0.001,0.002,0.004", help="[s], the first the reference")
    p.add_argument("--cores", type=int, default=os.cpu_count() or 1)
    p.add_argument("--seed", type=int, default=3)
    p.add_argument("--batch", type=int, default=8, help="simulations of the rollout")
    a = p.parse_args()
    steps = [float(x) for x in a.time_steps.split(",")]
    print(f"ArchNavigation-v0, {a.seconds:g} s simulated per run, {a.cores} cores\n")
    print("| interval | physics step | env steps/s, 1 process | all cores (per core) "
          "| tip vs finest: median, largest [mm] |")
    print("|---|---|---|---|---|")
    # 132 ms for a fluoroscopy frame: a whole number of steps of every time
    # step compared, so that the runs are compared at the same times.
    for interval, label in ((0.132, "132 ms (1/7.5 s)"), (0.012, "12 ms")):
        count = int(round(a.seconds / interval))
        actions = actions_for(count, a.seed)
        reference = None
        for dt in steps:
            if dt > interval:
                continue
            rate, tips = single(interval, dt, actions, a.seed)
            vec_rate = vector(interval, dt, actions, a.seed, a.cores)
            if reference is None:
                reference, error = tips, "reference"
            else:
                d = np.linalg.norm(tips - reference, axis=1) * 1e3
                error = f"{np.median(d):.2f}, {d.max():.2f}"
            print(f"| {label} | {dt * 1e3:g} ms | {rate:.1f} | {vec_rate:.1f} "
                  f"({vec_rate / a.cores:.1f}) | {error} |", flush=True)
    one, all_cores = rollout_rates(a.batch, 2.0, a.cores, a.seed)
    print(f"\nrollout of {a.batch} arch_navigation simulations, 2 s each: 1 thread "
          f"{one:.2f} simulated s per wall s, {a.cores} threads {all_cores:.2f} "
          f"({all_cores / one:.2f}x)")


def rollout_rates(batch, seconds, cores, seed):
    """Simulated seconds per wall second of a batch rolled out on 1 thread
    and on `cores` threads (each from the scene's start)."""
    import endovascular_sim as evs
    model = evs.load_scene(OPTIONS["scene"])
    hold = 40
    count = int(round(seconds / (hold * model.time_step)))
    rng = np.random.default_rng(seed)
    limits = np.array([[d["max_insertion_speed"], d["max_rotation_speed"]] for d in model.devices])
    u = rng.uniform(-1.0, 1.0, (batch, count, len(model.devices), 2))
    u[..., 0] = rng.uniform(-0.2, 1.0, u[..., 0].shape)
    commands = (u * limits).reshape(batch, count, -1)
    rates = []
    for threads in (1, cores):
        data = [evs.make_data(model) for _ in range(batch)]
        start = time.perf_counter()
        evs.rollout(model, data, commands, steps_per_command=hold, nthread=threads)
        rates.append(batch * count * hold * model.time_step / (time.perf_counter() - start))
    return rates


if __name__ == "__main__":
    main()
