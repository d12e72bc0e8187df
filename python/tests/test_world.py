"""linx.World from Python: loading, stepping and reading state, against `linx run` of the same
scenes (bit for bit) and closed forms."""

import csv
import math
import subprocess

import numpy as np
import pytest

import linx


def run_csv(program, scene, out, duration, every):
    subprocess.run([program, "run", str(scene), "--out", str(out), "--duration", str(duration),
                    "--every", str(every)], check=True, capture_output=True)
    frames = {}
    with open(out / "bodies.csv") as f:
        for row in csv.DictReader(f):
            frames.setdefault(float(row["time"]), []).append(row)
    return frames


# The validation scenes of the C++ suite: a pendulum (hinge), the slider-crank (closed loop), a
# double pendulum, a hinge chain, contacts (a pyramid) and a robot from its URDF.
SCENES = ["pendulum.json", "slider_crank.json", "double_pendulum.json", "hinge_chain.json",
          "pyramid.json", "robots/three_link_arm.urdf", "robots/four_bar.xml"]


@pytest.mark.parametrize("scene", SCENES)
def test_same_numbers_as_linx_run_to_the_bit(scene, examples, linx_program, tmp_path):
    path = examples / scene
    if not path.exists():
        pytest.skip(f"{scene} not in examples/")
    world = linx.load(path)
    steps, every = 300, 100
    frames = run_csv(linx_program, path, tmp_path, steps * world.timestep, every)
    for k in range(steps // every):
        world.step(every)
        rows = frames[min(frames, key=lambda t: abs(t - world.time))]
        assert [r["body"] for r in rows] == world.body_names
        expected = np.array([[float(r[c]) for c in ("x", "y", "z")] for r in rows])
        quats = np.array([[float(r[c]) for c in ("qw", "qx", "qy", "qz")] for r in rows])
        velocities = np.array([[float(r[c]) for c in ("vx", "vy", "vz")] for r in rows])
        spins = np.array([[float(r[c]) for c in ("wx", "wy", "wz")] for r in rows])
        assert np.array_equal(world.positions, expected)
        assert np.array_equal(world.orientations, quats)
        assert np.array_equal(world.linear_velocities, velocities)
        assert np.array_equal(world.angular_velocities, spins)


def test_free_fall_follows_the_discrete_closed_form():
    # Semi-implicit Euler: v_n = -g n h, z_n = z0 - g h^2 n (n + 1) / 2.
    scene = linx.Scene(gravity=[0, 0, -9.81], timestep=0.01)
    scene.body("ball", mass=2.0, position=[0, 0, 10], shapes=[linx.sphere(0.1)])
    world = scene.build()
    world.step(100)
    n, h, g = 100, 0.01, 9.81
    assert world.time == pytest.approx(1.0, abs=1e-12)
    assert world.positions[0, 2] == pytest.approx(10 - g * h * h * n * (n + 1) / 2, abs=1e-12)
    assert world.linear_velocities[0, 2] == pytest.approx(-g * n * h, abs=1e-12)
    assert world.step_count == 100


def test_pendulum_keeps_its_energy_and_reads_its_angle(examples):
    world = linx.load(examples / "pendulum.json")
    e0 = world.kinetic_energy + world.potential_energy
    world.step(2000)
    e1 = world.kinetic_energy + world.potential_energy
    # The first-order step bleeds 1.4e-3 of the 9.81 J it exchanges in 2 s (issue 19).
    assert abs(e1 - e0) < 2e-3 * 9.81
    # The angle about +y of the bob at (x, z) from the start along +x.
    x, _, z = world.positions[0]
    angle = world.coordinates[0]
    assert math.cos(angle) == pytest.approx(x, abs=1e-9)
    assert math.sin(angle) == pytest.approx(-z, abs=1e-9)
    # Its rate is the bob's angular velocity about the axis; y is the axis.
    assert world.coordinate_rates[0] == pytest.approx(world.angular_velocities[0, 1], rel=1e-7)
    assert world.coordinate_names == ["pivot.angle"]
    assert world.joint_errors[0] < 1e-9


def test_the_accurate_integrator_keeps_the_pendulums_energy(examples):
    # The same pendulum with "integrator": "accurate" (docs/integrators.md), set from a scene built
    # in Python: fifth order, its energy kept to round-off where the step bleeds 1.4e-3.
    scene = linx.Scene(gravity=[0, 0, -9.81], timestep=1e-3, integrator="accurate")
    bob = scene.body("bob", mass=1, position=[1, 0, 0], shapes=[linx.sphere(0.05)])
    scene.joint("hinge", bob, anchor=[0, 0, 0], axis=[0, 1, 0], name="pivot")
    world = scene.build()
    e0 = world.kinetic_energy + world.potential_energy
    world.step(2000)
    e1 = world.kinetic_energy + world.potential_energy
    assert abs(e1 - e0) < 1e-9 * 9.81
    assert world.joint_errors[0] < 1e-11


def test_joint_reaction_balances_the_bob(examples):
    world = linx.load(examples / "pendulum.json")
    world.step(500)
    # Newton: m a = m g + F (the joint's force on the bob, body1).
    v0 = world.linear_velocities[0].copy()
    world.step(1)
    a = (world.linear_velocities[0] - v0) / world.timestep
    force = world.joint("pivot").force
    assert np.allclose(a, world.gravity + force / world.body("bob").mass, atol=1e-6)
    assert np.array_equal(world.joint_forces[0], force)


def test_state_arrays_are_read_only_copies_and_writes_move_bodies(examples):
    world = linx.load(examples / "double_pendulum.json")
    p = world.positions
    with pytest.raises(ValueError):
        p[0, 0] = 1.0
    moved = p.copy()
    moved[:, 2] += 1.0
    world.positions = moved
    assert np.array_equal(world.positions, moved)
    q = np.tile([0.0, 0.0, 0.0, 2.0], (world.body_count, 1))  # normalized on the way in
    world.orientations = q
    assert np.allclose(world.orientations, [[0, 0, 0, 1]] * world.body_count)
    world.linear_velocities = np.ones((world.body_count, 3))
    assert np.array_equal(world.linear_velocities, np.ones((world.body_count, 3)))
    world.angular_velocities = [[0, 0, 1]] * world.body_count  # lists convert
    assert world.angular_velocities[0, 2] == 1.0


def test_handles_read_and_act(examples):
    world = linx.load(examples / "pendulum.json")
    bob = world.body("bob")
    assert bob == world.body(0) == world.bodies[0] == world.body(-1)
    assert bob.name == "bob" and bob.index == 0 and bob.mass == 1.0
    assert np.array_equal(bob.position, world.positions[0])
    pivot = world.joint("pivot")
    assert pivot.type == "hinge" and pivot.body1 == 0 and pivot.body2 is None
    assert pivot.free_coordinates == 1
    # A motor holds the angle's rate.
    pivot.set_motor(target_velocity=2.0, max_force=1e3)
    world.step(10)
    assert pivot.rates[0] == pytest.approx(2.0, abs=1e-9)
    pivot.clear_motor()
    # A force along the coordinate: a torque about the axis on the bob without gravity.
    world.gravity = [0, 0, 0]
    world.angular_velocities = [[0, 0, 0]]
    world.linear_velocities = [[0, 0, 0]]
    pivot.set_force(1.0)  # N m; the bob's inertia about the pivot is 1 + 0.001 kg m^2
    world.step(100)
    assert abs(pivot.rates[0]) == pytest.approx(0.1 / 1.001, rel=1e-6)


def test_contacts_of_a_resting_box_carry_its_weight():
    scene = linx.Scene(timestep=1e-3)
    scene.body("ground", static=True, shapes=[linx.plane()])
    scene.body("box", mass=2.0, position=[0, 0, 0.1], shapes=[linx.box([0.4, 0.4, 0.2])])
    world = scene.build()
    world.step(500)
    c = world.contacts
    assert len(c) == 4
    assert set(c.body1.tolist()) | set(c.body2.tolist()) == {0, 1}
    # The impulses over a step hold the weight: sum = m g h.
    assert c.normal_impulse.sum() == pytest.approx(2.0 * 9.81 * 1e-3, rel=1e-6)
    assert np.allclose(np.abs(c.normal[:, 2]), 1.0)
    assert c.point.shape == (4, 3) and c.friction_impulse.shape == (4, 3)


def test_settings_between_steps(examples):
    world = linx.load(examples / "pendulum.json")
    world.timestep = 5e-4
    world.step(10)
    assert world.time == pytest.approx(5e-3, abs=1e-15)
    world.threads = 2
    assert world.threads == 2
    # The pendulum's one island of joints alone: the accurate integrator moves it ("auto").
    assert world.integrator == "auto"
    assert world.integrator_report["bodies"] == 1 and world.integrator_report["steps"] >= 1
    assert world.max_joint_error < 1e-9
    # The step solves its rows.
    world.integrator = "step"
    world.step(1)
    r = world.solver_report
    assert r["converged"] and r["rows"] >= 5
    assert world.integrator_report["bodies"] == 0
    with pytest.raises(ValueError, match="unknown integrator 'euler'"):
        world.integrator = "euler"
    world.integrator_tolerance = 1e-8
    assert world.integrator_tolerance == 1e-8
    with pytest.raises(ValueError, match="between 1e-14 and 1e-2"):
        world.integrator_tolerance = 0.5
    assert world.warnings == []


def test_urdf_and_mjcf_load(examples):
    urdfs = sorted((examples / "robots").glob("*.urdf"))
    mjcfs = sorted((examples / "robots").glob("*.xml"))
    assert urdfs and mjcfs
    for model in urdfs[:1] + mjcfs[:1]:
        world = linx.load(model)
        world.step(10)
        assert world.body_count > 1 and np.isfinite(world.positions).all()
    # The root link is static, or free with floating_base: it then falls.
    fixed, floating = linx.load(urdfs[0]), linx.load(urdfs[0], floating_base=True)
    assert fixed.body(0).is_static and not floating.body(0).is_static
    z0 = floating.positions[0, 2]
    floating.step(100)
    assert floating.positions[0, 2] < z0 - 0.01


def test_type_stubs_and_docstrings_cover_the_module():
    import ast
    import pathlib
    stub = ast.parse((pathlib.Path(linx.__file__).parent / "_linx.pyi").read_text())
    stubbed = {n.name for n in stub.body if isinstance(n, (ast.ClassDef, ast.FunctionDef))}
    members = {}
    for n in stub.body:
        if isinstance(n, ast.ClassDef):
            members[n.name] = {m.name if isinstance(m, (ast.FunctionDef, ast.ClassDef))
                               else m.target.id for m in n.body
                               if isinstance(m, (ast.FunctionDef, ast.ClassDef, ast.AnnAssign))}
    from linx import _linx
    public = {k for k in dir(_linx) if not k.startswith("_")}
    assert public == stubbed
    for cls in ("World", "Body", "Joint", "Batch", "Recording"):
        names = {k for k in dir(getattr(_linx, cls)) if not k.startswith("_")}
        assert names <= members[cls], names - members[cls]
        for k in names:
            assert getattr(getattr(_linx, cls), k).__doc__, f"{cls}.{k} has no docstring"
    for k in public:
        assert getattr(_linx, k).__doc__, k


def test_version_is_the_linx_programs(linx_program):
    # linx.__version__ is the project's version: what `linx --version` prints ("linx X.Y.Z").
    printed = subprocess.run([linx_program, "--version"], check=True, capture_output=True,
                             text=True).stdout.split()
    assert printed[0] == "linx"
    assert linx.__version__ == printed[1]
    assert all(part.isdigit() for part in linx.__version__.split("."))
