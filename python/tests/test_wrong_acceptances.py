"""Arguments the Python API used to accept wrongly or refuse with the wrong error (issue 43): a
quaternion too large to normalize naively, an index beyond a 64-bit integer, a NaN in a Scene."""

import math

import numpy as np
import pytest

import linx


def pendulum(examples):
    return linx.load(examples / "pendulum.json")


@pytest.mark.parametrize("scale", [1e200, 1e-200, 1e308])
def test_a_quaternion_of_any_scale_is_its_direction(scale):
    # (s, s, 0, 0) for any s > 0 is a quarter turn about x: (cos 45°, sin 45°, 0, 0).
    scene = linx.Scene(gravity=[0, 0, 0])
    scene.body("b", mass=1, angular_velocity=[0, 0, 1], shapes=[linx.box([0.1, 0.2, 0.3])])
    world = scene.build()
    world.orientations = [[scale, scale, 0, 0]]
    expected = [math.sqrt(0.5), math.sqrt(0.5), 0, 0]
    assert np.allclose(world.orientations, [expected], rtol=0, atol=1e-15)
    bob = world.body(0)
    bob.orientation = [0, 0, -scale, 0]
    assert np.allclose(bob.orientation, [0, 0, -1, 0], rtol=0, atol=0)
    world.step()  # a unit quaternion: the step has a rotation to integrate
    assert abs(np.linalg.norm(world.orientations[0]) - 1) < 1e-12


def test_the_zero_quaternion_is_still_refused(examples):
    world = pendulum(examples)
    before = world.orientations.copy()
    with pytest.raises(ValueError, match="zero quaternion"):
        world.orientations = [[0, 0, 0, 0]]
    with pytest.raises(ValueError, match="zero quaternion"):
        world.body(0).orientation = [0.0, -0.0, 0, 0]
    assert np.array_equal(world.orientations, before)


@pytest.mark.parametrize("index", [10**20, -10**20, 2**63, 2**63 - 1, -2**63, 10**5000],
                         ids=["1e20", "-1e20", "2^63", "2^63-1", "-2^63", "1e5000"])
def test_an_index_beyond_64_bits_is_out_of_range(examples, index):
    world = pendulum(examples)
    with pytest.raises(IndexError, match="out of range: the world has 1 bodies") as e:
        world.body(index)
    if abs(index) < 10**100:
        assert str(index) in str(e.value)
    with pytest.raises(IndexError, match="out of range: the world has 1 joints"):
        world.joint(index)
    with pytest.raises(IndexError, match="of 2"):
        linx.Batch(world, 2)[index]
    with pytest.raises(ValueError, match="coordinate") as e:
        world.joint(0).set_limits(lower=-1, upper=1, coordinate=index)
    if abs(index) < 10**100:
        assert str(index) in str(e.value)
    with pytest.raises(ValueError, match="coordinate"):
        world.joint(0).set_coordinate(0.5, coordinate=index)


def test_numpy_integers_and_negative_indices_still_index(examples):
    world = pendulum(examples)
    assert world.body(np.int64(0)).name == world.body(-1).name == "bob"
    assert world.joint(np.uint8(0)).name == world.joint(0).name
    world.joint(0).set_limits(lower=-1, upper=1, coordinate=np.int32(0))
    with pytest.raises(TypeError):
        world.body(True)


@pytest.mark.parametrize("value, field", [
    (float("nan"), "bodies[0].mass"),
    (float("inf"), "bodies[0].mass"),
    (np.float64("-inf"), "bodies[0].mass"),
])
def test_a_nan_in_a_scene_names_its_field(value, field):
    scene = linx.Scene(timestep=1e-3)
    scene.body("bob", mass=value, shapes=[linx.sphere(0.05)])
    with pytest.raises(linx.SceneError) as e:
        scene.build()
    assert e.value.file == "<linx.Scene>"
    assert e.value.field == field
    assert e.value.problem == f"must be a finite number, got {float(value)}"
    assert str(e.value) == f"<linx.Scene>: {field}: must be a finite number, got {float(value)}"


def test_a_nan_in_an_array_or_a_top_level_field_names_its_place():
    scene = linx.Scene(gravity=np.array([0, 0, np.nan]))
    scene.body("bob", mass=1, shapes=[linx.sphere(0.05)])
    with pytest.raises(linx.SceneError, match=r"^<linx.Scene>: gravity\[2\]: must be a finite"):
        scene.build()
    scene = linx.Scene()
    scene.body("bob", mass=1, position=[0, 0, 1], shapes=[linx.sphere(0.05)])
    scene.joint("hinge", "bob", anchor=[0, 0, 0], axis=[0, 1, 0],
                limits={"lower": -1, "upper": float("nan")})
    with pytest.raises(linx.SceneError) as e:
        scene.to_json()
    assert e.value.field == "joints[0].limits.upper"
