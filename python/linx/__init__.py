"""linx: rigid multibody dynamics from Python (docs/python.md).

    import linx
    world = linx.load("examples/pendulum.json")
    world.step(1000)
    print(world.time, world.positions)
"""

from linx._linx import (
    Batch,
    Body,
    BoundExceeded,
    BusyError,
    CheckpointError,
    ClosedError,
    EnergyGrowth,
    Error,
    Joint,
    NonFiniteState,
    Recording,
    SceneError,
    StepFault,
    World,
    __version__,
    load,
    loads,
    schema,
)

__all__ = [
    "Batch", "Body", "BoundExceeded", "BusyError", "CheckpointError", "ClosedError",
    "EnergyGrowth", "Error", "Joint", "NonFiniteState", "Recording", "SceneError", "StepFault",
    "World", "__version__", "load", "loads", "schema",
]

from linx.pictures import Viewer, render, view
from linx.scene import Scene, box, capsule, convex, cylinder, ellipsoid, mesh, plane, sphere
from linx.sweeps import SweepError, serial, sweep, write_csv

__all__ += [
    "Viewer", "render", "view", "Scene", "box", "capsule", "convex", "cylinder", "ellipsoid",
    "mesh", "plane",
    "sphere", "SweepError", "serial", "sweep", "write_csv",
]
