"""What the tests of the Python package share: the repository's folders, the `karstgen`
command built from the same workspace (env KARSTGEN_BIN, set by `cargo xtask test`), and one
Dask LocalCluster of two worker processes for the ensemble tests."""

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "fixtures" / "scenes" / "tiny.toml"
DEFAULT = ROOT / "fixtures" / "scenes" / "default.toml"


def karstgen_command(*args, check=True):
    """Runs the `karstgen` command of this workspace; fails when `cargo xtask test` did not
    say where it is."""
    binary = os.environ.get("KARSTGEN_BIN")
    if not binary or not Path(binary).exists():
        pytest.fail("set KARSTGEN_BIN to the karstgen command of this workspace (cargo xtask test does this)")
    return subprocess.run([binary, *map(str, args)], check=check, capture_output=True, text=True)


@pytest.fixture(scope="session")
def cluster():
    """A real LocalCluster: two single-threaded worker processes (with nannies that restart
    a killed worker)."""
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as local:
        with Client(local) as client:
            yield client
