// POV-Ray scenes of a recorded run (docs/visualization.md, "POV-Ray frames"): one shared include
// with the camera, lights, sky, ground and every body's geometry in its body frame, and one small
// scene per frame that places the bodies at their poses and draws the joints as markers.
// `linx render` writes these files and runs the `povray` program on them.
#pragma once

#include "viz/camera.hpp"
#include "viz/run.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace linx::viz {

/// The recorded frames to draw for a video at `fps` pictures per second of simulated time: the
/// frame nearest to each time t0 + k / fps up to the last frame's time, each at most once, in
/// order. The first and last frames are always included. fps must be > 0.
std::vector<std::size_t> pickFrames(const Run& run, double fps);

/// The recorded frame nearest to `time` (the earlier one on a tie). The run must have frames.
std::size_t nearestFrame(const Run& run, double time);

/// The shared include of every frame: version, global settings, `camera` (as viz::project sees
/// it for a picture of aspect width / height), lights, sky, the ground (the scene's planes, or an
/// automatic one under the run's bounds against gravity; none without gravity), and one
/// `#declare LinxBodyN` per body in its body frame and `LinxJointN` markers per joint.
std::string povInclude(const Run& run, const Camera& camera, double aspect);

/// The scene of recorded frame `frame`: includes `include_name` and places every body and joint
/// marker at its pose of that frame.
std::string povFrame(const Run& run, std::size_t frame, const std::string& include_name);

}  // namespace linx::viz
