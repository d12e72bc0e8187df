// Joints a model may have but hardly means to, named with a warning (linx check, run and convert
// print it):
// - joints that repeat one another: the same type between the same two bodies, at the same anchor
//   and axis. Their rows are linearly dependent, which the exact solver survives only by solving
//   them densely (a thousand identical hinges took 100 s a step);
// - joints and springs between two things that never move (static bodies, the world): they never
//   act.
#pragma once

#include <linx/scene.hpp>

#include <string>
#include <vector>

namespace linx::io {

/// Every warning below, repeated joints first.
std::vector<std::string> jointWarnings(const Scene& scene);
/// One warning per group of repeated joints, naming the first and how many repeat it.
std::vector<std::string> redundantJointWarnings(const Scene& scene);
/// One warning per joint or spring whose two bodies never move.
std::vector<std::string> idleJointWarnings(const Scene& scene);

}  // namespace linx::io
