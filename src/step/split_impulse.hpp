// Which rows' position errors the split impulse removes (step/island_solver.hpp): a contact's
// penetration, unless the contact is a spring. A contact's rows carry bit 63 of their key
// (step/contact_stage); bit 62 marks a contact whose law is a spring and damper (contact
// stiffness and damping), whose push is a force that belongs in the velocity.
#pragma once

#include <linx/row.hpp>

#include <cstdint>

namespace linx::step {

inline constexpr std::uint64_t kContactKey = std::uint64_t{1} << 63;
inline constexpr std::uint64_t kSpringContactKey = std::uint64_t{1} << 62;

/// A contact's normal row with a penetration to push out (phi < 0: deeper than its slop) that
/// is not a spring's.
inline bool splitsPenetration(const Row& r) {
  return r.kind == RowKind::Unilateral && (r.key & kContactKey) != 0 &&
         (r.key & kSpringContactKey) == 0 && r.phi < 0.0;
}

}  // namespace linx::step
