// The world's state as numpy arrays, in body (joint) order: read as new read-only arrays, written
// from any array-like of the right shape (docs/python.md, "State").
#pragma once

#include "arguments.hpp"
#include "py_world.hpp"

#include <pybind11/numpy.h>

#include <string>

namespace linx::python {

enum class BodyField { Position, Orientation, LinearVelocity, AngularVelocity };

/// The field of one body into out[0..3) (a quaternion: out[0..4), w x y z); returns the count.
int readBody(const Body& body, BodyField field, double* out);
/// (bodies x 3) or (bodies x 4: w, x, y, z) of the field, into `out` (a row per body).
void readBodies(const World& world, const std::vector<BodyId>& bodies, BodyField field,
                double* out);
/// Writes the field of every body from `rows` (checked by matrixArgument). Static bodies keep a
/// zero velocity (ValueError for another); bodies moved or set moving are woken.
/// `what`: how messages name the value (default: the field's array, `positions[3]`).
void writeBodies(World& world, const std::vector<BodyId>& bodies, BodyField field,
                 const double* rows, const char* what = nullptr);
int fieldColumns(BodyField field);
const char* fieldName(BodyField field);

/// Binds World.contacts and its class World.Contacts (contact_arrays.cpp).
void bindContactArrays(pybind11::class_<PyWorld, std::shared_ptr<PyWorld>>& world);

/// Binds the array properties of linx.World (positions, velocities, coordinates, contacts, ...).
void bindStateArrays(pybind11::class_<PyWorld, std::shared_ptr<PyWorld>>& world);

}  // namespace linx::python
