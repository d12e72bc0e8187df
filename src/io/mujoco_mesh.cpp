// MuJoCo 2.2.2's mesh mass, step by step (see the header). The expressions keep MuJoCo's types:
// a float plus a float is a float, and a float stored in a double is exact.
#include "io/mujoco_mesh.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <stdexcept>
#include <utility>

namespace linx::io {
namespace {

constexpr double kMinValue = 1e-15;  // MuJoCo's mjMINVAL

using Vertex = std::array<float, 3>;

// A triangle's area, unit normal and centre; 0 for a triangle too small to have a normal.
double areaNormalCentre(Vec3& normal, Vec3& centre, const Vertex& v1, const Vertex& v2,
                        const Vertex& v3) {
  for (int i = 0; i < 3; ++i) centre[i] = (v1[i] + v2[i] + v3[i]) / 3;  // in single precision
  const Vec3 b(v2[0] - v1[0], v2[1] - v1[1], v2[2] - v1[2]);
  const Vec3 c(v3[0] - v1[0], v3[1] - v1[1], v3[2] - v1[2]);
  normal = Vec3(b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]);
  const double length = std::sqrt(normal.dot(normal));
  if (length < kMinValue) return 0.0;
  normal /= length;
  return length / 2;
}

// The centroid of the surface: triangle centres weighted by their areas.
Vec3 surfaceCentroid(const MujocoMesh& mesh) {
  Vec3 sum = Vec3::Zero(), normal, centre;
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    const double a = areaNormalCentre(normal, centre, mesh.vertices[t[0]], mesh.vertices[t[1]],
                                      mesh.vertices[t[2]]);
    sum += a * centre;
    area += a;
  }
  if (area < kMinValue) throw std::runtime_error("the mesh's surface area is too small");
  return sum / area;
}

// The centre of mass from pyramids of apex `apex` over the triangles.
Vec3 centreOfMass(const MujocoMesh& mesh, const Vec3& apex, bool exact) {
  double volume = 0.0;
  Vec3 sum = Vec3::Zero(), normal, centre;
  for (const auto& t : mesh.triangles) {
    const double a = areaNormalCentre(normal, centre, mesh.vertices[t[0]], mesh.vertices[t[1]],
                                      mesh.vertices[t[2]]);
    double v = (centre - apex).dot(normal) * a / 3;
    if (!exact) v = std::fabs(v);
    volume += v;
    for (int j = 0; j < 3; ++j) sum[j] += v * (centre[j] * 3.0 / 4.0 + apex[j] / 4.0);
  }
  if (volume < kMinValue) throw std::runtime_error("the mesh's volume is too small");
  return sum / volume;
}

}  // namespace

MujocoMesh mujocoMesh(const ShapeDef& read, const Vec3& scale, const Vec3& refpos,
                      const Quat& refquat) {
  MujocoMesh mesh;
  const Mat3 turn = refquat.normalized().toRotationMatrix();
  const std::array<float, 3> shift{static_cast<float>(refpos[0]), static_cast<float>(refpos[1]),
                                   static_cast<float>(refpos[2])};
  mesh.vertices.reserve(read.points.size());
  for (const Vec3& p : read.points) {
    Vertex v{static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
    for (int j = 0; j < 3; ++j) v[j] -= shift[j];
    const Vec3 turned = turn.transpose() * Vec3(v[0], v[1], v[2]);
    for (int j = 0; j < 3; ++j) v[j] = static_cast<float>(turned[j]);
    for (int j = 0; j < 3; ++j) v[j] = static_cast<float>(v[j] * scale[j]);
    mesh.vertices.push_back(v);
  }
  const bool mirrored = scale.prod() < 0;
  mesh.triangles = read.triangles;
  if (mirrored)
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

MeshMass mujocoMeshMass(MujocoMesh mesh, bool exact) {
  for (const auto& t : mesh.triangles)
    for (const int i : t)
      if (i < 0 || static_cast<std::size_t>(i) >= mesh.vertices.size())
        throw std::out_of_range("a triangle's vertex index is out of range");
  const Vec3 com = centreOfMass(mesh, surfaceCentroid(mesh), exact);
  for (Vertex& v : mesh.vertices)
    for (int j = 0; j < 3; ++j) v[j] = static_cast<float>(v[j] - com[j]);

  // Products of inertia from the tetrahedra of apex the centre (per unit density).
  constexpr int k[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  double products[6] = {0, 0, 0, 0, 0, 0};
  double volume = 0.0;
  Vec3 normal, centre;
  for (const auto& t : mesh.triangles) {
    const Vertex &d = mesh.vertices[t[0]], &e = mesh.vertices[t[1]], &f = mesh.vertices[t[2]];
    const double a = areaNormalCentre(normal, centre, d, e, f);
    double v = centre.dot(normal) * a / 3;
    if (!exact) v = std::fabs(v);
    volume += v;
    for (int j = 0; j < 6; ++j) {
      const int p = k[j][0], q = k[j][1];
      const float sum = 2 * (d[p] * d[q] + e[p] * e[q] + f[p] * f[q]) + d[p] * e[q] + d[q] * e[p] +
                        d[p] * f[q] + d[q] * f[p] + e[p] * f[q] + e[q] * f[p];
      products[j] += v / 20 * sum;
    }
  }
  Mat3 inertia;
  inertia << products[1] + products[2], -products[3], -products[4],  //
      -products[3], products[0] + products[2], -products[5],         //
      -products[4], -products[5], products[0] + products[1];
  const Vec3 moments =
      Eigen::SelfAdjointEigenSolver<Mat3>(inertia, Eigen::EigenvaluesOnly).eigenvalues();
  if (!(moments.minCoeff() > 0.0))
    throw std::runtime_error("the mesh's principal moments of inertia are not all positive");
  for (int i = 0; i < 3; ++i)
    if (moments[(i + 1) % 3] + moments[(i + 2) % 3] < moments[i])
      throw std::runtime_error("the mesh's principal moments break the triangle inequality");

  MeshMass out;
  out.centre = com;
  // The inertia box: half-sizes b_i = sqrt(6 (I_j + I_k - I_i) / m) / 2, m the mesh's volume.
  double box = 8.0;
  for (int i = 0; i < 3; ++i)
    box *= std::sqrt(6 * (moments[(i + 1) % 3] + moments[(i + 2) % 3] - moments[i]) / volume) / 2;
  out.volume = exact ? volume : box;
  out.inertia = out.volume / volume * inertia;  // the box's moments: the mesh's, scaled
  return out;
}

}  // namespace linx::io
