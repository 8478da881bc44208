"""Evaluate a study function over a design, in this process or on a Dask cluster.

A study function takes a block of runs, ``{factor: array (runs,)}`` of physical values
[N m/rad], and returns ``{name: array (runs, ...)}`` (for the sensitivity study: the weave
and wobble eigenvalues over speed). The design is cut into blocks of ``block_size`` runs; the
same blocks are evaluated in both paths, so a deterministic study function gives identical
results in process and on Dask. Bigger designs scale out by pointing ``scheduler`` at a
cluster, never by a home-made pool (docs/performance.md, the sensitivity study on Dask).

Dask workers should run single-threaded BLAS: a LocalCluster made here sets
OPENBLAS_NUM_THREADS=1 (and OMP/MKL) in its worker processes; workers of an existing cluster
should be started the same way (``OPENBLAS_NUM_THREADS=1 dask worker ADDRESS``).
"""
import os
import time
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from motoflex_ros.errors import ModelError
from motoflex_ros.progress import progress_bar

__all__ = ["StudyRun", "run_study", "design_blocks", "local_cluster", "SINGLE_THREAD_ENV"]

SINGLE_THREAD_ENV = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
                     "MKL_NUM_THREADS": "1"}


@dataclass(frozen=True, eq=False)
class StudyRun:
    """Outputs of a study over a design.

    design: the Design; outputs: {name: array (runs, ...)} in design order; seconds: wall
    time [s]; where: "in-process" or the Dask scheduler address.
    """

    design: object
    outputs: dict
    seconds: float
    where: str


def design_blocks(n_runs, block_size):
    """Consecutive (start, stop) run ranges of at most ``block_size`` runs."""
    if int(block_size) != block_size or block_size < 1:
        raise ModelError(f"block size must be a positive integer, got {block_size}")
    return [(start, min(start + int(block_size), n_runs))
            for start in range(0, n_runs, int(block_size))]


def _evaluate_block(study_function, values):
    """Call the study function on one block and check what it returns."""
    outputs = study_function(values)
    runs = len(next(iter(values.values())))
    if not isinstance(outputs, Mapping):
        raise ModelError("a study function must return a mapping {name: array (runs, ...)}")
    outputs = {name: np.asarray(array) for name, array in outputs.items()}
    for name, array in outputs.items():
        if array.ndim == 0 or array.shape[0] != runs:
            raise ModelError(f"study output '{name}' has shape {array.shape}, expected "
                             f"({runs}, ...)")
    return outputs


def _concatenate(block_outputs):
    names = list(block_outputs[0])
    return {name: np.concatenate([block[name] for block in block_outputs], axis=0)
            for name in names}


def _run_in_process(study_function, design, blocks, bar):
    outputs = []
    for start, stop in blocks:
        outputs.append(_evaluate_block(study_function, design.values(start, stop)))
        bar.update(stop - start)
    return outputs


def local_cluster(n_workers=None, processes=True):
    """A dask.distributed LocalCluster with one single-threaded-BLAS thread per worker."""
    from distributed import LocalCluster

    n_workers = n_workers or max(1, min(os.cpu_count() or 1, 4))
    kwargs = {"env": dict(SINGLE_THREAD_ENV)} if processes else {}
    return LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=processes,
                        dashboard_address=None, **kwargs)


def _run_on_dask(study_function, design, blocks, bar, client):
    from distributed import as_completed

    futures = {}
    for index, (start, stop) in enumerate(blocks):
        future = client.submit(_evaluate_block, study_function, design.values(start, stop),
                               pure=False)
        futures[future] = index
    outputs = [None] * len(blocks)
    for future in as_completed(futures):
        index = futures[future]
        outputs[index] = future.result()
        bar.update(blocks[index][1] - blocks[index][0])
    return outputs


def _connect(scheduler):
    """(client, things to close) for "local", an address, a Cluster or a Client."""
    from distributed import Client

    if isinstance(scheduler, Client):
        return scheduler, []
    if isinstance(scheduler, str) and scheduler != "local":
        client = Client(scheduler)
        return client, [client]
    cluster = local_cluster() if scheduler == "local" else scheduler
    client = Client(cluster)
    return client, [client] + ([cluster] if scheduler == "local" else [])


def run_study(study_function, design, scheduler=None, progress=True, block_size=64):
    """Evaluate ``study_function`` on every run of ``design``.

    Parameters
    ----------
    study_function : callable
        ``f({factor: array (runs,)}) -> {name: array (runs, ...)}``, vectorised over runs;
        picklable (module-level function or instance) for Dask worker processes.
    design : motoflex_ros.study.factorial.Design
        The runs.
    scheduler : None, "local", str, distributed.Client or Cluster
        None: in this process. "local": a new LocalCluster (closed afterwards). An address
        ("tcp://host:8786"): that scheduler. A Client or Cluster: used as given.
    progress : bool
        Show a progress bar of runs done (tqdm, on stderr).
    block_size : int
        Runs per call of the study function (one Dask task per block).

    """
    blocks = design_blocks(len(design), block_size)
    start = time.perf_counter()
    with progress_bar(total=len(design), unit="run", enabled=progress, desc="study") as bar:
        if scheduler is None:
            outputs, where = _run_in_process(study_function, design, blocks, bar), "in-process"
        else:
            client, to_close = _connect(scheduler)
            try:
                outputs = _run_on_dask(study_function, design, blocks, bar, client)
                where = str(client.scheduler.address)
            finally:
                for thing in to_close:
                    thing.close()
    return StudyRun(design=design, outputs=_concatenate(outputs),
                    seconds=time.perf_counter() - start, where=where)
