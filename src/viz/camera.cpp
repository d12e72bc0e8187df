#include "viz/camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace linx::viz {

double boundingRadius(const ShapeDef& s) {
  switch (s.type) {
    case ShapeType::Sphere:
      return s.radius;
    case ShapeType::Box:
      return s.size.norm() / 2;
    case ShapeType::Capsule:
      return s.length / 2 + s.radius;
    case ShapeType::Cylinder:
      return std::hypot(s.length / 2, s.radius);
    case ShapeType::Ellipsoid:
      return s.radii.cwiseAbs().maxCoeff();
    case ShapeType::Convex:
    case ShapeType::Mesh: {
      double r = 0;
      for (const Vec3& p : s.points) r = std::max(r, p.norm());
      return r;
    }
    case ShapeType::Plane:
      break;
  }
  return 0;
}

double shapeExtent(const ShapeDef& s, const Quat& q, const Vec3& dir) {
  const Vec3 u = q.conjugate() * dir;  // dir in the shape frame
  switch (s.type) {
    case ShapeType::Sphere:
      return s.radius;
    case ShapeType::Box:
      return (s.size / 2).dot(u.cwiseAbs());
    case ShapeType::Capsule:  // capsules and cylinders are along the shape's z axis
      return std::abs(u.z()) * s.length / 2 + s.radius;
    case ShapeType::Cylinder:
      return std::abs(u.z()) * s.length / 2 +
             s.radius * std::sqrt(std::max(0.0, 1 - u.z() * u.z()));
    case ShapeType::Ellipsoid:  // the support along u: |diag(radii) u|
      return s.radii.cwiseProduct(u).norm();
    case ShapeType::Convex:
    case ShapeType::Mesh: {
      double e = -kInfinity;
      for (const Vec3& p : s.points) e = std::max(e, p.dot(u));
      return e;
    }
    case ShapeType::Plane:
      break;
  }
  return kInfinity;
}

Bounds runBounds(const Run& run) {
  Bounds b;
  bool any = false;
  const auto grow = [&](const Vec3& lo, const Vec3& hi) {
    b.min = any ? b.min.cwiseMin(lo) : lo;
    b.max = any ? b.max.cwiseMax(hi) : hi;
    any = true;
  };
  for (const Frame& frame : run.frames) {
    for (std::size_t i = 0; i < run.bodies.size(); ++i) {
      const Pose& pose = frame.poses[i];
      for (const ShapeDef& s : run.bodies[i].shapes) {
        if (s.type == ShapeType::Plane) continue;
        if (s.type == ShapeType::Mesh) {  // exact box of the (static) mesh's vertices
          for (const Vec3& p : s.points) {
            const Vec3 w = pose.position + pose.orientation * (s.position + s.orientation * p);
            grow(w, w);
          }
          continue;
        }
        // A box symmetric about the shape's origin, tighter than a bounding sphere for long shapes.
        const Vec3 c = pose.position + pose.orientation * s.position;
        const Quat q = pose.orientation * s.orientation;
        Vec3 r;
        for (int k = 0; k < 3; ++k)
          r[k] = std::max(shapeExtent(s, q, Vec3::Unit(k)), shapeExtent(s, q, -Vec3::Unit(k)));
        grow(c - r, c + r);
      }
    }
    if (run.bodies.empty()) break;
  }
  if (!any) {
    for (const Frame& frame : run.frames)
      for (const Pose& p : frame.poses) grow(p.position, p.position);
  }
  return b;
}

Camera chooseCamera(const Run& run, double aspect) {
  Camera cam;
  const SceneView view = run.view.value_or(SceneView{});
  const double g = run.gravity.norm();
  cam.up = view.up ? view.up->normalized() : g > 0 ? Vec3(-run.gravity / g) : Vec3::UnitZ();
  cam.fov = view.fov;
  const Bounds bounds = runBounds(run);
  cam.target = view.target.value_or(bounds.center());
  if (view.eye) {
    cam.eye = *view.eye;
  } else {
    // In front (-y, or -x when up is along y), a little to the side, and above.
    Vec3 front = -Vec3::UnitY() + cam.up * cam.up.y();
    if (front.norm() < 0.5) front = -Vec3::UnitX() + cam.up * cam.up.x();
    front.normalize();
    const Vec3 side = cam.up.cross(front);
    // Higher above a flat scene (a planar mechanism lying on the ground) to see its plane.
    const Vec3 extent = bounds.max - bounds.min;
    const double height = std::abs(extent.dot(cam.up));
    const double elevation =
        height < 0.3 * (extent - cam.up * extent.dot(cam.up)).norm() ? 1.2 : 0.45;
    const Vec3 dir = (front + 0.35 * side + elevation * cam.up).normalized();
    const double half = cam.fov * std::numbers::pi / 360;
    const double half_min = std::min(half, std::atan(std::tan(half) * aspect));
    const double radius = std::max(bounds.radius(), 0.05);
    const double distance = 1.08 * radius / std::sin(half_min) +
                            (view.target ? (bounds.center() - cam.target).norm() : 0.0);
    cam.eye = cam.target + distance * dir;
  }
  // Make `up` perpendicular to the line of sight.
  const Vec3 look = (cam.target - cam.eye).normalized();
  Vec3 up = cam.up - look * look.dot(cam.up);
  if (up.norm() < 1e-9) up = look.unitOrthogonal();
  cam.up = up.normalized();
  return cam;
}

std::optional<Eigen::Vector2d> project(const Camera& camera, const Vec3& point, int width,
                                       int height) {
  const Vec3 look = (camera.target - camera.eye).normalized();
  const Vec3 right = look.cross(camera.up).normalized();
  const Vec3 up = right.cross(look);
  const Vec3 d = point - camera.eye;
  const double depth = d.dot(look);
  if (!(depth > 0)) return std::nullopt;
  const double f = (height / 2.0) / std::tan(camera.fov * std::numbers::pi / 360);
  return Eigen::Vector2d(width / 2.0 + f * d.dot(right) / depth,
                         height / 2.0 - f * d.dot(up) / depth);
}

}  // namespace linx::viz
