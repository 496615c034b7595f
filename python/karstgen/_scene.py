"""A scene from Python: a TOML file's path or a dict with the file's structure, plus overrides.

Overrides are keyword arguments of :func:`karstgen.run` and :func:`karstgen.ensemble`: a
section given as a dict changes only the fields it names (``skeleton={"gamma": 1.8}``), and a
double underscore reaches into a section (``skeleton__gamma=1.8``,
``keypoints__0__position=[10, 20, 5]``).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any, NamedTuple, Union

from . import _native

#: What :func:`karstgen.run` accepts as a scene.
SceneLike = Union[str, "os.PathLike[str]", Mapping[str, Any]]


class SceneSource(NamedTuple):
    """A checked scene: the path naming it (data files are read relative to its folder), its
    TOML text, its name and its seed. Plain values, so that a Dask task can carry it."""

    path: str
    text: str
    name: str
    seed: int


def source(scene: SceneLike, overrides: Mapping[str, Any]) -> SceneSource:
    """The scene ``scene`` with ``overrides`` applied, checked as ``karstgen run`` checks a
    file; raises :class:`karstgen.SceneError` naming the file, line and field."""
    changes = json.dumps(flatten(overrides), default=_plain)
    if isinstance(scene, (str, os.PathLike)):
        path = str(Path(scene).resolve())
        found = _native.scene_source(path, None, changes, os.getcwd())
    elif isinstance(scene, Mapping):
        found = _native.scene_source(None, json.dumps(scene, default=_plain), changes, os.getcwd())
    else:
        raise TypeError(f"scene must be a path or a dict, not {type(scene).__name__}")
    path, text, name, seed = found
    return SceneSource(str(path), text, name, seed)


def flatten(overrides: Mapping[str, Any]) -> list[tuple[str, Any]]:
    """``[(dotted field, value)]`` of keyword overrides (see the module's docs)."""
    fields: list[tuple[str, Any]] = []

    def walk(prefix: str, value: Any) -> None:
        if isinstance(value, Mapping):
            for key, inner in value.items():
                walk(f"{prefix}.{key}", inner)
        else:
            fields.append((prefix, value))

    for key, value in overrides.items():
        walk(key.replace("__", "."), value)
    return fields


def _plain(value: Any) -> Any:
    """NumPy scalars and arrays as plain Python values for JSON."""
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"{value!r} ({type(value).__name__}) has no TOML value")
