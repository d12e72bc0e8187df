// Joints that repeat one another: the same type between the same two bodies, at the same anchor
// and axis. Their rows are linearly dependent, which the exact solver survives only by solving
// them densely (a thousand identical hinges took 100 s a step), so a model that has them is
// named with a warning (linx check, run and convert print it).
#pragma once

#include <linx/scene.hpp>

#include <string>
#include <vector>

namespace linx::io {

/// One warning per group of repeated joints, naming the first and how many repeat it.
std::vector<std::string> redundantJointWarnings(const Scene& scene);

}  // namespace linx::io
