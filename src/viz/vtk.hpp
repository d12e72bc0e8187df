// ParaView files of a recorded run (docs/visualization.md, "ParaView"): one VTK XML PolyData file
// per frame with every shape as a surface, and a .pvd collection that ParaView opens as one time
// series.
//
//   DIR/run.pvd                 the collection: every frame's files with timestep = the frame's
//                               time; part 0 bodies, then joints, then contacts (those present)
//   DIR/vtk/bodies_NNNNNN.vtp   all shapes' triangles in world coordinates (planes as squares
//                               sized from the run's bounds). Point data: velocity (Float64 x 3,
//                               v + w x (p - c), the rigid-body velocity of the point), Normals
//                               (Float32 x 3). Cell data: body_id (Int32, scene.json's order),
//                               shape_id (Int32, index in the body's shapes).
//   DIR/vtk/joints_NNNNNN.vtp   (when the scene has joints) a vertex per joint at its anchor on
//                               body1. Point data: joint_id (Int32), joint_error (Float64, m),
//                               joint_coordinate (Float64, NaN for joints without one), axis
//                               (Float64 x 3, world, zero for joints without one), body1 and body2
//                               (Int32, -1 the world).
//   DIR/vtk/contacts_NNNNNN.vtp (when the run wrote contacts.csv) a vertex per contact point.
//                               Point data: normal (Float64 x 3), depth and normal_impulse
//                               (Float64), body1 and body2 (Int32).
// Every file carries its time as field data TimeValue. Arrays are base64 binary (header_type
// UInt64, the machine's byte order), which ParaView and every VTK XML reader read.
#pragma once

#include "viz/run.hpp"

#include <filesystem>

namespace linx::viz {

struct VtkSummary {
  std::filesystem::path collection;  ///< DIR/run.pvd
  std::filesystem::path folder;      ///< DIR/vtk
  int frames = 0;
};

struct VtkOptions {
  int sphere_subdivisions = 2;  ///< icosphere level of spheres (TessellationOptions)
  int segments = 24;            ///< points around capsules and cylinders
};

/// Writes DIR/vtk/*.vtp and DIR/run.pvd for every frame of `run`. Throws std::runtime_error when a
/// file cannot be written. Files are written under temporary names and renamed only when all are
/// complete (run.pvd last), so a failure while writing leaves no file under a final name. Files of
/// an earlier export that this one does not list (more frames, or contacts) are removed.
VtkSummary writeVtk(const Run& run, const std::filesystem::path& dir,
                    const VtkOptions& options = {});

}  // namespace linx::viz
