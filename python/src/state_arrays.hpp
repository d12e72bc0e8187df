// The world's state as numpy arrays, in body (joint) order: read as new read-only arrays, written
// from any array-like of the right shape (docs/python.md, "State").
#pragma once

#include "py_world.hpp"

#include <pybind11/numpy.h>

#include <string>

namespace linx::python {

/// A new C-ordered float64 array of the given shape, marked read-only once filled (readOnly).
pybind11::array_t<double> newArray(std::initializer_list<pybind11::ssize_t> shape);
/// Clears the array's writeable flag: it is a copy, and writing into it would change nothing.
pybind11::array_t<double> readOnly(pybind11::array_t<double> a);

/// `value` as a float64 array of `rows` x `columns` (columns 0: a vector of `rows`), or ValueError
/// naming `what`, the shape expected and the shape given, or the first entry that is not finite.
pybind11::array_t<double, pybind11::array::c_style> matrixArgument(pybind11::handle value,
                                                                   pybind11::ssize_t rows,
                                                                   pybind11::ssize_t columns,
                                                                   const std::string& what);
/// `value` as a float64 array of exactly `shape`, checked as matrixArgument does.
pybind11::array_t<double, pybind11::array::c_style> arrayArgument(
    pybind11::handle value, const std::vector<pybind11::ssize_t>& shape, const std::string& what);
/// A 3-vector argument (a force, a position).
Vec3 vectorArgument(pybind11::handle value, const std::string& what);
/// A quaternion argument (w, x, y, z), normalized; ValueError for a zero one.
Quat quaternionArgument(pybind11::handle value, const std::string& what);

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

/// Binds the array properties of linx.World (positions, velocities, coordinates, contacts, ...).
void bindStateArrays(pybind11::class_<PyWorld, std::shared_ptr<PyWorld>>& world);

}  // namespace linx::python
