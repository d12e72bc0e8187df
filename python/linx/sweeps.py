"""Sweeps: one function run over many parameter values, on the cores of this machine or on many
machines through dask.distributed (docs/python.md, "Sweeps").

    def run(damping):                      # a module-level function: it travels by pickling
        world = linx.load("pendulum.json")     # (or a copy of a World passed in the parameters)
        world.joint(0).set_spring(stiffness=0, damping=damping)
        world.step(2000)
        return {"damping": damping, "angle": world.coordinates[0]}

    rows = linx.sweep(run, [0.0, 0.1, 0.2])             # a local cluster, one worker per core
    rows = linx.sweep(run, values, address="tcp://scheduler:8786")   # a cluster's scheduler

A run must not change its parameters: dask may hand one deserialized object to several runs on a
worker, so a run steps a copy of a world it is given (world.copy()), not the world itself.

A run whose worker dies (killed, out of memory, a lost machine) is run again on another worker; a
run that raises is retried `retries` times. If a run still fails, sweep() raises SweepError naming
it: a table is never returned with a run missing.
"""

from __future__ import annotations

import copy
import csv
import os
from typing import Any, Callable, Iterable, Optional, Sequence

from linx._linx import Error

__all__ = ["sweep", "serial", "SweepError", "write_csv"]


class SweepError(Error):
    """Runs of a sweep that failed after their retries: `failures` lists (index, parameter,
    message) for each."""

    def __init__(self, failures: list[tuple[int, Any, str]]) -> None:
        self.failures = failures
        lines = [f"run {i} ({p!r}): {m}" for i, p, m in failures]
        super().__init__(f"{len(failures)} run(s) of the sweep failed:\n  " + "\n  ".join(lines))

    def __reduce__(self):  # pickled with its failures, not its message
        return (SweepError, (self.failures,))


def serial(run: Callable[[Any], Any], params: Iterable[Any]) -> list[Any]:
    """run(p) for each p in order, here: the reference a distributed sweep reproduces. As on the
    workers, each run gets its own copy of its parameter (a world in it is copied, not stepped
    on by the next run)."""
    return [run(copy.deepcopy(p)) for p in params]


def sweep(run: Callable[[Any], Any], params: Iterable[Any], *, address: Optional[str] = None,
          client: Any = None, workers: Optional[int] = None, retries: int = 2) -> list[Any]:
    """run(p) for every p of params on dask.distributed workers; the results in params' order.

    address: a dask scheduler ("tcp://host:8786") to spread the runs over its workers; client: an
    open distributed.Client to use instead; neither: a local cluster of `workers` processes (one
    per core by default), started and stopped here. `run` and the parameters are pickled to the
    workers (worlds and states pickle); each run is retried `retries` times if it raises, and
    run again elsewhere if its worker is lost. Raises SweepError if any run still failed."""
    from distributed import Client, LocalCluster, wait

    params = list(params)
    own_client = own_cluster = None
    if client is None:
        if address is not None:
            client = own_client = Client(address)
        else:
            own_cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1,
                                       threads_per_worker=1, processes=True,
                                       dashboard_address=":0")
            client = own_client = Client(own_cluster)
    try:
        futures = client.map(run, params, pure=False, retries=retries)
        wait(futures)
        failures = []
        for i, (p, f) in enumerate(zip(params, futures)):
            if f.status != "finished":
                failures.append((i, p, repr(f.exception())))
        if failures:
            raise SweepError(failures)
        return client.gather(futures)
    finally:
        if own_client is not None:
            own_client.close()
        if own_cluster is not None:
            own_cluster.close()


def write_csv(rows: Sequence[dict[str, Any]], path: "os.PathLike[str] | str") -> None:
    """Writes rows of results (dicts with the same keys) as a CSV table with a header."""
    if not rows:
        raise ValueError("write_csv: no rows")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for r in rows:
            w.writerow({k: repr(v) if isinstance(v, float) else v for k, v in r.items()})
