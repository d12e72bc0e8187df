// The camera of every picture of a run: the scene's `view` where it gives one, otherwise chosen
// from the bounding box of everything the run draws over all its frames (docs/visualization.md,
// "Camera"). POV-Ray frames and the browser viewer start from the same camera.
#pragma once

#include "viz/run.hpp"

namespace linx::viz {

struct Camera {
  Vec3 eye = Vec3(3, -4, 2);
  Vec3 target = Vec3::Zero();
  Vec3 up = Vec3::UnitZ();  ///< unit, perpendicular to target - eye
  double fov = 40.0;        ///< vertical field of view (degrees)
};

/// The farthest a shape reaches from its origin along the unit direction `dir` (world frame) when
/// its frame is turned by `q`: the largest (q x) . dir over its points x. Infinite for planes.
double shapeExtent(const ShapeDef& s, const Quat& q, const Vec3& dir);
/// Radius of a sphere about the shape's origin that holds the whole shape (0 for planes).
double boundingRadius(const ShapeDef& s);

/// Axis-aligned bounds of all bounded shapes (planes excluded) over all frames; the bodies'
/// centres when no shape is bounded.
struct Bounds {
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();
  Vec3 center() const { return (min + max) / 2; }
  double radius() const { return (max - min).norm() / 2; }
};
Bounds runBounds(const Run& run);

/// The camera for a picture of `aspect` = width / height. Unset parts of the scene's view are
/// filled in: target the centre of the bounds, up against gravity, and an eye above and in front,
/// far enough that the bounds' sphere fits the picture.
Camera chooseCamera(const Run& run, double aspect);

/// Where a world point lands in a picture of width x height pixels taken by `camera` (pixel
/// coordinates, origin top left, y down); nothing for points behind the camera.
std::optional<Eigen::Vector2d> project(const Camera& camera, const Vec3& point, int width,
                                       int height);

}  // namespace linx::viz
