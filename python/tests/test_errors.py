"""Every error path raises a Python exception with the engine's message; no call crashes the
interpreter, whatever its arguments."""

import json
import os
import threading

import numpy as np
import pytest

import linx


def pendulum(examples):
    return linx.load(examples / "pendulum.json")


def test_bad_scene_files_raise_scene_error_with_file_and_field(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"bodies": [{"name": "b", "mass": -1}]}))
    with pytest.raises(linx.SceneError) as e:
        linx.load(bad)
    assert e.value.file.endswith("bad.json")
    assert e.value.field == "bodies[0].mass"
    assert "bodies[0].mass" in str(e.value) and e.value.problem
    assert isinstance(e.value, ValueError) and isinstance(e.value, linx.Error)
    with pytest.raises(linx.SceneError, match="cannot open"):
        linx.load(tmp_path / "missing.json")
    with pytest.raises(linx.SceneError):
        linx.loads("{not json")
    with pytest.raises(linx.SceneError, match="<string>"):
        linx.loads("{}")


def test_the_message_is_the_command_lines(tmp_path, linx_program):
    import subprocess
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"bodies": [{"name": "b", "mass": 1, "shapes": [
        {"type": "sphere", "radius": 0}]}]}))
    cli = subprocess.run([linx_program, "check", str(bad)], capture_output=True, text=True)
    with pytest.raises(linx.SceneError) as e:
        linx.load(bad)
    assert str(e.value) in cli.stderr


def test_scene_builder_mistakes_name_the_field():
    scene = linx.Scene()
    scene.body("a", mass=1, shapes=[linx.box([1, 1, -1])])
    with pytest.raises(linx.SceneError, match=r"bodies\[0\]\.shapes\[0\]\.size"):
        scene.build()
    scene = linx.Scene()
    scene.body("a", mass=1, shapes=[linx.sphere(0.1)])
    scene.joint("hinge", "a", "nobody", anchor=[0, 0, 0], axis=[0, 0, 1])
    with pytest.raises(linx.SceneError, match=r"joints\[0\]\.body2"):
        scene.build()


@pytest.mark.parametrize("value", [
    np.zeros((2, 3)), np.zeros(3), np.zeros((1, 4)), "abc", None, [[1, 2]], [["a", "b", "c"]],
    np.array([[np.nan, 0, 0]]), np.array([[np.inf, 0, 0]]), object(), {"x": 1},
    np.zeros((1, 3), dtype=complex) + 1j,
])
def test_wrong_shapes_and_types_raise(value, examples):
    world = pendulum(examples)
    before = world.positions
    with pytest.raises((ValueError, TypeError)):
        world.positions = value
    assert np.array_equal(world.positions, before)


def test_integer_and_float32_arrays_convert(examples):
    world = pendulum(examples)
    world.positions = np.array([[1, 0, 0]], dtype=np.int32)
    world.positions = np.array([[1, 0, 0]], dtype=np.float32)
    world.positions = np.asfortranarray(np.array([[1.0, 0, 0]]))
    world.positions = np.array([[9, 1, 0, 0, 9]])[:, 1:4]  # a strided view
    assert np.array_equal(world.positions, [[1.0, 0, 0]])


def test_bad_values_raise_and_leave_the_world_unchanged(examples):
    world = pendulum(examples)
    with pytest.raises(ValueError, match="zero quaternion"):
        world.orientations = [[0, 0, 0, 0]]
    with pytest.raises(ValueError):
        world.timestep = 0
    with pytest.raises(ValueError):
        world.timestep = float("nan")
    with pytest.raises(ValueError):
        world.threads = -1
    with pytest.raises(ValueError):
        world.step(-1)
    with pytest.raises(TypeError):
        world.step("ten")
    with pytest.raises(ValueError):
        world.gravity = [0, 0]
    with pytest.raises(ValueError, match="coordinate 3"):
        world.joint(0).set_motor(target_velocity=1, coordinate=3)
    with pytest.raises(ValueError):
        world.joint(0).set_motor(target_velocity=1, max_force=-1)
    with pytest.raises(ValueError):
        world.joint(0).set_limits(lower=1, upper=-1)
    with pytest.raises(ValueError):
        world.body(0).apply_force([1, 2])
    with pytest.raises(ValueError):
        world.body(0).apply_force([1, 2, 3], point=[np.nan, 0, 0])
    assert world.step_count == 0


def test_static_bodies_refuse_velocities():
    scene = linx.Scene()
    scene.body("ground", static=True, shapes=[linx.plane()])
    scene.body("ball", mass=1, position=[0, 0, 1], shapes=[linx.sphere(0.1)])
    world = scene.build()
    with pytest.raises(ValueError, match="static"):
        world.linear_velocities = [[1, 0, 0], [0, 0, 0]]
    with pytest.raises(ValueError, match="static"):
        world.body("ground").angular_velocity = [0, 0, 1]
    assert np.array_equal(world.linear_velocities, np.zeros((2, 3)))


def test_unknown_bodies_and_joints(examples):
    world = pendulum(examples)
    with pytest.raises(IndexError):
        world.body(1)
    with pytest.raises(IndexError):
        world.body(-2)
    with pytest.raises(KeyError, match="nobody"):
        world.body("nobody")
    with pytest.raises(KeyError):
        world.joint("nothing")
    with pytest.raises(TypeError):
        world.body(1.5)
    with pytest.raises(TypeError):
        world.body(True)


def test_handles_of_another_world_are_refused(examples):
    a, b = pendulum(examples), pendulum(examples)
    with pytest.raises(ValueError, match="another"):
        b.body(a.body(0))
    with pytest.raises(ValueError, match="another"):
        b.joint(a.joint(0))
    with pytest.raises(ValueError, match="another"):
        b.apply_force(a.body(0), [1, 0, 0])
    assert b.body(b.body(0)) == b.body(0)
    assert a.body(0) != b.body(0)


def test_a_closed_world_and_its_handles_raise(examples):
    world = pendulum(examples)
    body, joint = world.body(0), world.joint(0)
    with world:
        world.step()
    assert world.closed
    for call in (lambda: world.step(), lambda: world.positions, lambda: world.time,
                 lambda: world.save_state(), lambda: world.copy(), lambda: body.position,
                 lambda: joint.coordinates, lambda: joint.set_motor(target_velocity=1),
                 lambda: world.body(0), lambda: world.contacts, lambda: world.body_names,
                 lambda: setattr(world, "positions", [[0, 0, 0]])):
        with pytest.raises(linx.ClosedError, match="closed"):
            call()
    with pytest.raises(linx.ClosedError):
        import pickle
        pickle.dumps(world)
    world.close()  # twice is fine
    assert "closed" in repr(world) and "closed" in repr(body)


# Steps long enough to be seen busy: about 0.3 s in the optimized build; the sanitized build
# (which preloads ASan, ASAN_OPTIONS set) steps some twenty times slower and needs a tenth.
BUSY_STEPS = 20000 if "ASAN_OPTIONS" in os.environ else 200000


def test_a_world_stepped_by_another_thread_is_busy(examples):
    world = pendulum(examples)
    errors = []
    stepped = []
    started = threading.Event()

    def stepper():
        started.set()
        try:
            world.step(BUSY_STEPS)
            stepped.append(True)
        except Exception as e:  # noqa: BLE001 - the step must not be disturbed
            errors.append(e)

    t = threading.Thread(target=stepper)
    t.start()
    started.wait()
    seen_busy = False
    closed = False
    # The step holds the world for its whole length: every call meanwhile is busy, and a close
    # that goes through can only come after the step returned (the thread may still be alive).
    while t.is_alive() and not closed:
        try:
            world.positions
            world.close()
            closed = True
        except linx.BusyError:
            seen_busy = True
        except Exception as e:  # noqa: BLE001 - anything else is a failure
            errors.append(e)
    t.join()
    assert not errors
    assert stepped == [True]
    assert seen_busy or closed
    if not closed:
        assert world.step_count == BUSY_STEPS
        world.close()


def test_numerical_faults_raise_with_their_step_and_time():
    scene = linx.Scene(gravity=[0, 0, 0], faults={"max_speed": 10.0})
    scene.body("rocket", mass=1.0, shapes=[linx.sphere(0.1)])
    world = scene.build()
    world.body(0).linear_velocity = [5, 0, 0]
    for _ in range(10):
        world.apply_force(0, [1000, 0, 0])
        try:
            world.step()
        except linx.BoundExceeded as e:
            assert isinstance(e, linx.StepFault) and isinstance(e, RuntimeError)
            assert e.step == world.step_count and e.time == pytest.approx(world.time)
            assert e.body == 0 and e.joint is None
            assert "rocket" in str(e) and "10" in str(e)
            break
    else:
        pytest.fail("no fault")
    # With stopping off, the fault is kept and the world steps on.
    world.stop_on_fault = False
    world.apply_force(0, [1000, 0, 0])
    world.step()
    assert world.faults and "rocket" in world.faults[-1]


def test_a_non_finite_state_raises():
    scene = linx.Scene(gravity=[0, 0, -1e308], faults={"max_speed": 1e308,
                                                       "energy": False})
    scene.body("b", mass=1.0, shapes=[linx.sphere(0.1)])
    world = scene.build()
    # A bound passed (the body beyond 1e8 m at once) is kept; an energy not finite still raises:
    # the potential energy overflows at the first step.
    world.stop_on_fault = False
    with pytest.raises(linx.NonFiniteState) as e:
        world.step(10000)
    assert e.value.body == 0 and "energy is not finite" in str(e.value)


def test_exceptions_pickle_with_their_message():
    import pickle
    try:
        linx.loads('{"bodies": []}', "x.json")
    except linx.SceneError as e:
        again = pickle.loads(pickle.dumps(e))
        assert type(again) is linx.SceneError and str(again) == str(e)


def test_numpy_integers_name_bodies(examples):
    world = linx.load(examples / "double_pendulum.json")
    assert world.body(np.int64(1)) == world.body(1)
    assert world.joint(np.int32(-1)) == world.joint(world.joint_count - 1)
    with pytest.raises(IndexError, match="2 bodies"):
        world.body(np.int64(2))


ODD_ARGUMENTS = [None, 0, -1, 2**70, 1e308, float("nan"), "x", b"x", [], [[]], (1, 2, 3),
                 np.zeros(0), np.zeros((1000, 3)), np.ones((1, 3, 1)), object(), {"a": 1}, True]


def test_no_argument_crashes_the_interpreter(examples):
    # Every method and setter, with every odd argument: a Python exception at worst.
    world = linx.load(examples / "double_pendulum.json")
    batch = linx.Batch(world, 2)
    targets = [world, world.body(0), world.joint(0), batch]
    skip = {"close", "record", "save", "step"}  # files and long runs: tested on their own
    calls = 0
    for target in targets:
        for name in dir(target):
            if name.startswith("_") or name in skip:
                continue
            attribute = getattr(type(target), name, None)
            for arg in ODD_ARGUMENTS:
                try:
                    if isinstance(attribute, property):
                        setattr(target, name, arg)
                    elif callable(getattr(target, name)):
                        getattr(target, name)(arg)
                except Exception:  # noqa: BLE001 - any Python exception is fine
                    pass
                calls += 1
    for arg in ODD_ARGUMENTS:
        for f in (world.step, batch.step, linx.load, linx.loads, world.restore_state):
            try:
                f(arg)
            except Exception:  # noqa: BLE001
                pass
    assert calls > 500
    world.step()  # still a working world
    assert world.step_count >= 1
