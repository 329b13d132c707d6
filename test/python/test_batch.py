"""Batches on a real Dask scheduler and two worker processes on loopback,
against the same batch run serially: the same rows, a worker killed
mid-batch, a failing task, a resumed batch, and the clusters it refuses."""
import io
import json
import os
import signal
import subprocess
import sys
import time

import pytest

from endovascular_sim.batch import runner, tasks
from endovascular_sim.batch.cluster import ClusterError, connect


def rollouts(count, commands=10, hold=40):
    return [{"task": f"rollout/{s}", "scene": "arch_navigation", "seed": s,
             "commands": commands, "hold": hold} for s in range(count)]


def untimed(rows):
    return [{k: str(v) for k, v in r.items() if k not in tasks.TIMING} for r in rows]


class Cluster:
    """dask-scheduler and dask-worker processes, as on a cluster's machines."""

    def __init__(self, folder, workers=2, python=sys.executable, env=None):
        self.file = str(folder / "scheduler.json")
        self.env = env
        self.scheduler = self._start(python, "dask_scheduler", "--host", "127.0.0.1",
                                     "--port", "0", "--scheduler-file", self.file,
                                     "--no-dashboard")
        for _ in range(600):
            if os.path.exists(self.file):
                break
            time.sleep(0.05)
        self.address = json.load(open(self.file))["address"]
        self.workers = [self.add_worker(python, env) for _ in range(workers)]

    def _start(self, python, cli, *args, env=None):
        return subprocess.Popen([python, "-m", f"distributed.cli.{cli}", *args],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                env=env or self.env, start_new_session=True)

    def add_worker(self, python=sys.executable, env=None):
        return self._start(python, "dask_worker", self.address, "--nthreads", "1",
                           "--no-nanny", "--no-dashboard", env=env)

    def close(self):
        for p in self.workers + [self.scheduler]:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGKILL)
            p.wait()


@pytest.fixture
def cluster(tmp_path):
    c = Cluster(tmp_path)
    yield c
    c.close()


def test_a_batch_on_two_workers_gives_the_serial_rows(cluster):
    batch = rollouts(6) + [{"task": "rollout/bad", "scene": "no_such_scene", "seed": 0,
                            "commands": 2, "hold": 2}]
    serial = runner.run(tasks.rollout, batch, stream=io.StringIO())
    from distributed import get_task_stream
    with connect(cluster.address, timeout=30) as client:
        client.wait_for_workers(2, timeout=30)
        with get_task_stream(client) as stream:
            distributed = runner.run(tasks.rollout, batch, client=client, stream=io.StringIO())
        # Another function over the same task ids runs anew (the navigation
        # task cannot read a rollout's spec: failed rows, not the rollouts').
        other = runner.run(tasks.navigate, batch, client=client, stream=io.StringIO())
    assert not any(r["ok"] for r in other) and "KeyError" in other[0]["error"]
    assert untimed(distributed) == untimed(serial)
    assert len({t["worker"] for t in stream.data}) == 2  # both workers ran tasks
    bad = distributed[-1]
    assert bad["ok"] is False and "no_such_scene" in bad["error"]  # the row's failure, its reason
    assert all(r["ok"] for r in distributed[:-1])


class KillOnFirstRow(io.StringIO):
    """A progress stream that kills a worker when the first row comes in."""

    def __init__(self, worker):
        super().__init__()
        self.worker, self.killed = worker, False

    def write(self, text):
        if not self.killed and text.startswith("["):
            os.killpg(self.worker.pid, signal.SIGKILL)
            self.killed = True
        return super().write(text)


def test_a_worker_killed_mid_batch_has_its_tasks_rerun_on_the_other(cluster):
    batch = rollouts(6, commands=20)
    serial = runner.run(tasks.rollout, batch, stream=io.StringIO())
    stream = KillOnFirstRow(cluster.workers[0])
    with connect(cluster.address, timeout=30) as client:
        client.wait_for_workers(2, timeout=30)
        rows = runner.run(tasks.rollout, batch, client=client, stream=stream)
    assert stream.killed and cluster.workers[0].poll() is not None
    assert untimed(rows) == untimed(serial)


class StopAfter(io.StringIO):
    def __init__(self, rows):
        super().__init__()
        self.rows = rows

    def write(self, text):
        super().write(text)
        if text.startswith("[") and self.getvalue().count("\n[") + 1 >= self.rows:
            raise KeyboardInterrupt


def test_a_stopped_batch_keeps_its_rows_and_resumes(tmp_path):
    batch = rollouts(5, commands=4)
    out = str(tmp_path / "rows.csv")
    with pytest.raises(KeyboardInterrupt):
        runner.run(tasks.rollout, batch, out, stream=StopAfter(2))
    assert len(runner.read_rows(out)) == 2
    log = io.StringIO()
    rows = runner.run(tasks.rollout, batch, out, stream=log)
    assert log.getvalue().count("\n") == 3  # only the three it had not finished
    assert untimed(rows) == untimed(runner.run(tasks.rollout, batch, stream=io.StringIO()))


def test_an_unreachable_cluster_is_refused_in_bounded_time():
    start = time.perf_counter()
    with pytest.raises(ClusterError, match="cannot reach the cluster at tcp://127.0.0.1:9"):
        with connect("tcp://127.0.0.1:9", timeout=2):
            pass
    assert time.perf_counter() - start < 30


def test_a_worker_without_the_package_is_named(tmp_path):
    bare = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    c = Cluster(tmp_path, workers=0)
    try:
        c.workers.append(c.add_worker("/usr/bin/python3", env=bare))  # Debian's Dask, no package
        with pytest.raises(ClusterError, match="without the endovascular_sim package: tcp://"
                                               ".*No module named 'endovascular_sim'"):
            with connect(c.address, timeout=30):
                pass
    finally:
        c.close()
