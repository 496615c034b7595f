"""Issue 19's budgets, in paired alternating runs (BENCHMARKS.md):

1. Python's overhead per run: `karstgen.run(default scene, until="skeleton")` in this process
   against the `karstgen run --to skeleton` command, both forced to rerun every stage, same
   output folder kind; CPU seconds (this process's, or the child's) and wall seconds.
2. Ensemble speed-up: 64 realizations of the karstnsim preset up to the skeleton on a
   LocalCluster of 1 and of 2 single-threaded worker processes (cluster started and karstgen
   imported on every worker before the clock), fresh folders each time; wall seconds.

Usage, from the repository root after `cargo xtask test --python` (which builds and installs
the wheel and the command):
    .venv/bin/python python/bench/bench.py [--pairs 5] [--karstgen target/release/karstgen]
"""

import argparse
import importlib
import resource
import shutil
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import karstgen

ROOT = Path(__file__).resolve().parents[2]
DEFAULT = ROOT / "fixtures/scenes/default.toml"
KARSTNSIM = ROOT / "fixtures/scenes/karstnsim.toml"


def cpu(who):
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime


def python_run(out):
    start, cpu0 = time.perf_counter(), cpu(resource.RUSAGE_SELF)
    karstgen.run(DEFAULT, out=out, until="skeleton", force=True)
    return time.perf_counter() - start, cpu(resource.RUSAGE_SELF) - cpu0


def command_run(binary, out):
    start, cpu0 = time.perf_counter(), cpu(resource.RUSAGE_CHILDREN)
    subprocess.run([binary, "run", DEFAULT, "--out", out, "--to", "skeleton", "--force"], check=True, capture_output=True)
    return time.perf_counter() - start, cpu(resource.RUSAGE_CHILDREN) - cpu0


def overhead(binary, pairs, scratch):
    python, command = [], []
    for _ in range(pairs):
        command.append(command_run(binary, scratch / "cli"))
        python.append(python_run(scratch / "py"))
    for name, runs in (("command", command), ("python", python)):
        wall = statistics.median(r[0] for r in runs)
        seconds = statistics.median(r[1] for r in runs)
        print(f"default to skeleton, {name:<8} median of {pairs}: {wall:.3f} s wall, {seconds:.3f} s CPU")
    ratio = statistics.median(p[1] / c[1] for p, c in zip(python, command))
    wall = statistics.median(p[0] / c[0] for p, c in zip(python, command))
    print(f"python / command, median of the pairs: CPU {ratio:.3f}, wall {wall:.3f} (budget ≤ 1.05)")


def ensemble_seconds(workers, scratch, tag):
    from karstgen._ensemble import _local_client

    # The cluster `karstgen.ensemble` starts when given no client (tasks sent to the workers
    # at once).
    client = _local_client(workers)
    with client.cluster, client:
        # Workers up and the package imported on each, as in a cluster that has run a
        # realization before: the clock measures realizations, not Python's start-up.
        client.run(importlib.import_module, "karstgen")
        out = scratch / f"ensemble-{workers}-{tag}"
        start = time.perf_counter()
        result = karstgen.ensemble(KARSTNSIM, 64, client=client, out=out, until="skeleton", keep=(), progress=False)
        seconds = time.perf_counter() - start
    assert result.ran == 64 and result.failures.empty
    shutil.rmtree(out)
    return seconds


def speedup(pairs, scratch):
    one, two = [], []
    for i in range(pairs):
        one.append(ensemble_seconds(1, scratch, i))
        two.append(ensemble_seconds(2, scratch, i))
    print(f"64 karstnsim realizations to skeleton, 1 worker: {[round(s, 2) for s in one]} s")
    print(f"64 karstnsim realizations to skeleton, 2 workers: {[round(s, 2) for s in two]} s")
    ratios = [a / b for a, b in zip(one, two)]
    print(f"speed-up, median of the pairs: {statistics.median(ratios):.2f} (budget ≥ 1.7)")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pairs", type=int, default=5)
    parser.add_argument("--karstgen", default=str(ROOT / "target/release/karstgen"))
    parser.add_argument("--only", choices=["overhead", "speedup"])
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="karstgen-bench-") as scratch:
        scratch = Path(scratch)
        if args.only in (None, "overhead"):
            overhead(args.karstgen, args.pairs, scratch)
        if args.only in (None, "speedup"):
            speedup(args.pairs, scratch)


if __name__ == "__main__":
    main()
