"""A run's conduit network as NumPy arrays and pandas DataFrames, and as networkx and karstnet
graphs."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from . import _native

if TYPE_CHECKING:
    import pandas as pd


class Network:
    """The conduit network of a run, read from its ``skeleton.json`` (and ``hydro.json`` when
    hydro ran on this skeleton).

    Attributes
    ----------
    nodes : numpy.ndarray
        (N, 3) float64 node coordinates x, y, z in metres, the artifact's values bit for bit.
    edges : numpy.ndarray
        (M, 2) int64 0-based node indices of every segment, ``source < target``, conduit by
        conduit (``network_links.dat`` holds the same links, sorted, 1-based).
    node_table : pandas.DataFrame
        One row per node: ``x``, ``y``, ``z``, ``zone`` (vadose, phreatic), ``keypoint`` (name
        or None), ``sample``; with hydro ``role`` (source, well, branch, pool, dry) and
        ``inflow``.
    edge_table : pandas.DataFrame
        One row per segment, as ``edges``: ``source``, ``target``, ``conduit``, ``type``
        (conduit type), ``radius_source``, ``radius_target`` (m), ``phase``; with hydro
        ``flow`` (network units), ``discharge`` (m³/s), ``water_type``, ``towards_target``
        (water runs from source to target), ``speed`` (m/s), ``depth``, ``width`` (m),
        ``slope`` (rad).
    conduit_table : pandas.DataFrame
        One row per conduit: ``first_node``, ``last_node``, ``segments``, ``length`` (m),
        ``phase``, ``keypoints`` (names at its ends, comma-separated); with hydro ``flow`` and
        ``dry``.
    """

    nodes: np.ndarray
    edges: np.ndarray
    node_table: pd.DataFrame
    edge_table: pd.DataFrame
    conduit_table: pd.DataFrame

    def __init__(self, out: str) -> None:
        raw = _native.read_network(out)
        self.nodes = np.frombuffer(raw["nodes"], dtype="<f8").reshape(-1, 3).copy()
        self.edges = np.frombuffer(raw["edges"], dtype="<i8").reshape(-1, 2).copy()
        self.node_table = _frame(raw["node_columns"])
        self.edge_table = _frame(raw["edge_columns"])
        self.conduit_table = _frame(raw["conduit_columns"])

    @property
    def has_hydro(self) -> bool:
        """True when the tables hold the water of the hydro stage."""
        return "flow" in self.edge_table.columns

    def __repr__(self) -> str:
        water = ", with hydro" if self.has_hydro else ""
        return f"<Network: {len(self.nodes)} nodes, {len(self.edges)} segments, {len(self.conduit_table)} conduits{water}>"

    def to_networkx(self) -> Any:
        """The network as an undirected ``networkx.Graph``: nodes 0..N-1 with the node table's
        columns as attributes (plus ``pos``, the (x, y, z) tuple), edges with the edge table's."""
        import networkx as nx

        graph = nx.Graph()
        for i, row in enumerate(self.node_table.to_dict("records")):
            graph.add_node(i, pos=(row["x"], row["y"], row["z"]), **row)
        for row in self.edge_table.to_dict("records"):
            graph.add_edge(int(row["source"]), int(row["target"]), **row)
        return graph

    def to_karstnet(self, verbose: bool = False) -> Any:
        """The network as a karstnet ``KGraph`` (needs the ``karstnet`` package), nodes
        numbered 0..N-1 as in karstnet's own readers."""
        import karstnet

        coordinates = {i: list(p) for i, p in enumerate(self.nodes.tolist())}
        return karstnet.KGraph(self.edges.tolist(), coordinates, {}, verbose=verbose)


def _frame(columns: list[tuple[str, str, Any]]) -> pd.DataFrame:
    import pandas as pd  # imported on use: Dask workers start faster without it

    data: dict[str, Any] = {}
    for name, dtype, values in columns:
        if dtype == "str":
            data[name] = pd.Series(values, dtype="object")
        else:
            data[name] = np.frombuffer(values, dtype=np.dtype(dtype).newbyteorder("<")).copy()
    return pd.DataFrame(data)
