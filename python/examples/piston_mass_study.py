"""A design study: how much torque does the slider-crank's motor need as the piston gets heavier?
100 runs of examples/slider_crank.json, each with its own piston mass from 0.1 to 10 kg, spread
over a dask.distributed cluster (a local one by default), gathered in one table.

    python3 python/examples/piston_mass_study.py [--runs 100] [--out study.csv]
        [--address tcp://scheduler:8786 | --workers N | --serial]
"""

import argparse
import json
import pathlib

import numpy as np

import linx

ROOT = pathlib.Path(__file__).resolve().parents[2]


def peak_torque(piston_mass: float) -> dict:
    """One run with the given piston mass: the motor's peak torque and the rod's peak force on
    the crank pin over a turn of the crank (1 s), after 0.2 s of spinning up from rest."""
    path = ROOT / "examples" / "slider_crank.json"
    scene = json.loads(path.read_text())
    next(b for b in scene["bodies"] if b["name"] == "piston")["mass"] = piston_mass
    world = linx.loads(json.dumps(scene), str(path))
    crank, pin = world.joint("crank"), world.joint("crank_pin")
    torque = force = 0.0
    world.step(round(0.2 / world.timestep))
    for _ in range(round(1.0 / world.timestep)):
        world.step()
        torque = max(torque, abs(crank.torque[2]))
        force = max(force, float(np.linalg.norm(pin.force)))
    return {"piston_mass": piston_mass, "peak_motor_torque": torque, "peak_pin_force": force}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=100)
    parser.add_argument("--out", default="study.csv", help="the table (CSV)")
    parser.add_argument("--address", help="a dask scheduler to spread the runs over")
    parser.add_argument("--workers", type=int, help="local cluster size (default: one per core)")
    parser.add_argument("--serial", action="store_true", help="run here, one after another")
    args = parser.parse_args()

    masses = np.linspace(0.1, 10.0, args.runs).tolist()
    if args.serial:
        rows = linx.serial(peak_torque, masses)
    else:
        rows = linx.sweep(peak_torque, masses, address=args.address, workers=args.workers)
    linx.write_csv(rows, args.out)
    light, heavy = rows[0], rows[-1]
    print(f"{len(rows)} runs -> {args.out}; peak motor torque {light['peak_motor_torque']:.3f} "
          f"N m at {light['piston_mass']:.1f} kg, {heavy['peak_motor_torque']:.3f} N m at "
          f"{heavy['piston_mass']:.1f} kg")


if __name__ == "__main__":
    main()
