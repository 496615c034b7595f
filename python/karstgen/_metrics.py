"""karstnet's network statistics of any network, a drop-in for ``KGraph.characterize_graph``."""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

from . import _native

#: The keys of karstnet 1.2.5's ``characterize_graph()``, in its order.
CHARACTERIZE_KEYS = (
    "mean length",
    "cv length",
    "length entropy",
    "tortuosity",
    "orientation entropy",
    "aspl",
    "cpd",
    "mean degree",
    "cv degree",
    "correlation vertex degree",
)


def metrics(nodes: Any, edges: Optional[Any] = None, *, all: bool = False) -> dict[str, float]:
    """karstnet 1.2.5's ``characterize_graph()`` values of a network (identical within 1e-9;
    undefined values are NaN), in a dict with its keys.

    ``metrics(nodes, edges)``: ``nodes`` an (N, 3) or (N, 2) array of coordinates (2D
    networks get z = 0, as in karstnet), ``edges`` an (M, 2) array of 0-based node indices
    (order and direction do not matter, duplicates collapse, nodes in no edge are ignored).
    ``metrics(kgraph)``: a karstnet ``KGraph``, read through its ``graph`` and ``pos3d``.

    With ``all=True`` the dict also holds every other statistic of ``metrics.json`` (counts,
    Howard's parameters, DC, Sturges entropies, length-weighted aspl, degree fractions). The
    length-weighted aspl depends, as karstnet's does, on the order of the nodes and edges: give
    them in the order of karstnet's input files to get karstnet's value (a ``KGraph`` does not
    keep its links' order).

    Raises ``ValueError`` for a network karstnet would get wrong or fail on: no edge, an index
    out of range, a self-loop, a non-finite coordinate.
    """
    if edges is None:
        nodes, edges = _from_kgraph(nodes)
    coordinates = np.asarray(nodes, dtype=np.float64)
    if coordinates.ndim != 2 or coordinates.shape[1] not in (2, 3):
        raise ValueError(f"nodes must be an (N, 3) or (N, 2) array, not {coordinates.shape}")
    if coordinates.shape[1] == 2:
        coordinates = np.column_stack([coordinates, np.zeros(len(coordinates))])
    links = np.asarray(edges)
    if links.size == 0:
        links = links.reshape(0, 2)
    if links.ndim != 2 or links.shape[1] != 2 or not np.issubdtype(links.dtype, np.integer):
        raise ValueError(f"edges must be an (M, 2) array of node indices, not {links.shape} {links.dtype}")
    values = _native.characterize(
        np.ascontiguousarray(coordinates, dtype="<f8").tobytes(),
        np.ascontiguousarray(links, dtype="<i8").tobytes(),
    )
    result = dict(values)
    if all:
        return result
    return {k: result[k] for k in CHARACTERIZE_KEYS}


def _from_kgraph(kgraph: Any) -> tuple[np.ndarray, np.ndarray]:
    """Node coordinates and 0-based edges of a karstnet ``KGraph``, nodes in the order of its
    coordinates (the order of karstnet's input files, which its length-weighted aspl depends
    on)."""
    if not (hasattr(kgraph, "graph") and hasattr(kgraph, "pos3d")):
        raise TypeError("metrics(kgraph) needs a karstnet KGraph; for arrays call metrics(nodes, edges)")
    order = list(kgraph.pos3d)
    order += [node for node in kgraph.graph.nodes if node not in kgraph.pos3d]
    index = {node: i for i, node in enumerate(order)}
    missing = [node for node in order if node not in kgraph.pos3d]
    if missing:
        raise ValueError(f"the KGraph has no coordinates for node {missing[0]!r}")
    nodes = np.array([list(kgraph.pos3d[node])[:3] for node in order], dtype=np.float64).reshape(-1, 3)
    edges = np.array([(index[a], index[b]) for a, b in kgraph.graph.edges], dtype=np.int64).reshape(-1, 2)
    return nodes, edges
