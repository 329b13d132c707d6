"""The distributed engine: Dask's (Debian's python3-distributed).

Why Dask: Debian packages it (Ray it does not); a scheduler and workers are
two commands (``dask-scheduler``, ``dask-worker ADDRESS``) on any machine
with the package; a local cluster of worker processes starts inside the
calling program with no set-up; tasks are plain functions of plain
arguments, their results plain rows; and a worker lost mid-batch has its
tasks re-run on the others by the scheduler.
"""
import contextlib
import logging

NO_WORKERS_TIMEOUT = 30.0  # [s] a batch on a cluster without workers stops after this


class ClusterError(RuntimeError):
    """The cluster cannot run the batch: unreachable, or a worker lacks the package."""


def _probe():
    """Runs on each worker: can it import the package? (Defined inside a
    function so that it travels by value, to a worker without the package.)"""
    def probe():
        try:
            import endovascular_sim
            return {"ok": True, "config": endovascular_sim.config_directory()}
        except Exception as error:  # noqa: BLE001 (reported, not raised)
            return {"ok": False, "error": f"{type(error).__name__}: {error}"}
    return probe


@contextlib.contextmanager
def connect(address=None, workers=2, timeout=10.0):
    """A Dask client: of the cluster at ``address`` (``tcp://host:port``, or a
    scheduler file's path), or of a local cluster of ``workers`` processes on
    this machine (one thread each) started here and stopped on exit.

    Raises ClusterError within ``timeout`` [s] when the address cannot be
    reached, has no workers, or a worker cannot import endovascular_sim.
    """
    import dask
    from distributed import Client, LocalCluster

    cluster = None
    with dask.config.set({"distributed.comm.timeouts.connect": f"{timeout}s",
                          "distributed.scheduler.allowed-failures": 3}):
        try:
            if address is None:
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       host="127.0.0.1", dashboard_address=None,
                                       silence_logs=logging.ERROR)
                client = Client(cluster, timeout=f"{timeout}s")
            elif address.endswith(".json"):
                client = Client(scheduler_file=address, timeout=f"{timeout}s")
            else:
                client = Client(address, timeout=f"{timeout}s")
        except (OSError, TimeoutError) as error:
            if cluster is not None:
                cluster.close()
            raise ClusterError(f"cannot reach the cluster at {address} within {timeout:g} s "
                               f"({type(error).__name__}: {error})") from None
        try:
            try:
                client.wait_for_workers(1, timeout=timeout)
            except (TimeoutError, OSError):
                raise ClusterError(f"the cluster at {address} has no workers "
                                   f"(waited {timeout:g} s)") from None
            lacking = {worker: answer["error"]
                       for worker, answer in client.run(_probe()).items() if not answer["ok"]}
            if lacking:
                raise ClusterError("workers without the endovascular_sim package: " + "; ".join(
                    f"{w}: {why}" for w, why in sorted(lacking.items())))
            yield client
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
