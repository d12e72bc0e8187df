// A mesh's volume, centre and inertia as MuJoCo 2.2.2 computes them for a <geom type="mesh">
// (user_mesh.cc, mjCMesh::Process, and mjCGeom::GetVolume and SetInertia), so that a model's
// bodies weigh what they weigh in MuJoCo.
//
// MuJoCo keeps a mesh's vertices in single precision, moved by refpos and refquat and scaled, and
// then:
// 1. the centroid c of the surface: triangle centres weighted by area;
// 2. the volume and centre of mass from pyramids of apex c over each triangle (by default, the
//    legacy rule, each pyramid's volume taken positive: exact for a closed convex mesh, not for
//    other meshes; `exactmeshinertia` takes them signed);
// 3. the vertices moved to that centre (again in single precision), and the inertia from the
//    tetrahedra of apex the centre over each triangle;
// 4. the box of equal principal moments per unit mass ("inertia box", half-sizes b from the
//    principal moments). Under the legacy rule the geom's mass is its density times that box's
//    volume, 8 b_x b_y b_z, and not the mesh's volume; its inertia is the box's, which is the
//    mesh's inertia scaled by the ratio of the two volumes.
// Here the arithmetic is done in the precisions MuJoCo does it in (single where its vertices are
// single), so that the results agree to rounding of the double steps; the principal axes come
// from Eigen's eigen decomposition in place of MuJoCo's Jacobi iteration.
#pragma once

#include <linx/shape.hpp>
#include <linx/types.hpp>

#include <array>
#include <vector>

namespace linx::io {

/// A mesh as MuJoCo holds it: single-precision vertices, and triangles of vertex indices.
struct MujocoMesh {
  std::vector<std::array<float, 3>> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// A mesh read from a file (io::loadMeshFile) as MuJoCo holds it: each vertex rounded to single
/// precision, moved by -refpos, turned by refquat's inverse and scaled, each step rounded to single
/// precision as MuJoCo rounds it. A scale that mirrors (a negative product) reverses the winding.
MujocoMesh mujocoMesh(const ShapeDef& read, const Vec3& scale, const Vec3& refpos,
                      const Quat& refquat);

/// What a geom of the mesh weighs per unit density, in the mesh's frame (as read and scaled).
struct MeshMass {
  double volume = 0.0;          ///< the geom's mass per unit density (m^3)
  Vec3 centre = Vec3::Zero();   ///< centre of mass (m)
  Mat3 inertia = Mat3::Zero();  ///< per unit density, about the centre (m^5)
};

/// MuJoCo's mesh mass (legacy rule unless `exact`). Throws std::runtime_error with MuJoCo's
/// reasons to refuse a mesh: a surface or volume too small, principal moments that are not
/// positive or break the triangle inequality.
MeshMass mujocoMeshMass(MujocoMesh mesh, bool exact);

}  // namespace linx::io
