"""Running the pipeline from Python (:func:`run`) and reading a run's outputs (:class:`Run`,
:func:`load`)."""

from __future__ import annotations

import json
import shutil
import tempfile
from pathlib import Path
from typing import Any, NamedTuple, Optional, Union

import numpy as np

from . import _native, _scene
from ._network import Network


class StageLine(NamedTuple):
    """What happened to one stage of a run, as ``karstgen run`` prints it."""

    stage: str
    status: str  # "ran" or "up to date"
    seconds: float
    headline: str


class Run:
    """The outputs of one run of the pipeline: the artifacts in :attr:`out`, read on demand.

    Made by :func:`run` (which may keep the artifacts in a temporary folder until the object
    goes) and :func:`load` (a folder written by ``karstgen run`` or :meth:`write`).
    """

    def __init__(
        self,
        out: Union[str, Path],
        report: Optional[list[StageLine]] = None,
        seed: Optional[int] = None,
        _temporary: Optional[tempfile.TemporaryDirectory] = None,
    ) -> None:
        self.out = Path(out)
        #: One line per stage of the run that made this object (None for :func:`load`).
        self.report = report
        #: The seed of the run, when known.
        self.seed = seed
        self._temporary = _temporary
        self._network: Optional[Network] = None

    def __repr__(self) -> str:
        stages = [s for s in _native.STAGES if self.artifact(s).exists()]
        return f"<Run {self.out}: {', '.join(stages) or 'no artifact'}>"

    def artifact(self, stage: str) -> Path:
        """The path of ``stage``'s artifact (``skeleton`` → ``out/skeleton.json``)."""
        files = dict(_native.STAGE_FILES)
        if stage not in files:
            raise ValueError(f"unknown stage {stage!r}; stages: {', '.join(files)}")
        return self.out / files[stage]

    @property
    def network(self) -> Network:
        """The conduit network (arrays and DataFrames); see :class:`Network`."""
        if self._network is None:
            self._network = Network(str(self.out))
        return self._network

    def payload(self, stage: str) -> dict[str, Any]:
        """The payload of a JSON artifact (``skeleton``, ``hydro``, ``metrics``) as a dict,
        after the same checks as every stage makes (raises :class:`ArtifactError`)."""
        return json.loads(_native.read_payload(str(self.artifact(stage))))

    @property
    def hydro(self) -> Optional[dict[str, Any]]:
        """The hydro payload (flow, water type and geometry of every segment, sinks,
        springs; docs/hydro.md), or None when hydro has not run."""
        return self.payload("hydro") if self.artifact("hydro").exists() else None

    @property
    def metrics(self) -> dict[str, float]:
        """karstnet's statistics of the network under karstnet's key names, then the lengths
        per zone (``vadose length``), conduit type (``tube length``) and, when hydro ran, water
        type (``stream water length``) and each spring's ``discharge (m3/s)``: the columns of
        an ensemble's summary table."""
        columns, values = _native.figures(str(self.out), self.seed or 0)
        return {c: v for c, v in zip(columns, values) if c != "seed"}

    def mesh(self, surface: str = "cave") -> tuple[np.ndarray, np.ndarray]:
        """``(vertices, faces)`` of one surface of the mesh artifact, ``cave``, ``terrain`` or
        ``water``: float32 (V, 3) in metres and uint32 (F, 3), counter-clockwise seen from
        outside the solid."""
        vertices, faces, nv, nf = _native.read_mesh(str(self.artifact("mesher")), surface)
        return (
            np.frombuffer(vertices, dtype="<f4").reshape(nv, 3).copy(),
            np.frombuffer(faces, dtype="<u4").reshape(nf, 3).copy(),
        )

    def to_networkx(self) -> Any:
        """The network as a ``networkx.Graph`` (see :meth:`Network.to_networkx`)."""
        return self.network.to_networkx()

    def to_karstnet(self, verbose: bool = False) -> Any:
        """The network as a karstnet ``KGraph`` (see :meth:`Network.to_karstnet`)."""
        return self.network.to_karstnet(verbose=verbose)

    def write(self, folder: Union[str, Path]) -> Path:
        """Copies every output of the run into ``folder`` (created if needed), which then
        reads with :func:`load` and ``karstgen inspect``; returns the folder."""
        folder = Path(folder)
        if folder.resolve() != self.out.resolve():
            shutil.copytree(self.out, folder, dirs_exist_ok=True)
        return folder


def run(
    scene: _scene.SceneLike,
    out: Union[str, Path, None] = None,
    until: Optional[str] = None,
    seed: Optional[int] = None,
    *,
    force: bool = False,
    threads: Optional[int] = None,
    **overrides: Any,
) -> Run:
    """Runs the pipeline on ``scene`` and returns its :class:`Run`.

    Parameters
    ----------
    scene
        A scene file's path, or a dict with the TOML file's structure (data files relative
        to the working folder).
    out
        The output folder; stages whose artifact there is up to date are skipped, as with
        ``karstgen run``. None: a temporary folder that lives as long as the returned object
        (keep the outputs with :meth:`Run.write`).
    until
        The last stage to run (``"skeleton"`` runs sampling, costgraph and skeleton); None:
        every stage.
    seed
        The seed, instead of the scene's.
    force
        Rerun every stage even when up to date.
    threads
        Threads for the Rust work (None: every core).
    **overrides
        Scene fields to change: ``skeleton={"gamma": 1.8}`` or ``skeleton__gamma=1.8``.

    Raises
    ------
    SceneError
        The scene is wrong (the message names the file, line and field).
    ArtifactError
        An artifact in ``out`` is corrupted or inconsistent.
    KarstgenError
        karstgen or the machine failed (a write, a bug).
    KeyboardInterrupt
        On Ctrl-C, at once; the pipeline stops before its next stage.
    """
    found = _scene.source(scene, overrides)
    temporary = None
    if out is None:
        temporary = tempfile.TemporaryDirectory(prefix="karstgen-run-")
        out = temporary.name
    lines = _native.run(found.path, found.text, str(out), until, seed, force, threads)
    report = [StageLine(*line) for line in lines]
    return Run(out, report, seed if seed is not None else found.seed, temporary)


def load(out: Union[str, Path]) -> Run:
    """The :class:`Run` of an output folder written by ``karstgen run`` (or :meth:`Run.write`);
    raises :class:`ArtifactError` when it holds no readable skeleton."""
    loaded = Run(out)
    loaded.network  # noqa: B018 - reads and checks the skeleton now
    return loaded
