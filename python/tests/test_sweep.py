"""Sweeps on dask.distributed: a local cluster of 2 workers gives the serial run's table; a lost
worker's run is run again, a failing run is named, never dropped."""

import os
import pathlib
import sys

import pytest

import linx

sys.path.insert(0, str(pathlib.Path(__file__).parent))
os.environ["PYTHONPATH"] = os.pathsep.join(
    [str(pathlib.Path(__file__).parent), os.environ.get("PYTHONPATH", "")])
import sweep_runs  # noqa: E402

DAMPINGS = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]


@pytest.fixture(scope="module")
def client():
    from distributed import Client, LocalCluster
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           dashboard_address=":0")
    with Client(cluster) as c:
        yield c
    cluster.close()


def test_a_local_cluster_gives_the_serial_table(examples, client):
    world = linx.load(examples / "pendulum.json")
    params = [(world, d) for d in DAMPINGS]
    serial = linx.serial(sweep_runs.swing, params)
    distributed = linx.sweep(sweep_runs.swing, params, client=client)
    assert distributed == serial  # the same numbers to the bit
    angles = [row["angle"] for row in serial]
    assert len(set(angles)) == len(DAMPINGS)  # the damping made a difference


def test_sweep_starts_its_own_local_cluster(examples):
    world = linx.load(examples / "pendulum.json")
    rows = linx.sweep(sweep_runs.swing, [(world, 0.1), (world, 0.2)], workers=2)
    assert rows == linx.serial(sweep_runs.swing, [(world, 0.1), (world, 0.2)])


def test_a_lost_workers_run_is_run_again(examples, client, tmp_path):
    world = linx.load(examples / "pendulum.json")
    marker = str(tmp_path / "killed")
    rows = linx.sweep(sweep_runs.swing_dying_once, [(world, d, marker) for d in DAMPINGS],
                      client=client)
    assert pathlib.Path(marker).exists()  # a worker did die
    assert rows == linx.serial(sweep_runs.swing, [(world, d) for d in DAMPINGS])


def test_failing_runs_are_named_not_dropped(client):
    with pytest.raises(linx.SweepError) as e:
        linx.sweep(sweep_runs.always_fails, [1, 2], client=client, retries=1)
    assert [f[0] for f in e.value.failures] == [0, 1]
    assert "no result for 2" in str(e.value)


def test_write_csv(tmp_path):
    path = tmp_path / "t.csv"
    linx.write_csv([{"a": 0.1, "b": 2}, {"a": 1 / 3, "b": 3}], path)
    lines = path.read_text().splitlines()
    assert lines[0] == "a,b" and lines[2] == "0.3333333333333333,3"
