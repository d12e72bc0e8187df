// The magnitudes a world holds in doubles: what a body's definition, a scene's timestep and the
// step's fault check are bounded by (docs/solver.md#faults, docs/reliability.md "Inputs").
#pragma once

namespace linx {

/// The farthest (m) a body's centre or a shape's geometry may lie from the origin, and the
/// largest a shape may be. Doubles at 1e8 m are 1.5e-8 m apart, so contact points and depths
/// there resolve more than 30,000 times finer than the default slop (5e-4 m); at 1e16 m they are
/// 2 m apart. (A capsule 1e30 m long half inside the ground fell through it: its contact was
/// found, 5e29 m deep, but its mass of 3e31 kg made the contact row's compliance, cfm = 1e-10,
/// outweigh its inverse mass 3e21 times, and the row held it with 3e-22 of its weight.)
inline constexpr double kMaxExtent = 1e8;

/// The shortest timestep (s): the step forms h^2 (the geometric stiffness, the soft contacts'
/// coefficients) and divides by h, and h = 1e-150 keeps h^2 = 1e-300 a normal double (above
/// 2.2e-308) and 1 / h^2 finite.
inline constexpr double kMinTimestep = 1e-150;

}  // namespace linx
