"""Calibration from Python: ``karstgen calibrate``'s search (CMA-ES over the scene's
``[calibrate]`` box, docs/calibrate.md) with its candidates run as Dask tasks across workers,
or in this process.

The search stays in this process (``_native.Calibration``, the Rust search's steps): each
generation it proposes parameter values, every (candidate, seed) pair runs as one task
(``_native.calibrate_evaluate``: sampling, cost graph, skeleton and karstnet's metrics in
memory), and the metrics go back to the search in candidate and seed order. The search
depends only on the metrics, so a calibration gives the same candidates, distances and
calibrated scene with a client, without one, and from ``karstgen calibrate``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional, Sequence, Union

from . import _native, _scene

if TYPE_CHECKING:
    import pandas as pd


@dataclass
class CalibrationResult:
    """What :func:`calibrate` returns.

    Attributes
    ----------
    scene : str
        The calibrated scene's TOML text (``calibrated.toml``): the best values, named
        ``<name>-calibrated``, its target recorded in ``[calibrate]``.
    path : Path
        ``calibrated.toml`` in ``out``, ready for :func:`karstgen.run`.
    history : pandas.DataFrame
        One row per candidate evaluated (``iterations.csv``): generation, candidate, sigma,
        distance, the parameter values, the ten metrics (medians over the seeds), failure.
    report : dict
        ``report.json``: distances before and after, the box, each metric's target.
    summary : str
        What ``karstgen calibrate`` prints: the distances, then the calibrated scene's
        verdict against the target and its hints.
    out : Path
        The output folder.
    """

    scene: str
    path: Path
    history: pd.DataFrame
    report: dict
    summary: str
    out: Path


def calibrate(
    scene: _scene.SceneLike,
    like: Optional[str] = None,
    target: Union[str, Path, Sequence[Union[str, Path]], None] = None,
    seeds: Optional[int] = None,
    evaluations: Optional[int] = None,
    minutes: Optional[float] = None,
    client: Any = None,
    out: Union[str, Path, None] = None,
    *,
    threads: Optional[int] = None,
    **overrides: Any,
) -> CalibrationResult:
    """Searches the network parameters of ``scene``'s ``[calibrate]`` box that bring its
    networks closest to a published network (``like``) or a surveyed cave (``target``).

    Parameters
    ----------
    scene
        A scene file's path or a dict (see :func:`karstgen.run`) with a ``[calibrate]`` box;
        its data files must be readable at the same path by every worker.
    like
        A published network (KNdata-public, any case) or ``"surveyed"`` (the median of the 25
        surveyed caves).
    target
        A surveyed cave: karstnet's ``BASE_nodes.dat`` (or ``BASE``), a GOCAD PLine ``.pl``,
        or two CSV files ``(nodes, edges)``. Neither ``like`` nor ``target``: the one the
        scene's ``[calibrate]`` names.
    seeds, evaluations, minutes
        Override ``calibrate.seeds`` (realizations per candidate), ``calibrate.evaluations``
        (candidates, the scene itself included) and ``calibrate.minutes`` (wall clock).
    client
        A ``dask.distributed.Client``: each generation's (candidate, seed) pairs run as tasks
        across its workers. None: in this process, on ``threads`` threads.
    out
        The output folder (default ``out/calibrate-<scene name>``): the same four files as
        ``karstgen calibrate``.
    threads
        Without a client: threads for the candidates (None: every core). With one: threads
        per task (None: 1, the workers make the parallelism).
    **overrides
        Scene fields to change, as for :func:`karstgen.run`.
    """
    import pandas as pd  # imported on use: Dask workers start faster without it
    import json

    if like is not None and target is not None:
        raise ValueError("calibrate: give like or target, not both")
    budget = {"seeds": seeds, "evaluations": evaluations, "minutes": minutes}
    for name, value in budget.items():
        if value is not None:
            overrides[f"calibrate__{name}"] = value
    found = _scene.source(scene, overrides)
    files = _target_files(target)
    search = _native.Calibration(found.path, found.text, like, files)
    folder = Path(out) if out is not None else Path("out") / f"calibrate-{found.name}"
    while (candidates := search.ask()) is not None:
        if client is None:
            runs = search.evaluate(candidates, threads)
        else:
            runs = _on_dask(client, found, search.names, candidates, search.seeds, threads or 1)
        search.tell(runs)
    summary = search.finish(str(folder.resolve()))
    path = folder / "calibrated.toml"
    history = pd.read_csv(folder / "iterations.csv")
    report = json.loads((folder / "report.json").read_text())
    return CalibrationResult(path.read_text(), path, history, report, summary, folder)


def _target_files(target: Union[str, Path, Sequence[Union[str, Path]], None]) -> Optional[list[str]]:
    if target is None:
        return None
    if isinstance(target, (str, Path)):
        return [str(Path(target).resolve())]
    files = [str(Path(t).resolve()) for t in target]
    if len(files) not in (1, 2):
        raise ValueError("target: one network file, or two CSV files (nodes, edges)")
    return files


def _evaluate(path: str, text: str, names: list[str], values: Optional[list[float]], seed: int, threads: int):
    """One Dask task: one candidate on one seed, to its ten metrics or ``(stage, error)``."""
    return _native.calibrate_evaluate(path, text, names, values, seed, threads)


def _on_dask(client, found, names, candidates, seeds, threads) -> list[list[Any]]:
    """Every (candidate, seed) pair of a generation as a task; results in candidate, seed order."""
    futures = [
        [client.submit(_evaluate, found.path, found.text, names, values, seed, threads, pure=False) for seed in seeds]
        for values in candidates
    ]
    results = client.gather(futures)
    return [[_plain(r) for r in row] for row in results]


def _plain(result: Any) -> Any:
    """A task's result as the search takes it: a list of ten floats, or (stage, message)."""
    if isinstance(result, tuple):
        return result
    return [float(v) for v in result]
