"""Batches of simulations (benchmarks, sweeps, evaluations, rollouts) on a
Dask cluster or serially: ``runner.run(function, tasks, out, client)`` with
the tasks of ``tasks`` and a client of ``cluster.connect``; from the shell,
``python -m endovascular_sim.batch`` (docs/python.md)."""
