// Arguments from Python checked and converted (numbers, vectors, quaternions, arrays of a given
// shape), and the read-only numpy arrays the state comes back in.
#pragma once

#include <linx/types.hpp>

#include <pybind11/numpy.h>

#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

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
/// ValueError unless `threads` is a count of worker threads a world takes ([0, kMaxThreads]).
void checkThreads(int threads);
/// A 3-vector argument (a force, a position).
Vec3 vectorArgument(pybind11::handle value, const std::string& what);
/// A quaternion argument (w, x, y, z), normalized; ValueError for a zero one.
Quat quaternionArgument(pybind11::handle value, const std::string& what);
/// (w, x, y, z) scaled to unit length without overflow or underflow (divided by its stableNorm, as
/// the scene reader does: (1e200, 1e200, 0, 0) is the rotation (0.7071, 0.7071, 0, 0)), or nullopt
/// for the zero quaternion, which is no rotation.
std::optional<Quat> unitQuaternion(const double* wxyz);

/// A Python int of any size, or whatever stands for one (numpy's integers; not a bool): its value
/// clamped to the range of long long, and its digits for messages. Every call that takes an index
/// takes one, so that 10**20 is an index out of range (IndexError, or the ValueError of a
/// coordinate out of range) rather than a number pybind11 cannot convert.
struct Index {
  long long value = 0;
  std::string text;
  bool fitsInt() const;
};
/// `value` as an Index, or nullopt if it is not an int.
std::optional<Index> indexArgument(pybind11::handle value);

}  // namespace linx::python

namespace pybind11::detail {
template <>
struct type_caster<linx::python::Index> {
  PYBIND11_TYPE_CASTER(linx::python::Index, const_name("int"));
  bool load(handle src, bool /*convert*/) {
    auto index = linx::python::indexArgument(src);
    if (!index) return false;
    value = std::move(*index);
    return true;
  }
  static handle cast(const linx::python::Index& index, return_value_policy, handle) {
    return PyLong_FromLongLong(index.value);
  }
};
}  // namespace pybind11::detail
