"""Batches of simulations on a Dask cluster (or here, serially):

    python -m endovascular_sim.batch navigation --network-targets 20 --out nav.csv
    python -m endovascular_sim.batch accuracy carotid beam root --out acc.csv
    python -m endovascular_sim.batch rollouts --scene arch_navigation --count 40 --out r.csv
    python -m endovascular_sim.batch evaluate --agent build/ppo/model.zip --out eval.csv

(through bash scripts/python.sh). Where they run: --workers N (default 2)
starts a local cluster of N worker processes here and stops it at the end;
--cluster ADDRESS (tcp://host:8786 or a scheduler file) uses a running one
(docs/python.md, "Batches on a cluster"); --serial runs here, one task
after another. Each batch prints its progress and writes its rows to --out
as they come; run it again to resume (--restart starts over). --speedup
runs the batch on 1 and on 2 local workers and prints the ratio.
"""
import argparse
import collections
import sys
import time

import numpy as np

from endovascular_sim.batch import runner, tasks
from endovascular_sim.batch.cluster import ClusterError, connect

ARCH_SCENES = ("arch_to_left_subclavian", "arch_to_left_common_carotid",
               "arch_to_right_common_carotid", "arch_to_right_subclavian")


def navigation_tasks(a):
    import endovascular_sim as evs
    from endovascular_sim.envs.targets import branch_targets
    out = []
    for scene in a.arch_scenes:
        target = next(t["vessel"] for t in evs.load_scene(scene).targets if t["vessel"])
        out.append({"task": f"arch/{scene}/{target}", "scene": scene, "target": target,
                    "timeout": a.timeout})
    if a.network_targets > 0:
        model = evs.load_scene(a.network_scene)
        lead = model.device_names.index("microwire") if "microwire" in model.device_names else -1
        names = branch_targets(model, lead, a.min_branchings, a.max_branchings, avoid=())
        trunk = set(branch_targets(model, lead, a.min_branchings, a.max_branchings)) ^ set(names)
        drawn = [names[k] for k in np.random.default_rng(a.seed).permutation(len(names))]
        for target in drawn[:a.network_targets]:
            scene = a.network_scene_trunk if target in trunk else a.network_scene
            out.append({"task": f"network/{scene}/{target}", "scene": scene, "target": target,
                        "timeout": a.timeout})
    return out


def summarize_navigation(rows):
    groups = collections.defaultdict(list)
    for r in rows:
        groups[r["task"].split("/")[0]].append(r)
    for group, rs in groups.items():
        reached = [r for r in rs if r.get("reached") in (True, "True")]
        times = [float(r["time_s"]) for r in reached]
        forces = [float(r["peak_wall_force_N"]) for r in rs if r.get("peak_wall_force_N")]
        print(f"{group}: {len(reached)} of {len(rs)} reached"
              + (f", time median {np.median(times):.2f} s, worst {max(times):.2f} s"
                 if times else "")
              + (f", peak wall force {max(forces):.3f} N" if forces else ""))
        for r in rs:
            if r not in reached:
                print(f"  not reached: {r['task']}: {r.get('reason') or r.get('error')}")


def build(a):
    """(function, tasks, summary) of the batch the arguments ask for."""
    if a.kind == "navigation":
        return tasks.navigate, navigation_tasks(a), summarize_navigation
    if a.kind == "accuracy":
        return tasks.accuracy, [{"task": f"accuracy/{w}", "what": w, "duration": a.duration}
                                for w in a.what], None
    if a.kind == "rollouts":
        return tasks.rollout, [{"task": f"rollout/{a.scene}/{s}", "scene": a.scene, "seed": s,
                                "commands": a.commands, "hold": a.hold}
                               for s in range(a.seed, a.seed + a.count)], None
    targets, scenes = a.targets, a.scenes or [None]
    specs = []
    for scene in scenes:  # the anatomies: one environment's scene each
        env, options = a.env, {"targets": list(targets), "time_step": a.time_step,
                               "time_limit": a.time_limit}
        if scene:
            env, options["scene"] = "endovascular_sim/Navigation-v0", scene
        for k in range(a.episodes):
            target = targets[k % len(targets)]
            specs.append({"task": f"evaluate/{scene or a.env}/{target}/{100000 + k}",
                          "agent": a.agent, "algo": a.algo, "vecnormalize": a.vecnormalize,
                          "env": env, "target": target, "seed": 100000 + k, "options": options})
    return tasks.evaluate, specs, None


def parser():
    p = argparse.ArgumentParser(prog="python -m endovascular_sim.batch", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    where = argparse.ArgumentParser(add_help=False)
    where.add_argument("--cluster", help="a running cluster: tcp://host:port or a scheduler file")
    where.add_argument("--workers", type=int, default=2, help="worker processes of a local cluster")
    where.add_argument("--serial", action="store_true", help="run here, one task after another")
    where.add_argument("--timeout-connect", type=float, default=10.0,
                       help="[s] to reach the cluster and its workers")
    where.add_argument("--out", help="CSV of the rows, written as they come")
    where.add_argument("--restart", action="store_true", help="do not resume from --out")
    where.add_argument("--speedup", action="store_true",
                       help="run on 1 and on 2 local workers, print the ratio")
    kinds = p.add_subparsers(dest="kind", required=True)
    nav = kinds.add_parser("navigation", parents=[where], help="the autopilot's benchmark")
    nav.add_argument("--arch-scenes", nargs="*", default=list(ARCH_SCENES))
    nav.add_argument("--network-scene", default="network_navigation")
    nav.add_argument("--network-scene-trunk", default="network_navigation_headhunter")
    nav.add_argument("--network-targets", type=int, default=50)
    nav.add_argument("--min-branchings", type=int, default=3)
    nav.add_argument("--max-branchings", type=int, default=6)
    nav.add_argument("--seed", type=int, default=1)
    nav.add_argument("--timeout", type=float, default=90.0, help="[s] simulated per run")
    acc = kinds.add_parser("accuracy", parents=[where], help="evsim bench accuracy, per scene")
    acc.add_argument("what", nargs="+", help="scenes, beam, root")
    acc.add_argument("--duration", type=float, help="simulated seconds per run")
    rol = kinds.add_parser("rollouts", parents=[where], help="seeded random-command rollouts")
    rol.add_argument("--scene", default="arch_navigation")
    rol.add_argument("--count", type=int, default=20)
    rol.add_argument("--commands", type=int, default=30)
    rol.add_argument("--hold", type=int, default=40, help="steps per command")
    rol.add_argument("--seed", type=int, default=0)
    ev = kinds.add_parser("evaluate", parents=[where], help="an agent over targets and seeds")
    ev.add_argument("--agent", required=True, help="a Stable-Baselines3 agent's .zip")
    ev.add_argument("--algo", default="sac", choices=("sac", "ppo"))
    ev.add_argument("--vecnormalize", help="its VecNormalize statistics (.pkl)")
    ev.add_argument("--env", default="endovascular_sim/ArchNavigation-v0")
    ev.add_argument("--scenes", nargs="*", help="anatomies: scenes to evaluate in (Navigation-v0)")
    ev.add_argument("--targets", nargs="+", default=["right_common_carotid",
                                                      "left_common_carotid"])
    ev.add_argument("--episodes", type=int, default=100, help="per scene")
    ev.add_argument("--time-step", type=float, default=0.002)
    ev.add_argument("--time-limit", type=float, default=20.0)
    return p


def run_on(a, function, specs, out, workers=None, resume=True):
    if a.serial and workers is None:
        return runner.run(function, specs, out, None, resume)
    with connect(None if workers else a.cluster, workers or a.workers, a.timeout_connect) as client:
        return runner.run(function, specs, out, client, resume)


def main(argv=None):
    a = parser().parse_args(argv)
    try:
        function, specs, summary = build(a)
        if a.speedup:
            walls, results = [], []
            for workers in (1, 2):
                start = time.perf_counter()
                results.append(run_on(a, function, specs, None, workers, resume=False))
                walls.append(time.perf_counter() - start)
            same = [_untimed(r) for r in results[0]] == [_untimed(r) for r in results[1]]
            print(f"{len(specs)} tasks: 1 worker {walls[0]:.1f} s, 2 workers {walls[1]:.1f} s: "
                  f"speed-up {walls[0] / walls[1]:.2f}; the same rows: {same}")
            rows = results[1]
        else:
            rows = run_on(a, function, specs, a.out, resume=not a.restart)
    except (ClusterError, ValueError) as error:
        print(f"batch: {error}", file=sys.stderr)
        return 2
    if summary:
        summary(rows)
    failed = [r for r in rows if r.get("ok") not in (True, "True")]
    print(f"{len(rows) - len(failed)} rows ok, {len(failed)} failed"
          + (f" (written to {a.out})" if a.out and not a.speedup else ""))
    return 1 if failed else 0


def _untimed(row):
    return {k: v for k, v in row.items() if k not in tasks.TIMING}


if __name__ == "__main__":
    sys.exit(main())
