"""linx.Batch: copies of a world stepped together give each copy's own steps to the bit."""

import numpy as np
import pytest

import linx


def test_copies_match_worlds_stepped_alone(examples):
    world = linx.load(examples / "double_pendulum.json")
    batch = linx.Batch(world, 6, threads=2)
    assert len(batch) == 6
    # Each copy gets its own start: different first velocities.
    v = batch.angular_velocities.copy()
    v[:, :, 1] += np.arange(6)[:, None] * 0.1
    batch.angular_velocities = v
    alone = []
    for i in range(6):
        w = world.copy()
        w.angular_velocities = v[i]
        alone.append(w)
    for _ in range(3):
        batch.step(100)
        for w in alone:
            w.step(100)
        expected = np.stack([w.positions for w in alone])
        assert np.array_equal(batch.positions, expected)
        assert np.array_equal(batch.orientations, np.stack([w.orientations for w in alone]))
    assert np.allclose(batch.time, 0.3)
    assert batch[2] is batch.worlds[2]
    assert batch.positions.shape == (6, world.body_count, 3)


def test_drive_targets_per_copy(examples):
    world = linx.load(examples / "pendulum.json")
    batch = linx.Batch(world, 3)
    for i, copy in enumerate(batch):
        copy.joint(0).set_motor(target_velocity=float(i), max_force=1e3)
    batch.step(50)
    rates = [copy.joint(0).rates[0] for copy in batch]
    assert rates == pytest.approx([0.0, 1.0, 2.0], abs=1e-9)


def test_a_faulting_copy_stops_alone_and_is_named():
    scene = linx.Scene(gravity=[0, 0, 0], faults={"max_speed": 10.0})
    scene.body("b", mass=1.0, shapes=[linx.sphere(0.1)])
    batch = linx.Batch(scene.build(), 3)
    batch[1].body(0).linear_velocity = [20, 0, 0]
    with pytest.raises(linx.BoundExceeded):
        batch.step(10)
    assert batch.faults[0] is None and batch.faults[2] is None
    assert batch.faults[1].startswith("copy 1:")
    assert batch[0].step_count == 10 and batch[1].step_count == 1


def test_bad_arguments():
    scene = linx.Scene()
    scene.body("b", mass=1.0, shapes=[linx.sphere(0.1)])
    world = scene.build()
    with pytest.raises(ValueError):
        linx.Batch(world, 0)
    with pytest.raises(ValueError):
        linx.Batch(world, 2, threads=-3)
    batch = linx.Batch(world, 2)
    with pytest.raises(ValueError, match=r"\(2, 1, 3\)"):
        batch.positions = np.zeros((2, 3))
    with pytest.raises(IndexError):
        batch[5]
    batch[0].close()
    with pytest.raises(linx.ClosedError):
        batch.step()


def test_a_batch_pickles_and_goes_on_identically(examples):
    import pickle
    batch = linx.Batch(linx.load(examples / "double_pendulum.json"), 3)
    batch.step(20)
    again = pickle.loads(pickle.dumps(batch))
    batch.step(50)
    again.step(50)
    assert np.array_equal(batch.positions, again.positions)
    assert len(again) == 3 and again[0] is not batch[0]
