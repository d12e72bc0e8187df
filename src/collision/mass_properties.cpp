// Closed forms for solids of revolution and boxes (shape frame, about the shape's centre), moved
// into the body frame by the shape's pose, and combined with the parallel-axis theorem. A convex
// hull's volume, centroid and inertia come from tetrahedra over its faces (collision/geometry.hpp);
// its points need not be centred: the centre of mass is the hull's centroid placed by the pose.
#include <linx/mass_properties.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "collision/geometry.hpp"

namespace linx {

namespace {
constexpr double kPi = std::numbers::pi;

Mat3 parallelAxis(double m, const Vec3& d) {
  return m * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
}

/// Principal moments of a solid shape of mass m about its centre, in the shape's frame.
Vec3 moments(const ShapeDef& s, double m) {
  const double r2 = s.radius * s.radius;
  switch (s.type) {
    case ShapeType::Sphere:
      return Vec3::Constant(0.4 * m * r2);
    case ShapeType::Box: {
      const Vec3 l2 = s.size.cwiseProduct(s.size);
      return m / 12.0 * Vec3(l2.y() + l2.z(), l2.x() + l2.z(), l2.x() + l2.y());
    }
    case ShapeType::Cylinder: {
      const double side = m * (3.0 * r2 + s.length * s.length) / 12.0;
      return Vec3(side, side, 0.5 * m * r2);
    }
    case ShapeType::Capsule: {
      // A cylinder of length L and two hemispherical caps, the mass split by volume; each cap's
      // centroid lies 3r/8 beyond the end of the cylinder.
      const double L = s.length, r = s.radius;
      const double cylinder = L, caps = 4.0 / 3.0 * r;  // volumes over pi r^2
      const double mc = m * cylinder / (cylinder + caps), ms = m - mc;
      const double side =
          mc * (L * L / 12.0 + r2 / 4.0) + ms * (0.4 * r2 + L * L / 4.0 + 3.0 * L * r / 8.0);
      return Vec3(side, side, 0.5 * mc * r2 + 0.4 * ms * r2);
    }
    case ShapeType::Ellipsoid: {  // m/5 (b^2 + c^2), m/5 (a^2 + c^2), m/5 (a^2 + b^2)
      const Vec3 a2 = s.radii.cwiseProduct(s.radii);
      return m / 5.0 * Vec3(a2.y() + a2.z(), a2.x() + a2.z(), a2.x() + a2.y());
    }
    case ShapeType::Plane:
    case ShapeType::Convex:
    case ShapeType::Mesh:
      break;  // not solids of a closed form: see shapeVolume / shapeMassProperties
  }
  return Vec3::Zero();
}
}  // namespace

Mat3 MassProperties::inertiaAboutOrigin() const {
  return inertia + parallelAxis(mass, center);
}

double shapeVolume(const ShapeDef& s) {
  const double r = s.radius;
  switch (s.type) {
    case ShapeType::Sphere:
      return 4.0 / 3.0 * kPi * r * r * r;
    case ShapeType::Box:
      return s.size.prod();
    case ShapeType::Cylinder:
      return kPi * r * r * s.length;
    case ShapeType::Capsule:
      return kPi * r * r * s.length + 4.0 / 3.0 * kPi * r * r * r;
    case ShapeType::Ellipsoid:
      return 4.0 / 3.0 * kPi * s.radii.prod();
    case ShapeType::Plane:
    case ShapeType::Mesh:
      throw std::invalid_argument(fmt::format(
          "a {} shape has no volume (it belongs on a static body)", shapeTypeName(s.type)));
    case ShapeType::Convex:
      return collision::Geometry::convexHull(s.points)->volume();
  }
  return 0.0;
}

MassProperties shapeMassProperties(const ShapeDef& shape, double density) {
  MassProperties p;
  if (shape.type == ShapeType::Convex) {
    // The hull's inertia per unit density about its centroid, rotated into the body frame.
    const auto hull = collision::Geometry::convexHull(shape.points);
    const Mat3 r = shape.orientation.normalized().toRotationMatrix();
    p.mass = density * hull->volume();
    p.center = shape.position + r * hull->centroid();
    p.inertia = density * (r * hull->unitInertia() * r.transpose());
    return p;
  }
  p.mass = density * shapeVolume(shape);
  p.center = shape.position;
  const Mat3 r = shape.orientation.normalized().toRotationMatrix();
  p.inertia = r * moments(shape, p.mass).asDiagonal() * r.transpose();
  return p;
}

MassProperties combine(std::span<const MassProperties> parts) {
  MassProperties total;
  for (const MassProperties& p : parts) {
    total.mass += p.mass;
    total.center += p.mass * p.center;
  }
  if (total.mass <= 0.0) return MassProperties{};
  total.center /= total.mass;
  for (const MassProperties& p : parts)
    total.inertia += p.inertia + parallelAxis(p.mass, p.center - total.center);
  return total;
}

bool isSolid(ShapeType type) {
  return type != ShapeType::Plane && type != ShapeType::Mesh;
}

// Mass properties computed from shapes' sizes (and densities) that a double cannot hold, or that
// vanish: named against the shapes, which the user gave, not the mass or inertia, which they did
// not.
void checkMadeFromShapes(double mass, const Mat3& inertia) {
  if (!(mass > 0.0 && std::isfinite(mass)))
    throw std::invalid_argument(
        fmt::format("shapes: their sizes and densities make a mass of {:.3g} kg, too {} to "
                    "simulate",
                    mass, mass > 0.0 ? "large" : "small"));
  const double largest = inertia.cwiseAbs().maxCoeff();
  if (!std::isfinite(largest) || !(inertia.diagonal().minCoeff() > 0.0))
    throw std::invalid_argument(
        fmt::format("shapes: their sizes and densities make an inertia of {:.3g} kg m^2, too {} to "
                    "simulate (give the "
                    "inertia, or shapes of a size between a micrometre and a kilometre)",
                    largest, std::isfinite(largest) ? "small" : "large"));
}

void setMassFromShapes(BodyDef& body) {
  std::vector<MassProperties> parts;
  for (std::size_t k = 0; k < body.shapes.size(); ++k) {
    const ShapeDef& s = body.shapes[k];
    if (!isSolid(s.type)) continue;
    if (!s.density || !(*s.density >= 0.0) || !std::isfinite(*s.density))
      throw std::invalid_argument(
          fmt::format("shapes[{}].density: a density >= 0 is needed to compute the mass", k));
    // Density 0: a massless shape (it collides, it weighs nothing: MJCF's mass="0" geoms).
    if (*s.density > 0.0) parts.push_back(shapeMassProperties(s, *s.density));
  }
  const bool solid = std::any_of(body.shapes.begin(), body.shapes.end(),
                                 [](const ShapeDef& s) { return isSolid(s.type); });
  if (!solid) throw std::invalid_argument("shapes: no solid shape to compute the mass from");
  if (parts.empty())
    throw std::invalid_argument("shapes: every density is 0: no mass to compute (give one > 0)");
  const MassProperties total = combine(parts);
  checkMadeFromShapes(total.mass, total.inertia);
  body.mass = total.mass;
  body.inertia = total.inertia;
  // The stated position and velocity were the shapes' origin's; the body's are its centre's.
  const Vec3 offset = body.orientation.normalized() * total.center;
  body.position += offset;
  body.linear_velocity += body.angular_velocity.cross(offset);
  for (ShapeDef& s : body.shapes) s.position -= total.center;
}

Mat3 uniformShapesInertia(const BodyDef& body, double mass) {
  double volume = 0.0;
  for (const ShapeDef& s : body.shapes)
    if (isSolid(s.type)) volume += shapeVolume(s);
  const bool solid = std::any_of(body.shapes.begin(), body.shapes.end(),
                                 [](const ShapeDef& s) { return isSolid(s.type); });
  if (!solid)
    throw std::invalid_argument("inertia: missing (give it, or a solid shape to compute it from)");
  if (!(volume > 0.0 && std::isfinite(volume)))
    throw std::invalid_argument(
        fmt::format("shapes: their volume, {:.3g} m^3, is too {} to compute the inertia from (give "
                    "the inertia)",
                    volume, volume > 0.0 ? "large" : "small"));
  std::vector<MassProperties> parts;
  for (const ShapeDef& s : body.shapes)
    if (isSolid(s.type)) parts.push_back(shapeMassProperties(s, mass / volume));
  const Mat3 inertia = combine(parts).inertiaAboutOrigin();
  checkMadeFromShapes(mass, inertia);
  return inertia;
}

void completeMassProperties(BodyDef& body) {
  if (body.is_static || body.kinematic) return;
  const bool densities = std::any_of(body.shapes.begin(), body.shapes.end(), [](const ShapeDef& s) {
    return isSolid(s.type) && s.density.has_value();
  });
  if (!body.mass) {
    if (body.inertia)
      throw std::invalid_argument("inertia: give the mass with the inertia, or neither");
    setMassFromShapes(body);  // names a shape without a density, or the lack of shapes
    return;
  }
  if (densities) {
    // Both: they must agree (a body read from a scene has both, the mass made from the densities).
    BodyDef from_shapes = body;
    from_shapes.mass.reset();
    from_shapes.inertia.reset();
    setMassFromShapes(from_shapes);
    if (!(std::abs(*from_shapes.mass - *body.mass) <= 1e-9 * *body.mass))
      throw std::invalid_argument(
          fmt::format("mass: {} kg, but the shapes' densities make {} kg (give one or the other)",
                      *body.mass, *from_shapes.mass));
    if (!body.inertia) body = from_shapes;
    return;
  }
  if (!body.inertia) body.inertia = uniformShapesInertia(body, *body.mass);
}

}  // namespace linx
