"""Type stubs of karstgen's extension module (python/src/*.rs); the public API is karstgen's."""

from os import PathLike
from typing import Optional, Union

_Path = Union[str, PathLike[str]]

VERSION: str
STAGES: list[str]
STAGE_FILES: list[tuple[str, str]]

class KarstgenError(Exception):
    """A failure of karstgen or of the machine (the command line's exit code 1)."""

class SceneError(KarstgenError):
    """The scene (or a data file it names) is wrong; the message names the file, line and field."""

class ArtifactError(KarstgenError):
    """An artifact is missing, corrupted or inconsistent; the message says which stage to rerun."""

def scene_source(
    path: Optional[_Path], table_json: Optional[str], overrides_json: str, folder: _Path
) -> tuple[str, str, str, int]: ...
def run(
    path: _Path,
    text: str,
    out: _Path,
    until: Optional[str] = None,
    seed: Optional[int] = None,
    force: bool = False,
    threads: Optional[int] = None,
) -> list[tuple[str, str, float, str]]: ...
def read_network(out: _Path) -> dict[str, object]: ...
def read_mesh(path: _Path, surface: str) -> tuple[bytes, bytes, int, int]: ...
def read_payload(path: _Path) -> str: ...
def figures(out: _Path, seed: int) -> tuple[list[str], list[float]]: ...
def characterize(nodes: bytes, links: bytes) -> list[tuple[str, float]]: ...
def ensemble_prepare(
    path: _Path, text: str, out: _Path, until: Optional[str], cell: float, keep: list[str]
) -> str: ...
def ensemble_pending(
    path: _Path, text: str, out: _Path, until: Optional[str], cell: float, keep: list[str], seeds: list[int]
) -> list[int]: ...
def realize(
    path: _Path,
    text: str,
    out: _Path,
    until: Optional[str],
    cell: float,
    keep: list[str],
    seed: int,
    threads: Optional[int] = 1,
) -> tuple[int, Optional[str]]: ...
def record_failure(out: _Path, key: str, seed: int, error: str) -> None: ...
def ensemble_summarize(out: _Path, depth_band: Optional[tuple[float, float]] = None) -> dict[str, object]: ...
def parse_seeds(spec: str) -> list[int]: ...

#: One candidate on one seed: karstnet's ten metrics (NaN: undefined), or (stage, error).
_RunResult = Union[list[float], tuple[str, str]]

class Calibration:
    """The Rust calibration search (CMA-ES) of a scene towards a target, step by step."""

    def __init__(
        self, path: _Path, text: str, like: Optional[str] = None, target: Optional[list[_Path]] = None
    ) -> None: ...
    @property
    def seeds(self) -> list[int]: ...
    @property
    def names(self) -> list[str]: ...
    def ask(self) -> Optional[list[Optional[list[float]]]]: ...
    def evaluate(
        self, candidates: list[Optional[list[float]]], threads: Optional[int] = None
    ) -> list[list[_RunResult]]: ...
    def tell(self, runs: list[list[_RunResult]]) -> None: ...
    def finish(self, out: _Path) -> str: ...

def calibrate_evaluate(
    path: _Path,
    text: str,
    names: list[str],
    values: Optional[list[float]],
    seed: int,
    threads: Optional[int] = 1,
) -> _RunResult: ...
