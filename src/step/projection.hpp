// Optional post-stabilization (position projection): after a step, Newton iterations on the
// joints' position errors. Each iteration assembles the rows at the current positions and solves
//   J M^-1 J^T dl = -phi   (equality rows; limit rows that are overshot, as unilateral rows;
//                           not rows made soft by a cfm above the world's)
// with the exact solver, then moves every body by dx = M^-1 J^T dl. The correction is the
// mass-weighted smallest one, so it does not push momentum into a free mechanism.
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/solver.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace linx::step {

/// Projects the bodies' positions onto the joint constraints. Returns the largest remaining error.
/// Bodies flagged in `frozen` (sleeping ones) are held where they are, as if static.
double projectPositions(std::span<const std::unique_ptr<Joint>> joints, std::span<Body> bodies,
                        const SolverSettings& settings, std::span<const std::uint8_t> frozen = {});

}  // namespace linx::step
