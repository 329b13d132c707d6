"""Runs a batch of tasks, serially here or on a Dask cluster, writing its
rows as they come (a CSV with the task's columns), so that a batch stopped
half-way keeps what it finished and resumes from it."""
import csv
import os
import sys
import time

from endovascular_sim.batch.cluster import NO_WORKERS_TIMEOUT, ClusterError


class Progress:
    """'[done/total] rate tasks/s, ETA' lines on a stream."""

    def __init__(self, total, already, stream=sys.stderr):
        self.total, self.done, self.stream = total, already, stream
        self.start, self.started_at = time.perf_counter(), already

    def step(self, row):
        self.done += 1
        elapsed = time.perf_counter() - self.start
        rate = (self.done - self.started_at) / elapsed if elapsed > 0 else 0.0
        left = (self.total - self.done) / rate if rate > 0 else float("inf")
        status = "ok" if row.get("ok") in (True, "True") else f"failed: {row.get('error', '')}"
        print(f"[{self.done}/{self.total}] {row['task']} {status}  {rate:.2f} tasks/s, "
              f"{left:.0f} s left", file=self.stream, flush=True)


def read_rows(path):
    if not path or not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def _as_rows(result):
    return result if isinstance(result, list) else [result]


def run(function, tasks, out=None, client=None, resume=True, stream=sys.stderr):
    """function(spec) for every spec of ``tasks`` (each with a unique 'task'
    id); on ``client`` (a Dask client) or here, one after another.

    Rows go to ``out`` (CSV, function.columns) as each task ends; with
    ``resume`` the tasks whose rows it already holds are not run again. At
    the end the file holds every row in the tasks' order. Returns the rows
    (as read back from the file when ``out`` is given: strings)."""
    ids = [t["task"] for t in tasks]
    if len(set(ids)) != len(ids):
        raise ValueError("task ids must be unique")
    kept = read_rows(out) if resume else []
    done = {r["task"] for r in kept}
    pending = [t for t in tasks if t["task"] not in done]
    progress = Progress(len(tasks), len(tasks) - len(pending), stream)
    columns = function.columns
    handle = None
    if out:
        fresh = not kept
        handle = open(out, "w" if fresh else "a", newline="")
        writer = csv.DictWriter(handle, fieldnames=columns, extrasaction="ignore")
        if fresh:
            writer.writeheader()
    rows = list(kept)

    def take(result):
        for row in _as_rows(result):
            rows.append(row)
            if handle:
                writer.writerow(row)
                handle.flush()
            progress.step(row)

    try:
        if client is None:
            for spec in pending:
                take(function(spec))
        else:
            _on_cluster(client, function, pending, take)
    finally:
        if handle:
            handle.close()
    order = {task: k for k, task in enumerate(ids)}
    rows.sort(key=lambda r: order.get(r["task"], len(order)))
    if out:
        with open(out, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore")
            w.writeheader()
            w.writerows(rows)
        return read_rows(out)
    return rows


def _on_cluster(client, function, pending, take):
    """Submits every task, takes their rows as they complete. A task whose
    workers died running it (the scheduler's allowed failures) is that
    row's failure; a cluster left without workers stops the batch."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    # A key per function and task: two batches of one client with the same
    # task ids are different tasks.
    futures = {client.submit(function, spec, key=f"{function.__name__}/{spec['task']}",
                             pure=False): spec for spec in pending}
    waiting = as_completed(futures, with_results=False)
    alone_since = None
    while not waiting.is_empty():
        batch = waiting.next_batch(block=False)
        if not batch:
            if not client.scheduler_info().get("workers"):
                alone_since = alone_since or time.perf_counter()
                if time.perf_counter() - alone_since > NO_WORKERS_TIMEOUT:
                    raise ClusterError(f"the cluster has had no workers for "
                                       f"{NO_WORKERS_TIMEOUT:g} s: the batch stops (its rows "
                                       "so far are kept; run it again to resume)")
            else:
                alone_since = None
            time.sleep(0.05)
            continue
        for future in batch:
            spec = futures[future]
            try:
                take(future.result())
            except KilledWorker as error:
                take({"task": spec["task"], "ok": False,
                      "error": f"its workers died running it ({error})"})
