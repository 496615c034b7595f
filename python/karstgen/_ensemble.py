"""Ensembles on Dask: one task per realization on a ``dask.distributed`` cluster (a
``LocalCluster`` by default, a Slurm cluster through dask-jobqueue; docs/ensembles.md).

The folder is the command line's (``karstgen ensemble``): ``ensemble.json``, one record per
realization under ``realizations/``, ``metrics.csv``, ``summary.csv``, ``failures.csv``,
``probability.vti`` and the probability slices, plus ``summary.parquet`` (the table) and
``probability.nc`` (the probability volume as an xarray Dataset). Folders written by Dask and
by the command line are interchangeable, and ``karstgen ensemble merge`` merges either.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Iterable, Optional, Union

import numpy as np

from . import _native, _scene

if TYPE_CHECKING:
    import pandas as pd

#: The default artifacts a realization keeps beside its record.
DEFAULT_KEEP = ("metrics", "skeleton")


@dataclass
class EnsembleResult:
    """What :func:`ensemble` returns.

    Attributes
    ----------
    out : Path
        The ensemble folder.
    table : pandas.DataFrame
        One row per complete realization of the folder, by seed (``summary.parquet``).
    failures : pandas.DataFrame
        ``seed`` and ``error`` of every failed realization.
    probability : xarray.Dataset
        ``probability`` (fraction of realizations with a conduit in each cell) and ``count``
        on dims (z, y, x) at the cell centres, metres (``probability.nc``).
    ran : int
        Realizations run by this call (the others were complete already).
    """

    out: Path
    table: pd.DataFrame
    failures: pd.DataFrame
    probability: Any
    ran: int


def ensemble(
    scene: _scene.SceneLike,
    seeds: Union[int, str, Iterable[int]],
    client: Any = None,
    out: Union[str, Path, None] = None,
    until: Optional[str] = None,
    keep: Iterable[str] = DEFAULT_KEEP,
    *,
    cell: float = 10.0,
    depth_band: Optional[tuple[float, float]] = None,
    threads: int = 1,
    progress: Optional[bool] = None,
    on_result: Optional[Callable[[int, Optional[str]], None]] = None,
    **overrides: Any,
) -> EnsembleResult:
    """Runs the realizations of ``seeds`` of ``scene`` on a Dask cluster, resumably, and
    summarises the folder.

    Parameters
    ----------
    scene
        A scene file's path or a dict (see :func:`karstgen.run`); its data files must be
        readable at the same path by every worker.
    seeds
        An int n (the scene's seed and the n − 1 after it), a string as ``--seeds`` takes it
        (``"100..200"``, ``"1,5,7"``) or any iterable of ints.
    client
        A ``dask.distributed.Client``. None: a ``LocalCluster`` of one single-threaded worker
        process per core, closed afterwards (only when there is work).
    out
        The ensemble folder (default ``out/ensemble-<scene name>``). A rerun skips the
        realizations already complete there.
    until
        The stage each realization runs to, with the stages it needs, or ``"all"``; None:
        hydro, what the metrics read.
    keep
        The artifacts each realization keeps beside its record (stage names, ``"all"``);
        the record always holds the metrics, hydro figures and probability cells.
    cell
        Edge of a probability-grid cell, metres.
    depth_band
        ``(min, max)`` metres below ground: ``probability.tif`` counts the conduits within
        that band only; None: at any depth.
    threads
        Threads per task for the Rust work (1: Dask's workers make the parallelism).
    progress
        Show a progress bar (tqdm) on stderr; None: when tqdm is installed.
    on_result
        Called in this process as each realization finishes, with its seed and its error
        (None when complete), in the order they finish.
    **overrides
        Scene fields to change, as for :func:`karstgen.run`.

    A failing realization is recorded with its error (``failures``) and does not stop the
    others; a worker that dies is replaced and its task rescheduled by Dask. Each task holds
    one realization's artifacts in memory at a time, as ``karstgen run`` would
    (docs/ensembles.md gives the peak per scene).
    """
    found = _scene.source(scene, overrides)
    seed_list = _seeds(seeds, found.seed)
    folder = Path(out) if out is not None else Path("out") / f"ensemble-{found.name}"
    plan = (found.path, found.text, str(folder.resolve()), until, float(cell), list(_keep(keep)))
    key = _native.ensemble_prepare(*plan)
    pending = _native.ensemble_pending(*plan, seed_list)
    if pending:
        _compute(plan, key, pending, client, threads, progress, on_result)
    return _summary(folder, len(pending), depth_band)


def _seeds(seeds: Union[int, str, Iterable[int]], first: int) -> list[int]:
    if isinstance(seeds, bool):
        raise TypeError("seeds must be a count, a --seeds string or seeds")
    if isinstance(seeds, int):
        if seeds < 1:
            raise ValueError(f"seeds: at least one realization (got {seeds})")
        return list(range(first, first + seeds))
    if isinstance(seeds, str):
        return _native.parse_seeds(seeds)
    listed = [int(s) for s in seeds]
    if not listed or min(listed) < 0:
        raise ValueError("seeds: give at least one seed, none negative")
    return list(dict.fromkeys(listed))


def _keep(keep: Iterable[str]) -> list[str]:
    if isinstance(keep, str):
        return [keep]
    return list(keep)


def _realize(path: str, text: str, out: str, until: Optional[str], cell: float, keep: list[str], seed: int, threads: int):
    """One Dask task: the realization of ``seed``, its record written; ``(seed, error)``."""
    return _native.realize(path, text, out, until, cell, keep, seed, threads)


def _compute(plan, key, pending, client, threads, progress, on_result) -> None:
    from dask.distributed import as_completed

    own = None
    if client is None:
        client = own = _local_client(min(len(pending), os.cpu_count() or 1))
    bar = _bar(len(pending), progress)
    try:
        futures = {
            client.submit(_realize, *plan, seed, threads, key=f"karstgen-realize-{key[:16]}-{seed}"): seed
            for seed in pending
        }
        for future in as_completed(futures):
            seed = futures[future]
            try:
                _, error = future.result()
            except Exception as e:  # the task could not run (its worker died too often, ...)
                error = f"{type(e).__name__}: {e}"
                _native.record_failure(plan[2], key, seed, error)
            if bar is not None:
                bar.update(1)
            if on_result is not None:
                on_result(seed, error)
    finally:
        if bar is not None:
            bar.close()
        if own is not None:
            cluster = own.cluster
            own.close()
            cluster.close()


def _local_client(workers: int) -> Any:
    """A client of a new ``LocalCluster`` of ``workers`` single-threaded worker processes.

    Its scheduler sends every task to the workers at once (``worker-saturation: inf``) instead
    of queuing them: realizations are independent and small in memory, and a worker then always
    holds its next task, which matters when a realization takes a tenth of a second.
    """
    import dask
    from dask.distributed import Client, LocalCluster

    with dask.config.set({"distributed.scheduler.worker-saturation": float("inf")}):
        cluster = LocalCluster(n_workers=max(1, workers), threads_per_worker=1, processes=True, dashboard_address=None)
    return Client(cluster)


def _bar(total: int, progress: Optional[bool]) -> Any:
    if progress is False:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        if progress:
            raise
        return None
    return tqdm(total=total, desc="ensemble", unit="realization")


def _summary(folder: Path, ran: int, depth_band: Optional[tuple[float, float]] = None) -> EnsembleResult:
    import pandas as pd  # imported on use: Dask workers start faster without it
    import xarray as xr

    summary = _native.ensemble_summarize(str(folder.resolve()), depth_band)
    columns = summary["columns"]
    values = np.frombuffer(summary["rows"], dtype="<f8").reshape(-1, len(columns))
    table = pd.DataFrame(values.copy(), columns=columns)
    table["seed"] = table["seed"].astype("int64")
    _atomically(folder / "summary.parquet", lambda path: table.to_parquet(path, index=False))
    failures = pd.DataFrame(summary["failures"], columns=["seed", "error"]).astype({"seed": "int64"})
    (x0, y0, z0), cell, (nx, ny, nz) = summary["grid"]
    counts = np.frombuffer(summary["counts"], dtype="<u4").reshape(nz, ny, nx).astype(np.int32)
    n = summary["complete"]
    centre = lambda start, count: start + cell * (np.arange(count) + 0.5)  # noqa: E731
    dataset = xr.Dataset(
        {
            "probability": (("z", "y", "x"), (counts / max(n, 1)).astype(np.float32)),
            "count": (("z", "y", "x"), counts),
        },
        coords={"x": centre(x0, nx), "y": centre(y0, ny), "z": centre(z0, nz)},
        attrs={"realizations": n, "cell": cell, "title": "karstgen conduit probability"},
    )
    dataset["probability"].attrs.update(long_name="fraction of realizations with a conduit in the cell")
    dataset["count"].attrs.update(long_name="realizations with a conduit in the cell")
    for axis in "xyz":
        dataset[axis].attrs.update(units="m", long_name=f"{axis} of the cell centre")
    _atomically(folder / "probability.nc", lambda path: dataset.to_netcdf(path, engine="scipy"))
    return EnsembleResult(out=folder, table=table, failures=failures, probability=dataset, ran=ran)


def _atomically(path: Path, write: Callable[[Path], Any]) -> None:
    """``write`` into a temporary file beside ``path``, then renamed over it."""
    temporary = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        write(temporary)
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
