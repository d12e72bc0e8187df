"""State round trips: in memory, through pickling and copies, through checkpoint files; each
continues bit for bit as the world it came from."""

import copy
import pickle

import numpy as np
import pytest

import linx

SCENES = ["slider_crank.json", "pyramid.json", "ragdoll.json", "hinge_chain.json"]


def trajectory(world, steps=50):
    out = []
    for _ in range(steps):
        world.step()
        out.append(np.hstack([world.positions, world.orientations, world.linear_velocities,
                              world.angular_velocities]))
    return np.array(out)


@pytest.mark.parametrize("scene", SCENES)
def test_restore_state_continues_bit_for_bit(scene, examples):
    world = linx.load(examples / scene)
    world.step(100)
    state = world.save_state()
    assert isinstance(state, bytes) and len(state) > 0
    first = trajectory(world)
    world.restore_state(state)
    assert np.array_equal(trajectory(world), first)
    # Into a fresh world of the same scene as well.
    fresh = linx.load(examples / scene)
    fresh.restore_state(state)
    assert fresh.time == pytest.approx(100 * fresh.timestep)
    assert np.array_equal(trajectory(fresh), first)


@pytest.mark.parametrize("scene", SCENES)
def test_pickled_and_copied_worlds_continue_identically(scene, examples):
    world = linx.load(examples / scene)
    world.step(80)
    clones = [pickle.loads(pickle.dumps(world)), world.copy(), copy.deepcopy(world),
              copy.copy(world)]
    expected = trajectory(world)
    for clone in clones:
        assert np.array_equal(trajectory(clone), expected)


def test_changes_made_between_steps_travel_with_the_pickle(examples):
    world = linx.load(examples / "pendulum.json")
    world.timestep = 2e-3
    world.joint(0).set_motor(target_velocity=1.0, max_force=50.0)
    world.joint(0).set_limits(lower=-2.0, upper=2.0)
    world.step(20)
    clone = pickle.loads(pickle.dumps(world))
    assert clone.timestep == 2e-3
    assert np.array_equal(trajectory(clone, 400), trajectory(world, 400))


def test_checkpoint_file_round_trip(examples, tmp_path):
    world = linx.load(examples / "slider_crank.json")
    world.step(123)
    path = tmp_path / "crank.lxc"
    world.save(path)
    again = linx.load(path)
    assert again.step_count == 123
    assert np.array_equal(trajectory(again), trajectory(world))


def test_checkpoint_of_linx_run_loads(examples, linx_program, tmp_path):
    import subprocess
    subprocess.run([linx_program, "run", str(examples / "pendulum.json"), "--out",
                    str(tmp_path), "--duration", "0.5", "--checkpoint-every", "0.2"],
                   check=True, capture_output=True)
    checkpoints = sorted((tmp_path / "checkpoints").glob("*.lxc"))
    assert checkpoints
    world = linx.load(checkpoints[-1])
    assert world.time == pytest.approx(0.4, abs=1e-9)
    reference = linx.load(examples / "pendulum.json")
    reference.step(400)
    assert np.array_equal(world.positions, reference.positions)


def test_a_state_of_another_world_is_refused_and_changes_nothing(examples):
    world = linx.load(examples / "pendulum.json")
    world.step(10)
    before = world.positions
    other = linx.load(examples / "double_pendulum.json").save_state()
    with pytest.raises(ValueError):
        world.restore_state(other)
    with pytest.raises(ValueError):
        world.restore_state(b"not a state")
    damaged = bytearray(world.save_state())
    damaged[len(damaged) // 2] ^= 0xFF
    try:
        world.restore_state(bytes(damaged))  # may be a valid state whose numbers differ
    except ValueError:
        assert np.array_equal(world.positions, before)
    assert np.array_equal(linx.load(examples / "pendulum.json").positions.shape, (1, 3))


def test_damaged_checkpoint_file_raises_checkpoint_error(examples, tmp_path):
    world = linx.load(examples / "pendulum.json")
    path = tmp_path / "p.lxc"
    world.save(path)
    data = bytearray(path.read_bytes())
    data[-5] ^= 0x01
    path.write_bytes(bytes(data))
    with pytest.raises(linx.CheckpointError, match="p.lxc"):
        linx.load(path)


def test_every_example_and_robot_pickles_and_continues_bit_for_bit(examples):
    models = sorted(examples.glob("*.json")) + sorted((examples / "robots").glob("*"))
    assert len(models) > 30
    for model in models:
        world = linx.load(model)
        world.step(5)
        clone = pickle.loads(pickle.dumps(world))
        world.step(5)
        clone.step(5)
        assert np.array_equal(world.positions, clone.positions), model.name
        assert np.array_equal(world.angular_velocities, clone.angular_velocities), model.name
