"""What the Python layer adds to linx's C++ cost (issue 18's targets): a World.step() call on a
small scene (the pendulum) under 1 microsecond above the C++ step, and reading the state of 1,000
bodies (positions, orientations, linear and angular velocities) under 5 microseconds above the
C++ copy.

Each figure is compared with its C++ cost in the same process, on the same world: a step with
World.step(n) (the loop in C++), a read with linx._linx._read_cost (the same copy into
preallocated buffers, without Python). Python and C++ timings alternate, 31 repeats each;
medians are printed.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py
"""

import pathlib
import statistics
import time

import linx
from linx import _linx

ROOT = pathlib.Path(__file__).resolve().parents[1]
REPEATS = 31


def per_call_ns(calls: int, work) -> float:
    t0 = time.perf_counter_ns()
    work(calls)
    return (time.perf_counter_ns() - t0) / calls


def thousand_bodies() -> linx.World:
    scene = linx.Scene()
    for i in range(1000):
        scene.body(f"b{i}", mass=1.0, position=[i % 10, (i // 10) % 10, i // 100],
                   shapes=[linx.sphere(0.1)])
    return scene.build()


def compare(python, cxx) -> tuple[float, float]:
    """Medians of alternating repeats of the Python and the C++ timing."""
    py, cc = [], []
    for _ in range(REPEATS):
        py.append(python())
        cc.append(cxx())
    return statistics.median(py), statistics.median(cc)


def main() -> None:
    pendulum = linx.load(ROOT / "examples" / "pendulum.json")

    def step_calls(n):
        step = pendulum.step
        for _ in range(n):
            step()

    world = thousand_bodies()

    def body_state(n):
        read = world.body_state
        for _ in range(n):
            read()

    def properties(n):
        for _ in range(n):
            world.positions, world.orientations, world.linear_velocities, world.angular_velocities

    rows = [
        ("World.step(), pendulum", 1000.0,
         *compare(lambda: per_call_ns(20000, step_calls), lambda: per_call_ns(20000, pendulum.step))),
        ("World.body_state(), 1,000 bodies", 5000.0,
         *compare(lambda: per_call_ns(2000, body_state),
                  lambda: _linx._read_cost(world, 2000, True))),
        ("4 properties, 1,000 bodies", 5000.0,
         *compare(lambda: per_call_ns(2000, properties),
                  lambda: _linx._read_cost(world, 2000, False))),
    ]
    print(f"{'':34} {'Python':>10} {'C++':>10} {'overhead':>10} {'target':>10}")
    for name, target, py, cc in rows:
        over = py - cc
        verdict = "met" if over < target else "MISSED"
        print(f"{name:34} {py / 1000:9.3f}us {cc / 1000:9.3f}us {over / 1000:9.3f}us "
              f"{'< %g us' % (target / 1000):>10} {verdict}")


if __name__ == "__main__":
    main()
