"""A run folder written from Python (World.record): one frame per time, and one writer per folder
(the folder's lock), as `linx run` keeps them (docs/python.md, "Pictures")."""

import pytest

import linx


def rows(path):
    return path.read_text().splitlines()[1:]


def test_record_right_after_world_record_writes_the_first_frame_once(examples, tmp_path):
    world = linx.load(examples / "pendulum.json")
    h = world.timestep
    with world.record(tmp_path, every=1) as rec:
        rec.record()  # the state world.record() wrote already: no second frame at t = 0
        world.step()
        rec.record()
        rec.record()  # no step since: nothing
    times = [float(r.split(",")[0]) for r in rows(tmp_path / "world.csv")]
    assert times == [0.0, h]
    bodies = rows(tmp_path / "bodies.csv")
    assert len(bodies) == 2 * world.body_count
    assert len(rows(tmp_path / "joints.csv")) == 2 * world.joint_count


def test_a_folder_another_recording_has_open_is_refused(examples, tmp_path):
    world = linx.load(examples / "pendulum.json")
    other = linx.load(examples / "pendulum.json")
    first = world.record(tmp_path, every=1)
    world.step()
    first.record()
    files = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    with pytest.raises(linx.Error) as refused:
        other.record(tmp_path)
    assert str(refused.value) == (
        f"{tmp_path}: another run or recording is writing into this folder (it holds the "
        "folder's lock); wait for it to end, or choose another folder")
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == files  # nothing touched
    world.step()
    first.record()  # the first goes on
    first.close()
    assert len(rows(tmp_path / "world.csv")) == 3
    with other.record(tmp_path) as rec:  # closed: the folder is free
        assert rec.dir == tmp_path
    assert len(rows(tmp_path / "world.csv")) == 1
