"""linx.Scene builds the same world as the scene file it writes, and its worlds behave as the
closed forms say."""

import json
import math

import numpy as np
import pytest

import linx


def test_a_built_pendulum_is_the_example_file(examples):
    scene = linx.Scene(gravity=[0, 0, -9.81], timestep=0.001, duration=5, solver={"type": "exact"})
    scene.body("bob", mass=1, position=np.array([1.0, 0, 0]), shapes=[linx.sphere(0.05)])
    scene.joint("hinge", "bob", "world", name="pivot", anchor=[0, 0, 0], axis=[0, 1, 0])
    built = scene.build()
    loaded = linx.load(examples / "pendulum.json")
    built.step(1000)
    loaded.step(1000)
    assert np.array_equal(built.positions, loaded.positions)
    assert json.loads(scene.to_json())["joints"][0]["name"] == "pivot"


def test_slider_with_a_spring_oscillates_at_its_frequency():
    k, m = 100.0, 1.0
    scene = linx.Scene(gravity=[0, 0, 0], timestep=1e-4)
    scene.body("block", mass=m, position=[0.1, 0, 0], shapes=[linx.box([0.1, 0.1, 0.1])])
    scene.joint("slider", "block", name="rail", axis=[1, 0, 0],
                spring={"stiffness": k, "rest": -0.1})
    world = scene.build()
    period = 2 * math.pi * math.sqrt(m / k)
    world.step(round(period / 2 / 1e-4))
    # Half a period from +0.1 m about the rest (-0.1 m from the start): the other extreme.
    assert world.coordinates[0] == pytest.approx(-0.2, abs=2e-4)


def test_springs_forces_and_torques():
    scene = linx.Scene(gravity=[0, 0, 0], timestep=1e-3)
    scene.body("a", mass=2.0, shapes=[linx.sphere(0.1)])
    scene.body("b", mass=1.0, position=[2, 0, 0], shapes=[linx.sphere(0.1)])
    scene.force("a", [1.0, 0, 0])
    scene.torque("b", [0, 0, 0.5])
    world = scene.build()
    world.step(1000)
    # F = m a: x = a t^2 / 2 with the semi-implicit Euler's (n + 1) / n.
    assert world.positions[0, 0] == pytest.approx(0.5 * 1.0 / 2.0 * 1.0 * 1001 / 1000, rel=1e-9)
    inertia = 2 / 5 * 1.0 * 0.1 ** 2
    assert world.angular_velocities[1, 2] == pytest.approx(0.5 / inertia * 1.0, rel=1e-9)
    scene2 = linx.Scene(gravity=[0, 0, 0])
    scene2.body("c", mass=1.0, position=[1, 0, 0], shapes=[linx.sphere(0.1)])
    name = scene2.spring("c", anchor1=[1, 0, 0], anchor2=[0, 0, 0], stiffness=10.0,
                         rest_length=1.0)
    assert scene2.build().joint_names == [name]


def test_every_shape_helper_builds():
    scene = linx.Scene()
    scene.body("ground", static=True, shapes=[linx.plane(), linx.mesh(
        points=[[5, 5, -1], [6, 5, -1], [5, 6, -1]], triangles=[[0, 1, 2]])])
    scene.body("s", mass=1, position=[0, 0, 1], shapes=[linx.sphere(0.1)])
    scene.body("b", mass=1, position=[1, 0, 1], shapes=[linx.box([0.1, 0.2, 0.3])])
    scene.body("c", mass=1, position=[2, 0, 1], shapes=[linx.capsule(0.1, 0.2)])
    scene.body("y", mass=1, position=[3, 0, 1], shapes=[linx.cylinder(0.1, 0.2)])
    scene.body("h", mass=1, position=[4, 0, 1], shapes=[linx.convex(
        [[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]])])
    world = scene.build()
    world.step(2000)
    assert world.body_names == ["ground", "s", "b", "c", "y", "h"]
    assert (world.positions[1:, 2] < 1.0).all() and (world.positions[1:, 2] > -0.01).all()


def test_schema_describes_the_fields_the_reader_checks():
    # linx.schema() is the reader's own description: each bound it gives is refused by the reader.
    records = linx.schema()
    assert {"solver", "contact", "sleep", "faults", "motor", "limits"} <= set(records)
    erp = {f["name"]: f for f in linx.schema("solver")}["erp"]
    assert (erp["lower"], erp["upper"], erp["default"]) == (0.0, 1.0, "`0.2`")
    max_force = {f["name"]: f for f in records["motor"]}["max_force"]
    assert "max_torque" in max_force["aliases"] and max_force["lower"] == 0.0
    scene = linx.Scene()
    scene.body("b", mass=1.0, inertia=[1, 1, 1])
    scene.set(solver={"erp": erp["upper"] + 0.5})
    with pytest.raises(linx.SceneError, match="solver.erp: must be between 0 and 1, got 1.5"):
        scene.build()
    with pytest.raises(KeyError, match="no record 'solvr'"):
        linx.schema("solvr")
