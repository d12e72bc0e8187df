"""What the Python layer adds to linx's C++ cost (issue 18's targets): a World.step() call on a
small scene (the pendulum) under 1 microsecond above the C++ step, and reading the state of
1,000 bodies (positions, orientations, linear and angular velocities) under 5 microseconds above
the C++ copy. Medians of 15 repeats; the C++ figures come from linx-call-costs, run here.

    PYTHONPATH=build/python python3 bench/python_overhead.py [--build build]
"""

import argparse
import json
import pathlib
import statistics
import subprocess
import time

import linx

ROOT = pathlib.Path(__file__).resolve().parents[1]


def median_ns(repeats: int, calls: int, work) -> float:
    per_call = []
    for _ in range(repeats):
        t0 = time.perf_counter_ns()
        work(calls)
        per_call.append((time.perf_counter_ns() - t0) / calls)
    return statistics.median(per_call)


def thousand_bodies() -> linx.World:
    scene = linx.Scene()
    for i in range(1000):
        scene.body(f"b{i}", mass=1.0, position=[i % 10, (i // 10) % 10, i // 100],
                   shapes=[linx.sphere(0.1)])
    return scene.build()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=str(ROOT / "build"), help="the build folder")
    args = parser.parse_args()
    pendulum_file = ROOT / "examples" / "pendulum.json"
    cxx = json.loads(subprocess.run([str(pathlib.Path(args.build) / "bench" / "linx-call-costs"),
                                     str(pendulum_file)], check=True, capture_output=True,
                                    text=True).stdout)

    pendulum = linx.load(pendulum_file)

    def one_step_calls(n):
        step = pendulum.step
        for _ in range(n):
            step()

    step_call = median_ns(15, 20000, one_step_calls)
    step_loop = median_ns(15, 20000, pendulum.step)  # step(n): the loop in C++

    world = thousand_bodies()

    def reads(n):
        for _ in range(n):
            world.positions, world.orientations, world.linear_velocities, world.angular_velocities

    read = median_ns(15, 2000, reads)
    read_once = median_ns(15, 2000, lambda n: [world.body_state() for _ in range(n)])

    # The step call's overhead is taken against step(n)'s steps, in the same process on the same
    # world (the separate C++ program's step is shown for reference: another process's timing).
    rows = [
        ("World.step() on the pendulum", step_call, step_loop, 1000.0),
        ("World.body_state(), 1,000 bodies", read_once, cxx["read_1000_ns"], 5000.0),
        ("4 properties, 1,000 bodies", read, cxx["read_1000_ns"], 5000.0),
    ]
    print(f"{'':34} {'Python':>10} {'C++':>10} {'overhead':>10} {'target':>10}")
    for name, py, c, target in rows:
        over = py - c
        verdict = "met" if over < target else "MISSED"
        print(f"{name:34} {py / 1000:9.3f}us {c / 1000:9.3f}us {over / 1000:9.3f}us "
              f"{'< %g us' % (target / 1000):>10} {verdict}")
    print(f"(C++ program: {cxx['step_ns'] / 1000:.3f} us a step; the C++ column of the step row "
          f"is World.step(n)'s per step, the loop in C++)")


if __name__ == "__main__":
    main()
