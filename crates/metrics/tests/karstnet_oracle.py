"""Oracle for the karst-metrics tests: run karstnet 1.2.5 on one network and print every metric
that karst-metrics computes, as one JSON object on stdout (non-finite values as null).

Usage: karstnet_oracle.py BASE        reads BASE_nodes.dat / BASE_links.dat (1-based links)
       karstnet_oracle.py FILE.pl     reads a GOCAD PLine
karstnet's own printing is suppressed and matplotlib runs headless. The time taken by loading
and characterising (imports excluded) is printed on stderr as `karstnet seconds: S`.
"""
import contextlib
import io
import json
import math
import os
import sys
import time
import warnings

os.environ.setdefault("MPLBACKEND", "Agg")
warnings.filterwarnings("ignore")

import numpy as np  # noqa: E402

if not hasattr(np, "float_"):  # karstnet 1.2.5 from_pline uses the NumPy 1 alias
    np.float_ = np.float64

import karstnet as kn  # noqa: E402
import networkx as nx  # noqa: E402


def load(path):
    with contextlib.redirect_stdout(io.StringIO()):
        if path.endswith(".pl"):
            return kn.from_pline(path, verbose=False)
        return kn.from_nodlink_dat(path, verbose=False)


def metrics(kg):
    g, gs = kg.graph, kg.graph_simpl
    with contextlib.redirect_stdout(io.StringIO()):
        out = dict(kg.characterize_graph(verbose=False))
        out["length entropy sturges"] = kg.length_entropy(mode="sturges")
        out["orientation entropy sturges"] = kg.orientation_entropy(mode="sturges")
        out["aspl length weighted"] = kg.average_SPL(dist_weight=True)
    n, s = gs.number_of_nodes(), gs.number_of_edges()
    p = nx.number_connected_components(gs)
    cycles = s - n + p
    # IEEE division (a 2-node reduced graph has an infinite gamma, as in karst-metrics).
    alpha, beta, gamma = (np.float64(a) / np.float64(b) for a, b in ((cycles, 2 * n - 5), (s, n), (s, 3 * (n - 2))))
    degrees = [d for _, d in gs.degree()]
    counts = {
        "1": sum(d == 1 for d in degrees),
        "2": sum(d == 2 for d in degrees),
        "3": sum(d == 3 for d in degrees),
        ">3": sum(d > 3 for d in degrees),
    }
    out.update({
        "n_nodes_full": g.number_of_nodes(),
        "n_edges_full": g.number_of_edges(),
        "n_components_full": nx.number_connected_components(g),
        "n_nodes_simpl": n,
        "n_edges_simpl": s,
        "n_components_simpl": p,
        "n_cycles": cycles,
        "n_branches": len(kg.branches),
        "n_looping_branches": sum(b[0] == b[-1] for b in kg.branches),
        "total_length": float(sum(kg.br_lengths)),
        "howard alpha": alpha,
        "howard beta": beta,
        "howard gamma": gamma,
        "connectivity degree DC (%)":
            100 * (alpha / 0.25 + (beta - 1) / 0.5 + (gamma - 0.33) / 0.17) / 3,
        "simpl max degree": max(degrees),
    })
    for k, c in counts.items():
        out["simpl count deg" + k] = c
        out["simpl frac deg" + k] = c / n
    return out


def clean(v):
    if isinstance(v, int):
        return v
    v = float(v)
    return v if math.isfinite(v) else None


if __name__ == "__main__":
    start = time.perf_counter()
    result = metrics(load(sys.argv[1]))
    seconds = time.perf_counter() - start
    print(json.dumps({k: clean(v) for k, v in result.items()}, indent=1))
    print(f"karstnet seconds: {seconds}", file=sys.stderr)
