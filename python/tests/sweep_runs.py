"""Run functions of the sweep tests, importable by the dask workers (PYTHONPATH has this folder)."""

import os
import pathlib

import linx


def swing(args):
    """A pendulum world (pickled to the worker) with a damped joint: its angle after 1 s. The
    world is copied first: dask may hand the same object to several runs on one worker."""
    world, damping = args
    world = world.copy()
    world.joint(0).set_spring(stiffness=0.0, damping=damping)
    world.step(1000)
    return {"damping": damping, "angle": float(world.coordinates[0]),
            "energy": world.kinetic_energy + world.potential_energy}


def swing_dying_once(args):
    """swing(), but the first attempt at damping 0.3 kills its worker process."""
    world, damping, marker = args
    if damping == 0.3 and not pathlib.Path(marker).exists():
        pathlib.Path(marker).write_text("killed once")
        os._exit(1)
    return swing((world, damping))


def always_fails(x):
    raise RuntimeError(f"no result for {x}")
