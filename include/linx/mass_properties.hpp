// Mass properties of solid shapes of uniform density, and of compound bodies made of several.
#pragma once

#include <linx/body.hpp>
#include <linx/shape.hpp>
#include <linx/types.hpp>

#include <span>

namespace linx {

struct MassProperties {
  double mass = 0.0;            ///< (kg)
  Vec3 center = Vec3::Zero();   ///< centre of mass, body frame (m)
  Mat3 inertia = Mat3::Zero();  ///< about `center`, body-frame axes (kg m^2)

  /// The inertia about the body frame's origin instead of the centre of mass (parallel axes).
  Mat3 inertiaAboutOrigin() const;
};

/// Volume of a shape (m^3).
double shapeVolume(const ShapeDef& shape);

/// A solid shape of uniform density (kg/m^3), placed by its local pose in the body frame.
MassProperties shapeMassProperties(const ShapeDef& shape, double density);

/// The shapes together: total mass, common centre of mass, inertia about it.
MassProperties combine(std::span<const MassProperties> parts);

/// Whether a shape is a closed solid with a volume (all but planes and meshes).
bool isSolid(ShapeType type);

/// Gives a body the mass, centre of mass and inertia of its solid shapes at their densities. The
/// body's position moves to the shapes' common centre of mass and the shapes are moved the other
/// way in the body frame, so they stay where they were in the world; the linear velocity becomes
/// that centre's (v + w x offset). Throws std::invalid_argument
/// naming the shape if a solid shape has no density (or a non-positive one), or if the body has
/// no solid shape.
void setMassFromShapes(BodyDef& body);

/// The inertia about the body frame's origin of a body's solid shapes filled uniformly to `mass`.
/// Throws std::invalid_argument if the body has no solid shape.
Mat3 uniformShapesInertia(const BodyDef& body, double mass);

/// Completes a dynamic body's mass properties where it leaves them out (see BodyDef): no mass,
/// setMassFromShapes; a mass without inertia, that of the shapes at their densities if they have
/// them, else uniformShapesInertia. Static bodies are left as they are. Throws
/// std::invalid_argument, the message starting with the field: a mass that the shapes' densities
/// contradict (one would be ignored), an inertia without a mass, a mass without inertia and
/// without a solid shape, and what setMassFromShapes refuses.
void completeMassProperties(BodyDef& body);

}  // namespace linx
