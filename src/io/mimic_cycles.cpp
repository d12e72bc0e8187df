#include "io/mimic_cycles.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

namespace linx::io {

std::optional<MimicCycle> findMimicCycle(const Scene& scene) {
  const std::size_t n = scene.joints.size();
  // The mimic joints leaving each joint (its follower side), in the scene's order.
  std::vector<std::vector<std::size_t>> mimics_of(n);
  for (std::size_t m = 0; m < n; ++m) {
    const JointDef& d = scene.joints[m].def;
    if (scene.joints[m].type != "mimic" || !d.follower || !d.leader) continue;
    const auto follower = static_cast<std::size_t>(d.follower->index);
    if (follower < n && static_cast<std::size_t>(d.leader->index) < n)
      mimics_of[follower].push_back(m);
  }
  // Depth first along follower -> leader, with the mimic joints taken on the way.
  enum class Seen { no, on_path, done };
  std::vector<Seen> seen(n, Seen::no);
  std::vector<std::size_t> path;  // mimic joints from the start to the joint being visited
  struct Frame {
    std::size_t joint, next = 0;
  };
  for (std::size_t start = 0; start < n; ++start) {
    if (seen[start] != Seen::no) continue;
    std::vector<Frame> stack{{start}};
    seen[start] = Seen::on_path;
    while (!stack.empty()) {
      Frame& top = stack.back();
      if (top.next == mimics_of[top.joint].size()) {
        seen[top.joint] = Seen::done;
        stack.pop_back();
        if (!path.empty()) path.pop_back();
        continue;
      }
      const std::size_t m = mimics_of[top.joint][top.next++];
      const auto leader = static_cast<std::size_t>(scene.joints[m].def.leader->index);
      if (seen[leader] == Seen::done) continue;
      path.push_back(m);
      if (seen[leader] == Seen::on_path) {  // round: from the mimic that leaves `leader`
        const auto first = std::find_if(path.begin(), path.end(), [&](std::size_t p) {
          return static_cast<std::size_t>(scene.joints[p].def.follower->index) == leader;
        });
        std::string chain;
        for (auto p = first; p != path.end(); ++p) {
          const JointDef& d = scene.joints[*p].def;
          chain += fmt::format("{}'{}' follows '{}'", chain.empty() ? "" : ", ",
                               scene.joints[static_cast<std::size_t>(d.follower->index)].def.name,
                               scene.joints[static_cast<std::size_t>(d.leader->index)].def.name);
        }
        return MimicCycle{*first,
                          fmt::format("the mimic joints form a cycle ({}): a joint cannot follow "
                                      "itself through others",
                                      chain)};
      }
      seen[leader] = Seen::on_path;
      stack.push_back({leader});
    }
  }
  return std::nullopt;
}

}  // namespace linx::io
