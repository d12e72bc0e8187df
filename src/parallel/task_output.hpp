// Per-task results of a parallel loop (src/parallel/parallel_for.hpp), kept apart in memory.
#pragma once

namespace linx::parallel {

/// One task's output, alone on its cache lines: tasks that append to neighbouring vectors would
/// otherwise write the same line (their end pointers) on every append, from different cores.
template <class T>
struct alignas(64) TaskOutput {
  T value;
};

}  // namespace linx::parallel
