"""Scenes built in code: the fields of a scene file (docs/scene-format.md) as keyword arguments.

    scene = linx.Scene(timestep=1e-3)
    scene.body("bob", mass=1.0, position=[1, 0, 0], shapes=[linx.sphere(0.05)])
    scene.joint("hinge", "bob", name="pivot", anchor=[0, 0, 0], axis=[0, 1, 0],
                limits={"lower": -1, "upper": 1})
    world = scene.build()

The scene is checked by the same reader as a scene file: a mistake raises linx.SceneError naming
the field as a path (`bodies[0].mass`), whichever way it was written.
"""

from __future__ import annotations

import json
import math
from typing import Any, Iterable, Optional

from linx._linx import SceneError, World, loads

__all__ = ["Scene", "sphere", "box", "capsule", "cylinder", "plane", "convex", "mesh"]


def _plain(value: Any) -> Any:
    """numpy arrays and numbers as JSON's lists and numbers."""
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def _non_finite(value: Any, path: str) -> Optional[tuple[str, float]]:
    """The path (`bodies[0].mass`) and value of the first NaN or infinity in `value`, or None."""
    if isinstance(value, float) and not math.isfinite(value):
        return path, value
    items = (value.items() if isinstance(value, dict)
             else enumerate(value) if isinstance(value, list) else ())
    for key, item in items:
        found = _non_finite(item, f"{path}.{key}" if isinstance(key, str) else f"{path}[{key}]")
        if found:
            return found
    return None


class Scene:
    """A scene under construction. Top-level fields (gravity, timestep, duration, threads, solver,
    integrator, contact, sleep, faults, view) are keyword arguments; bodies, joints, springs,
    forces and torques are added in order with the methods below, each taking its scene-file
    fields."""

    def __init__(self, **fields: Any) -> None:
        self._top: dict[str, Any] = {k: _plain(v) for k, v in fields.items()}
        self._bodies: list[dict[str, Any]] = []
        self._joints: list[dict[str, Any]] = []
        self._springs: list[dict[str, Any]] = []
        self._forces: list[dict[str, Any]] = []
        self._torques: list[dict[str, Any]] = []

    def body(self, name: str, *, shapes: Iterable[dict[str, Any]] = (), **fields: Any) -> str:
        """Adds a body (mass, inertia, position, orientation, linear_velocity, angular_velocity,
        static, kinematic, path, linear_damping, angular_damping) with its shapes (sphere(), box(),
        ...). Returns its name, for joints."""
        self._bodies.append({"name": name, **_plain(fields), "shapes": [_plain(s) for s in shapes]})
        return name

    def joint(self, type: str, body1: str, body2: str = "world", *, name: Optional[str] = None,
              **fields: Any) -> str:
        """Adds a joint of `type` ("hinge", "slider", "ball", ...) between two bodies (or a body
        and the world) with its fields: anchor, axis, axis1, axis2, limits, motor, spring,
        friction, armature, force, reference, initial, break_force, erp, cfm, collide, ...
        Returns its name (by default "TYPE_N")."""
        name = name or f"{type}_{len(self._joints)}"
        self._joints.append({"name": name, "type": type, "body1": body1, "body2": body2,
                             **_plain(fields)})
        return name

    def spring(self, body1: str, body2: str = "world", *, name: Optional[str] = None,
               **fields: Any) -> str:
        """Adds a spring and damper between two points (anchor1, anchor2, stiffness, damping,
        rest_length). Returns its name."""
        name = name or f"springs[{len(self._springs)}]"
        self._springs.append({"name": name, "body1": body1, "body2": body2, **_plain(fields)})
        return name

    def force(self, body: str, force: Any, **fields: Any) -> None:
        """A force (N, world frame) on the body at every step: a vector or a table in time
        ({"times": [...], "values": [...]}); `point` where it acts."""
        self._forces.append({"body": body, "force": _plain(force), **_plain(fields)})

    def torque(self, body: str, torque: Any, **fields: Any) -> None:
        """A torque (N m, world frame) on the body at every step, constant or a table in time."""
        self._torques.append({"body": body, "torque": _plain(torque), **_plain(fields)})

    def set(self, **fields: Any) -> "Scene":
        """Sets top-level fields (solver={"type": "soft"}, contact={...}, gravity=[...])."""
        self._top.update({k: _plain(v) for k, v in fields.items()})
        return self

    def to_dict(self) -> dict[str, Any]:
        """The scene as a scene file's JSON object."""
        d = dict(self._top)
        d["bodies"] = self._bodies
        for key, items in (("joints", self._joints), ("springs", self._springs),
                           ("forces", self._forces), ("torques", self._torques)):
            if items:
                d[key] = items
        return d

    def to_json(self, file: str = "<linx.Scene>") -> str:
        """The scene as the text of a scene file. A NaN or an infinity, which JSON cannot hold,
        raises linx.SceneError naming its field (`bodies[0].mass`) and `file`."""
        d = self.to_dict()
        found = _non_finite(d, "")
        if found:
            field, value = found[0].lstrip("."), found[1]
            problem = f"must be a finite number, got {value}"
            error = SceneError(f"{file}: {field}: {problem}")
            error.file, error.field, error.problem = file, field, problem
            raise error
        return json.dumps(d, indent=2, allow_nan=False)

    def build(self, file: str = "<linx.Scene>") -> World:
        """The world of the scene. Raises linx.SceneError naming the field at fault."""
        return loads(self.to_json(file), file)


def _shape(type: str, **fields: Any) -> dict[str, Any]:
    return {"type": type, **_plain(fields)}


def sphere(radius: float, **fields: Any) -> dict[str, Any]:
    """A sphere (m); fields: position, orientation, density, friction, restitution, group, mask."""
    return _shape("sphere", radius=radius, **fields)


def box(size: Any, **fields: Any) -> dict[str, Any]:
    """A box of full edge lengths [lx, ly, lz] (m)."""
    return _shape("box", size=size, **fields)


def capsule(radius: float, length: float, **fields: Any) -> dict[str, Any]:
    """A capsule along its z axis: `length` between the cap centres (m)."""
    return _shape("capsule", radius=radius, length=length, **fields)


def cylinder(radius: float, length: float, **fields: Any) -> dict[str, Any]:
    """A cylinder along its z axis (m)."""
    return _shape("cylinder", radius=radius, length=length, **fields)


def ellipsoid(radii: Any, **fields: Any) -> dict[str, Any]:
    """An ellipsoid of semi-axes [a, b, c] along its x, y, z (m)."""
    return _shape("ellipsoid", radii=radii, **fields)


def plane(normal: Any = (0.0, 0.0, 1.0), offset: float = 0.0, **fields: Any) -> dict[str, Any]:
    """A plane (static bodies only): the points x with normal . x = offset; solid below."""
    return _shape("plane", normal=normal, offset=offset, **fields)


def convex(points: Any, **fields: Any) -> dict[str, Any]:
    """The convex hull of points (m, shape frame)."""
    return _shape("convex", points=points, **fields)


def mesh(file: Optional[str] = None, *, points: Any = None, triangles: Any = None,
         **fields: Any) -> dict[str, Any]:
    """A triangle mesh (static bodies only): an .obj or .stl file, or points and triangles."""
    if file is not None:
        return _shape("mesh", file=file, **fields)
    return _shape("mesh", points=points, triangles=triangles, **fields)
