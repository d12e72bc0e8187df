// The binary form of a world's state between steps (World::saveState, checkpoints): one class
// that either writes values to a byte buffer or reads them back in the same order, so that each
// part of the state lists its fields once, in a persist(Archive&) of its own. Values are stored
// in the machine's byte order (checkpoints record it and refuse another). Reading checks every
// length against what is left, so a damaged buffer throws StateError, never reads past its end.
#pragma once

#include <linx/row.hpp>
#include <linx/types.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace linx::state {

/// A state that cannot be read back: truncated, damaged, or of another world.
class StateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Archive;

template <class T>
concept Persistent = requires(T& x, Archive& a) {
  x.persist(a);
};

class Archive {
 public:
  /// Appends what it is given to `out`.
  static Archive writer(std::vector<std::byte>& out) { return Archive(&out, {}); }
  /// Reads from `in`, which must outlive the archive.
  static Archive reader(std::span<const std::byte> in) { return Archive(nullptr, in); }

  bool loading() const { return out_ == nullptr; }
  /// Whether a reader has read everything.
  bool atEnd() const { return in_.empty(); }

  void bytes(void* data, std::size_t size) {
    if (out_) {
      const auto* p = static_cast<const std::byte*>(data);
      out_->insert(out_->end(), p, p + size);
      return;
    }
    if (size > in_.size()) throw StateError("the state ends early");
    if (size > 0) std::memcpy(data, in_.data(), size);
    in_ = in_.subspan(size);
  }

  template <class T>
  requires std::is_arithmetic_v<T> || std::is_enum_v<T>
  void operator()(T& x) { bytes(&x, sizeof x); }
  /// A bool as one byte, 0 or 1: any other byte read back is refused (it is no bool's value).
  void operator()(bool& x) {
    std::uint8_t byte = x ? 1 : 0;
    bytes(&byte, 1);
    if (byte > 1) throw StateError("a boolean that is neither 0 nor 1");
    x = byte == 1;
  }
  /// Fixed-size matrices, and those of a bounded size (JointCoordinates) with their size.
  template <class Scalar, int R, int C, int O, int MR, int MC>
  void operator()(Eigen::Matrix<Scalar, R, C, O, MR, MC>& m) {
    if constexpr (R > 0 && C > 0) {
      bytes(m.data(), sizeof(Scalar) * R * C);
    } else {
      static_assert(MR > 0 && MC > 0, "matrices of a bounded size only");
      std::int64_t rows = m.rows(), cols = m.cols();
      (*this)(rows);
      (*this)(cols);
      if (loading()) {
        if (rows < 0 || rows > MR || cols < 0 || cols > MC || (R > 0 && rows != R) ||
            (C > 0 && cols != C))
          throw StateError("a matrix of an impossible size");
        m.resize(rows, cols);
      }
      bytes(m.data(), sizeof(Scalar) * static_cast<std::size_t>(rows * cols));
    }
  }
  void operator()(Quat& q) { bytes(q.coeffs().data(), sizeof(double) * 4); }
  void operator()(Row& r) {
    fields(r.Ja, r.Jb, r.phi, r.speed, r.lo, r.hi, r.erp, r.cfm, r.kind, r.normal, r.mu, r.key,
           r.body_a, r.body_b, r.Jc, r.Jd, r.body_c, r.body_d);
  }
  void operator()(Pose& p) {
    (*this)(p.position);
    (*this)(p.orientation);
  }
  void operator()(std::string& s) {
    std::uint64_t n = s.size();
    (*this)(n);
    if (loading()) s.resize(checkedCount(n, 1));
    bytes(s.data(), s.size());
  }
  template <Persistent T>
  void operator()(T& x) {
    x.persist(*this);
  }
  /// Several values in order: a plain struct's fields.
  template <class... T>
  void fields(T&... x) {
    ((*this)(x), ...);
  }
  /// A vector of plain structs, each through `each(archive, item)`.
  template <class T, class F>
  void each(std::vector<T>& v, F&& item) {
    std::uint64_t n = v.size();
    (*this)(n);
    if (loading()) v.resize(checkedCount(n, 1));
    for (T& x : v) item(*this, x);
  }
  template <class T>
  void operator()(std::optional<T>& x) {
    bool has = x.has_value();
    (*this)(has);
    if (loading()) {
      if (has)
        x.emplace();
      else
        x.reset();
    }
    if (has) (*this)(*x);
  }
  template <class T, class U>
  void operator()(std::pair<T, U>& p) {
    (*this)(p.first);
    (*this)(p.second);
  }
  template <class T, std::size_t N>
  void operator()(std::array<T, N>& a) {
    for (T& x : a) (*this)(x);
  }
  template <class T>
  void operator()(std::vector<T>& v) {
    std::uint64_t n = v.size();
    (*this)(n);
    if (loading())
      v.resize(checkedCount(n, std::is_arithmetic_v<T> || std::is_enum_v<T> ? sizeof(T) : 1));
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      bytes(v.data(), v.size() * sizeof(T));
    } else {
      for (T& x : v) (*this)(x);
    }
  }

  /// A count read back, refused when what is left cannot hold that many items of at least
  /// `min_size` bytes (a damaged length must not allocate the machine's memory).
  std::size_t checkedCount(std::uint64_t n, std::size_t min_size) const {
    if (min_size > 0 && n > in_.size() / min_size) throw StateError("the state ends early");
    return static_cast<std::size_t>(n);
  }

 private:
  Archive(std::vector<std::byte>* out, std::span<const std::byte> in) : out_(out), in_(in) {}

  std::vector<std::byte>* out_;
  std::span<const std::byte> in_;
};

}  // namespace linx::state
