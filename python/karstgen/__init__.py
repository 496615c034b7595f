"""karstgen: geologically coherent 3D karst cave networks, from Python.

The pipeline (sampling → costgraph → skeleton → hydro → sdf → mesher → metrics) runs in this
process from the same Rust crates as the ``karstgen`` command, with the GIL released:

>>> import karstgen
>>> run = karstgen.run("fixtures/scenes/tiny.toml", until="hydro")   # doctest: +SKIP
>>> run.network.nodes.shape, run.metrics["aspl"]                     # doctest: +SKIP

- :func:`run` / :func:`load` and :class:`Run`: a run's network (NumPy arrays, pandas
  DataFrames, networkx, karstnet), hydro, metrics and meshes;
- :func:`metrics`: karstnet's ``characterize_graph`` of any network, identical to karstnet;
- :func:`ensemble`: many seeds on a Dask cluster, resumable, summarised to Parquet and an
  xarray probability volume;
- :func:`calibrate`: the scene's ``[calibrate]`` box searched towards a published network or a
  surveyed cave, its candidates on a Dask cluster or in this process.

Errors are exceptions: :class:`SceneError` (the scene; names file, line and field),
:class:`ArtifactError` (an artifact), :class:`KarstgenError` (karstgen or the machine).
Guides: docs/python.md and docs/ensembles.md.
"""

from ._native import VERSION as __version__
from ._native import ArtifactError, KarstgenError, SceneError
from ._native import STAGES as _STAGES
from ._calibrate import CalibrationResult, calibrate
from ._ensemble import EnsembleResult, ensemble
from ._metrics import CHARACTERIZE_KEYS, metrics
from ._network import Network
from ._run import Run, StageLine, load, run

#: The stages, in pipeline order.
STAGES: tuple[str, ...] = tuple(_STAGES)

__all__ = [
    "ArtifactError",
    "CHARACTERIZE_KEYS",
    "CalibrationResult",
    "EnsembleResult",
    "KarstgenError",
    "Network",
    "Run",
    "STAGES",
    "SceneError",
    "StageLine",
    "__version__",
    "calibrate",
    "ensemble",
    "load",
    "metrics",
    "run",
]
