"""Type stubs of the linx package (docs/python.md)."""

from linx._linx import (
    Batch as Batch,
    Body as Body,
    BoundExceeded as BoundExceeded,
    BusyError as BusyError,
    CheckpointError as CheckpointError,
    ClosedError as ClosedError,
    EnergyGrowth as EnergyGrowth,
    Error as Error,
    Joint as Joint,
    NonFiniteState as NonFiniteState,
    Recording as Recording,
    SceneError as SceneError,
    StepFault as StepFault,
    World as World,
    __version__ as __version__,
    load as load,
    loads as loads,
    schema as schema,
)
from linx.pictures import Viewer as Viewer, render as render, view as view
from linx.scene import (
    Scene as Scene,
    box as box,
    capsule as capsule,
    convex as convex,
    cylinder as cylinder,
    ellipsoid as ellipsoid,
    mesh as mesh,
    plane as plane,
    sphere as sphere,
)
from linx.sweeps import (
    SweepError as SweepError,
    serial as serial,
    sweep as sweep,
    write_csv as write_csv,
)

__all__: list[str]
