"""karstgen.ensemble on a real LocalCluster: the same table as sequential runs, a killed
worker, a rerun that does no work, failures recorded, the outputs read by the programs they
are for (pyarrow, xarray, VTK) and interchangeable with the command line's."""

import os
import signal

import numpy as np
import pandas as pd
import pytest

import karstgen
from conftest import TINY, karstgen_command

SEEDS = list(range(20, 28))


def same(a, b):
    return a == b or (np.isnan(a) and np.isnan(b))


@pytest.fixture(scope="module")
def finished(cluster, tmp_path_factory):
    """8 seeds of the tiny scene to hydro on two worker processes; a worker is killed when
    the first realization arrives."""
    out = tmp_path_factory.mktemp("ensemble")
    pids = list(cluster.run(os.getpid).values())
    arrived = []

    def kill_a_worker(seed, error):
        if not arrived:
            os.kill(pids[0], signal.SIGKILL)
        arrived.append((seed, error))

    result = karstgen.ensemble(TINY, SEEDS, client=cluster, out=out, progress=False, on_result=kill_a_worker)
    cluster.wait_for_workers(2)
    assert pids[0] not in cluster.run(os.getpid).values(), "the killed worker was replaced"
    return out, result, arrived


def test_the_table_equals_sequential_runs(finished):
    _, result, arrived = finished
    assert sorted(seed for seed, _ in arrived) == SEEDS
    assert all(error is None for _, error in arrived), arrived
    assert result.ran == 8 and result.failures.empty
    assert result.table["seed"].tolist() == SEEDS
    for seed, row in zip(SEEDS, result.table.to_dict("records")):
        alone = karstgen.run(TINY, until="hydro", seed=seed).metrics
        assert set(alone) == set(row) - {"seed"}
        for column, value in alone.items():
            assert same(row[column], value), (seed, column, row[column], value)


def test_the_outputs_open_in_their_programs(finished):
    out, result, _ = finished
    assert pd.read_parquet(out / "summary.parquet").equals(result.table)
    import xarray as xr

    volume = xr.open_dataset(out / "probability.nc", engine="scipy")
    assert volume.attrs["realizations"] == 8
    assert np.array_equal(volume["probability"].values, result.probability["probability"].values)
    assert volume["probability"].max() > 0 and volume["probability"].max() <= 1
    assert int(volume["count"].max()) <= 8

    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    reader = vtk.vtkXMLImageDataReader()
    reader.SetFileName(str(out / "probability.vti"))
    reader.Update()
    image = reader.GetOutput()
    nz, ny, nx = volume["probability"].shape
    assert image.GetDimensions() == (nx + 1, ny + 1, nz + 1)
    cell = result.probability.attrs["cell"]
    assert image.GetSpacing() == (cell, cell, cell)
    assert image.GetOrigin() == pytest.approx(tuple(volume[a].values[0] - cell / 2 for a in "xyz"))
    probability = vtk_to_numpy(image.GetCellData().GetArray("probability")).reshape(nz, ny, nx)
    assert np.array_equal(probability, volume["probability"].values)
    assert image.GetCellData().GetScalars().GetName() == "probability"
    assert image.GetFieldData().GetArray("realizations").GetValue(0) == 8


def test_a_rerun_does_no_work(finished, cluster):
    out, result, _ = finished
    records = sorted((out / "realizations").glob("seed-*/record.json"))
    assert len(records) == 8
    before = [r.stat().st_mtime_ns for r in records]
    called = []
    again = karstgen.ensemble(TINY, SEEDS, client=cluster, out=out, progress=False, on_result=lambda *a: called.append(a))
    assert again.ran == 0 and not called
    assert [r.stat().st_mtime_ns for r in records] == before
    assert again.table.equals(result.table)


def test_the_command_line_reads_and_merges_a_dask_folder(finished, tmp_path):
    out, result, _ = finished
    karstgen_command("ensemble", TINY, "--seeds", "28..30", "--out", tmp_path / "cli", "--keep", "skeleton")
    merged = tmp_path / "merged"
    karstgen_command("ensemble", "merge", out, tmp_path / "cli", "--out", merged)
    table = pd.read_csv(merged / "metrics.csv")
    assert table["seed"].tolist() == SEEDS + [28, 29]
    assert np.allclose(table.iloc[:8, 1:].to_numpy(float), result.table.iloc[:, 1:].to_numpy(float), equal_nan=True, rtol=1e-15)


def test_a_failing_realization_is_recorded_and_the_others_complete(cluster, tmp_path):
    out = tmp_path / "failing"
    # A folder where seed 41's samples.bin must go: that realization cannot write it.
    (out / "realizations" / "seed-41" / "samples.bin" / "blocked").mkdir(parents=True)
    result = karstgen.ensemble(TINY, [40, 41, 42], client=cluster, out=out, until="skeleton", keep=(), progress=False)
    assert result.table["seed"].tolist() == [40, 42]
    assert result.failures["seed"].tolist() == [41]
    assert "samples.bin" in result.failures["error"][0]
    assert "water length" not in " ".join(result.table.columns), "no hydro columns without hydro"
    assert sorted(p.name for p in (out / "realizations" / "seed-40").iterdir()) == ["record.json"]


def test_seeds_and_scenes_are_checked(tmp_path):
    with pytest.raises(karstgen.SceneError):
        karstgen.ensemble({"name": "x"}, 2, out=tmp_path / "a")
    with pytest.raises(ValueError, match="empty"):
        karstgen.ensemble(TINY, "5..5", out=tmp_path / "b")
    with pytest.raises(ValueError, match="at least one"):
        karstgen.ensemble(TINY, 0, out=tmp_path / "c")
    with pytest.raises(ValueError, match="skeleton"):
        karstgen.ensemble(TINY, 2, out=tmp_path / "d", until="costgraph")
