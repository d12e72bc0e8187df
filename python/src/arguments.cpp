#include "arguments.hpp"

#include <linx/world.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace py = pybind11;

namespace linx::python {

py::array_t<double> newArray(std::initializer_list<py::ssize_t> shape) {
  return py::array_t<double>(std::vector<py::ssize_t>(shape));
}

py::array_t<double> readOnly(py::array_t<double> a) {
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

namespace {

std::string shapeText(const py::array& a) {
  std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
  if (shape.size() == 1) return fmt::format("({},)", shape[0]);
  return fmt::format("({})", fmt::join(shape, ", "));
}

}  // namespace

py::array_t<double, py::array::c_style> arrayArgument(py::handle value,
                                                      const std::vector<py::ssize_t>& shape,
                                                      const std::string& what) {
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  const auto typeName = [&] { return std::string(py::str(py::type::of(value).attr("__name__"))); };
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) || value.is_none())
    throw py::type_error(fmt::format("{}: expected an array of numbers, got {}", what, typeName()));
  // Real numbers only: a forced cast would drop imaginary parts and read strings.
  const py::array raw = py::array::ensure(value);
  if (!raw)
    throw py::type_error(fmt::format("{}: expected an array of numbers, got {}", what, typeName()));
  const char kind = raw.dtype().kind();
  if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f')
    throw py::type_error(fmt::format("{}: expected real numbers, got an array of {}", what,
                                     std::string(py::str(raw.dtype()))));
  Array a = Array::ensure(raw);
  if (!a)
    throw py::type_error(fmt::format("{}: expected an array of numbers, got {}", what, typeName()));
  const bool ok = static_cast<std::size_t>(a.ndim()) == shape.size() &&
                  std::equal(shape.begin(), shape.end(), a.shape());
  if (!ok) {
    const std::string expected = shape.size() == 1 ? fmt::format("({},)", shape[0])
                                                   : fmt::format("({})", fmt::join(shape, ", "));
    throw py::value_error(
        fmt::format("{}: expected shape {}, got {}", what, expected, shapeText(a)));
  }
  const double* data = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    if (std::isfinite(data[i])) continue;
    std::string index;  // the entry's indices, [i][j][k]
    for (py::ssize_t rest = i, d = a.ndim() - 1; d >= 0; rest /= a.shape(d), --d)
      index = fmt::format("[{}]", rest % a.shape(d)) + index;
    throw py::value_error(fmt::format("{}{}: {} is not finite", what, index, data[i]));
  }
  return a;
}

py::array_t<double, py::array::c_style> matrixArgument(py::handle value, py::ssize_t rows,
                                                       py::ssize_t columns,
                                                       const std::string& what) {
  return columns == 0 ? arrayArgument(value, {rows}, what)
                      : arrayArgument(value, {rows, columns}, what);
}

void checkThreads(int threads) {
  if (threads < 0 || threads > kMaxThreads)
    throw py::value_error(
        fmt::format("threads: must be in [0, {}] (0: one per core)", kMaxThreads));
}

Vec3 vectorArgument(py::handle value, const std::string& what) {
  const auto a = matrixArgument(value, 3, 0, what);
  return Vec3(a.data()[0], a.data()[1], a.data()[2]);
}

Quat quaternionArgument(py::handle value, const std::string& what) {
  const auto a = matrixArgument(value, 4, 0, what);
  const double* d = a.data();
  const std::optional<Quat> q = unitQuaternion(d);
  if (!q) throw py::value_error(fmt::format("{}: a zero quaternion is no rotation", what));
  return *q;
}

std::optional<Quat> unitQuaternion(const double* wxyz) {
  const Eigen::Vector4d c(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
  const double length = c.stableNorm();
  if (!(length > 0)) return std::nullopt;
  return Quat(c[0] / length, c[1] / length, c[2] / length, c[3] / length);  // w, x, y, z
}

bool Index::fitsInt() const {
  return value >= std::numeric_limits<int>::min() && value <= std::numeric_limits<int>::max();
}

std::optional<Index> indexArgument(py::handle value) {
  if (!PyIndex_Check(value.ptr()) || py::isinstance<py::bool_>(value)) return std::nullopt;
  const auto number = py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr()));
  if (!number) throw py::error_already_set();
  int overflow = 0;
  Index index;
  index.value = PyLong_AsLongLongAndOverflow(number.ptr(), &overflow);
  if (overflow != 0)
    index.value = overflow > 0 ? std::numeric_limits<long long>::max()
                               : std::numeric_limits<long long>::min();
  try {
    index.text = py::str(number);
  } catch (const py::error_already_set&) {  // more digits than Python writes out
    index.text = overflow > 0 ? "(an int of thousands of digits)"
                              : "(a negative int of thousands of digits)";
  }
  return index;
}

}  // namespace linx::python
