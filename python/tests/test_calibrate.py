"""karstgen.calibrate: the Rust search with its candidates in this process or on a real
LocalCluster of two workers gives the same history and calibrated scene, the same as
`karstgen calibrate`; bad aims raise."""

import pandas as pd
import pytest

import karstgen
from conftest import ROOT, TINY, karstgen_command

#: A box of two parameters, two seeds, two generations of three candidates.
BOX = """
[calibrate]
seeds = 2
evaluations = 7
population = 3

[[calibrate.parameters]]
name = "skeleton.amplification_points"
min = 0
max = 8

[[calibrate.parameters]]
name = "skeleton.tortuosity"
min = 0.0
max = 1.0
"""


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    path = tmp_path_factory.mktemp("calibrate") / "scene.toml"
    text = TINY.read_text().replace('"data/', f'"{TINY.parent}/data/')
    path.write_text(text + BOX)
    return path


@pytest.fixture(scope="module")
def in_process(scene, tmp_path_factory):
    return karstgen.calibrate(scene, like="Sakany", out=tmp_path_factory.mktemp("alone"))


def test_the_history_is_the_searchs(in_process):
    history = in_process.history
    assert len(history) == 7
    assert history["generation"].tolist() == [0, 1, 1, 1, 2, 2, 2]
    assert list(history.columns[4:6]) == ["skeleton.amplification_points", "skeleton.tortuosity"]
    assert list(history.columns[6:16]) == list(karstgen.CHARACTERIZE_KEYS)
    assert in_process.report["distance"]["after"] == history["distance"].min()
    assert in_process.report["target"] == "Sakany"
    assert 'like = "Sakany"' in in_process.scene, "the calibrated scene records its target"
    assert in_process.summary.splitlines()[1].startswith("verdict of the calibrated scene: ")


def test_a_dask_cluster_gives_the_same_calibration(in_process, scene, cluster, tmp_path):
    on_dask = karstgen.calibrate(scene, like="Sakany", client=cluster, out=tmp_path)
    pd.testing.assert_frame_equal(on_dask.history, in_process.history)
    assert on_dask.scene == in_process.scene
    assert on_dask.report == in_process.report
    assert on_dask.summary.splitlines()[1:] == in_process.summary.splitlines()[1:]


def test_the_command_line_gives_the_same_calibration(in_process, scene, tmp_path):
    karstgen_command("calibrate", scene, "--like", "Sakany", "--out", tmp_path)
    assert (tmp_path / "iterations.csv").read_text() == (in_process.out / "iterations.csv").read_text()
    assert (tmp_path / "calibrated.toml").read_text() == in_process.scene


def test_the_budget_arguments_override_the_box(scene, tmp_path):
    result = karstgen.calibrate(scene, like="surveyed", seeds=1, evaluations=4, out=tmp_path)
    assert len(result.history) == 4 and result.report["seeds"] == [result.report["seeds"][0]]
    assert result.report["target"] == "median of 25 surveyed caves"


def test_bad_aims_raise(scene, tmp_path):
    with pytest.raises(ValueError, match="not both"):
        karstgen.calibrate(scene, like="Sakany", target=ROOT / "fixtures/caves/Sakany_nodes.dat", out=tmp_path)
    with pytest.raises(ValueError, match="Lascaux"):
        karstgen.calibrate(scene, like="Lascaux", out=tmp_path)
    with pytest.raises(ValueError, match="no calibration target"):
        karstgen.calibrate(scene, out=tmp_path)
