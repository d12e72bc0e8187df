#include "viz/povray.hpp"

#include "io/quoting.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>

namespace linx::viz {

namespace {

// Numbers with enough digits for a picture; never "nan" or "inf" (POV-Ray cannot read them).
std::string num(double x) {
  if (!std::isfinite(x)) x = 0;
  if (x == 0) x = 0;  // no "-0"
  return fmt::format("{:.9g}", x);
}

std::string vec(const Vec3& v) {
  return fmt::format("<{}, {}, {}>", num(v.x()), num(v.y()), num(v.z()));
}

// POV-Ray's `matrix` maps (x, y, z) to x * row0 + y * row1 + z * row2 + row3: the rows are the
// images of the axes, i.e. the columns of the rotation.
std::string matrix(const Quat& q, const Vec3& t) {
  const Eigen::Matrix3d r = q.normalized().toRotationMatrix();
  return fmt::format("matrix <{}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}>", num(r(0, 0)),
                     num(r(1, 0)), num(r(2, 0)), num(r(0, 1)), num(r(1, 1)), num(r(2, 1)),
                     num(r(0, 2)), num(r(1, 2)), num(r(2, 2)), num(t.x()), num(t.y()), num(t.z()));
}

// Colours of dynamic bodies (sRGB), in turn; static bodies are grey.
constexpr std::array<std::array<double, 3>, 8> kPalette{{
    {0.90, 0.28, 0.14},  // vermilion
    {0.17, 0.45, 0.85},  // blue
    {0.22, 0.68, 0.30},  // green
    {0.96, 0.70, 0.12},  // amber
    {0.58, 0.33, 0.80},  // violet
    {0.10, 0.66, 0.70},  // teal
    {0.92, 0.40, 0.62},  // pink
    {0.55, 0.40, 0.25},  // brown
}};

std::string srgb(const std::array<double, 3>& c, double factor = 1.0) {
  return fmt::format("srgb <{}, {}, {}>", num(c[0] * factor), num(c[1] * factor),
                     num(c[2] * factor));
}

// A "nice" length (1, 2 or 5 times a power of ten) at most `x`.
double niceBelow(double x) {
  if (!(x > 0) || !std::isfinite(x)) return 1.0;
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (const double m : {5.0, 2.0, 1.0})
    if (m * p <= x) return m * p;
  return p;
}

// Half of a shape's thinnest dimension (for the size of joint markers).
double halfThickness(const ShapeDef& s) {
  switch (s.type) {
    case ShapeType::Sphere:
    case ShapeType::Capsule:
      return s.radius;
    case ShapeType::Box:
      return s.size.minCoeff() / 2;
    case ShapeType::Cylinder:
      return std::min(s.radius, s.length / 2);
    case ShapeType::Ellipsoid:
      return s.radii.cwiseAbs().minCoeff();
    case ShapeType::Convex: {
      double r = 0;
      for (const Vec3& p : s.points) r = std::max(r, p.norm());
      return r / 2;
    }
    case ShapeType::Plane:
    case ShapeType::Mesh:
      break;
  }
  return 0;
}

// The body's geometry in its body frame, without texture ("" when it has nothing to draw).
std::string shapeObject(const ShapeDef& s, const std::string& texture) {
  std::string body;
  switch (s.type) {
    case ShapeType::Sphere:
      body = fmt::format("sphere {{ 0, {} }}", num(s.radius));
      break;
    case ShapeType::Box:
      body = fmt::format("box {{ {}, {} }}", vec(-s.size / 2), vec(s.size / 2));
      break;
    case ShapeType::Capsule: {
      const Vec3 a(0, 0, -s.length / 2), b(0, 0, s.length / 2);
      body = fmt::format(
          "merge {{ cylinder {{ {a}, {b}, {r} }} sphere {{ {a}, {r} }} sphere {{ {b}, {r} }} }}",
          fmt::arg("a", vec(a)), fmt::arg("b", vec(b)), fmt::arg("r", num(s.radius)));
      break;
    }
    case ShapeType::Cylinder:
      body = fmt::format("cylinder {{ {}, {}, {} }}", vec(Vec3(0, 0, -s.length / 2)),
                         vec(Vec3(0, 0, s.length / 2)), num(s.radius));
      break;
    case ShapeType::Convex:
    case ShapeType::Mesh: {
      if (s.points.empty() || s.triangles.empty()) return "";
      std::string m = fmt::format("mesh2 {{\n    vertex_vectors {{ {}", s.points.size());
      for (const Vec3& p : s.points) m += ",\n      " + vec(p);
      m += fmt::format(" }}\n    face_indices {{ {}", s.triangles.size());
      for (const auto& t : s.triangles) m += fmt::format(",\n      <{}, {}, {}>", t[0], t[1], t[2]);
      m += " }\n  }";
      body = m;
      break;
    }
    case ShapeType::Ellipsoid:  // a unit sphere scaled by the semi-axes, in the shape frame
      body = fmt::format("sphere {{ 0, 1 scale {} }}", vec(s.radii.cwiseAbs()));
      break;
    case ShapeType::Plane:
      return "";  // the ground (povInclude)
  }
  return fmt::format("object {{ {} {} {} }}", body, texture, matrix(s.orientation, s.position));
}

// Whether shapeObject draws anything of the body (planes are drawn as the ground).
bool drawable(const RunBody& body) {
  return std::any_of(body.shapes.begin(), body.shapes.end(), [](const ShapeDef& s) {
    if (s.type == ShapeType::Plane) return false;
    if (s.type == ShapeType::Convex || s.type == ShapeType::Mesh)
      return !s.points.empty() && !s.triangles.empty();
    return true;
  });
}

// The lowest point of the shape along `up` (the world frame), at body pose `pose`.
std::optional<double> lowest(const ShapeDef& s, const Pose& pose, const Vec3& up) {
  if (s.type == ShapeType::Plane) return std::nullopt;
  const Quat q = pose.orientation * s.orientation;
  return pose.toWorld(s.position).dot(up) - shapeExtent(s, q, -up);
}

// Distance from the body's origin (its centre of mass) to the farthest point of its shapes.
double reach(const RunBody& body) {
  double r = 0;
  for (const ShapeDef& s : body.shapes) {
    if (s.type != ShapeType::Plane) r = std::max(r, s.position.norm() + boundingRadius(s));
  }
  return r;
}

struct Ground {
  Vec3 normal;
  double offset;  // points x with normal . x = offset
};

}  // namespace

std::size_t nearestFrame(const Run& run, double time) {
  const auto& f = run.frames;
  const auto it = std::lower_bound(f.begin(), f.end(), time,
                                   [](const Frame& a, double t) { return a.time < t; });
  if (it == f.begin()) return 0;
  if (it == f.end()) return f.size() - 1;
  const auto i = static_cast<std::size_t>(it - f.begin());
  return time - f[i - 1].time <= f[i].time - time ? i - 1 : i;
}

std::vector<std::size_t> pickFrames(const Run& run, double fps) {
  std::vector<std::size_t> picked;
  if (run.frames.empty()) return picked;
  const double t0 = run.frames.front().time, t1 = run.frames.back().time;
  const double count = std::floor((t1 - t0) * fps + 1e-6);
  const auto n = static_cast<std::size_t>(std::clamp(count, 0.0, 1e9));
  const auto at = [&](std::size_t k) {
    return nearestFrame(run, t0 + static_cast<double>(k) / fps);
  };
  // The frames picked by k = 0..n, without trying every k (up to 1e9 of them for a long run at a
  // high fps, for a few recorded frames): at(k) never decreases with k, so after k picks frame i,
  // the k up to just before the midpoint between frames i and i + 1 pick i again and are skipped.
  for (std::size_t k = 0; k <= n;) {
    const std::size_t i = at(k);
    if (picked.empty() || i > picked.back()) picked.push_back(i);
    if (i + 1 >= run.frames.size()) break;  // the last frame: no later k picks another
    const double mid = 0.5 * (run.frames[i].time + run.frames[i + 1].time);
    const double guess = std::floor((mid - t0) * fps);
    std::size_t next = k + 1;
    if (guess > static_cast<double>(next)) {
      const auto skip = static_cast<std::size_t>(std::min(guess, static_cast<double>(n) + 1));
      // The guess is checked, not trusted, against rounding: the k skipped pick i as well when
      // the last of them does, as at(k) never decreases.
      if (skip > next && at(skip - 1) <= i) next = skip;
    }
    k = next;
  }
  if (picked.back() != run.frames.size() - 1) picked.push_back(run.frames.size() - 1);
  return picked;
}

std::string povInclude(const Run& run, const Camera& camera, double aspect) {
  const Bounds bounds = runBounds(run);
  const double size = std::max(bounds.radius(), 0.05);
  const double g = run.gravity.norm();
  const Vec3 up_world = g > 0 ? Vec3(-run.gravity / g) : camera.up;

  std::string out =
      "// linx render: shared by every frame (camera, lights, sky, ground, bodies, joints).\n"
      "#version 3.7;\n"
      "global_settings { assumed_gamma 1.0 ambient_light rgb 1 max_trace_level 5 }\n\n";

  // Camera: the same pinhole as viz::project. Explicit direction, right and up vectors in the
  // (right-handed) world frame: a pixel's ray is direction + u right + v up, u from left to right
  // and v from bottom to top of the picture, so no handedness flip is needed.
  const Vec3 look = (camera.target - camera.eye).normalized();
  const Vec3 right = look.cross(camera.up).normalized();
  const Vec3 up = right.cross(look);
  const double span = 2 * std::tan(camera.fov * std::numbers::pi / 360);
  out += fmt::format(
      "camera {{\n  perspective\n  location {}\n  direction {}\n  right {}\n  up {}\n}}\n\n",
      vec(camera.eye), vec(look), vec(right * span * aspect), vec(up * span));

  // Lights: a key light above, behind and to the left of the camera (shadows), and a weak
  // shadowless fill from the camera.
  const double distance = std::max((camera.eye - camera.target).norm(), size);
  const Vec3 key_dir = (-0.6 * look - 0.5 * right + 1.2 * up_world).normalized();
  out += fmt::format("light_source {{ {} color rgb 0.85 }}\n",
                     vec(camera.target + 6 * distance * key_dir));
  out += fmt::format("light_source {{ {} color rgb 0.3 shadowless }}\n\n",
                     vec(camera.eye + 0.3 * distance * up_world));

  // Sky: light at the horizon, blue above.
  out += fmt::format(
      "sky_sphere {{ pigment {{ gradient {} color_map {{ [0.0 srgb <0.80, 0.84, 0.90>] "
      "[0.5 srgb <0.93, 0.95, 0.98>] [1.0 srgb <0.52, 0.68, 0.90>] }} scale 2 translate {} }} "
      "}}\n\n",
      vec(up_world), vec(-up_world));

  // Textures.
  out +=
      "#declare LinxFinish = finish { ambient 0.14 diffuse 0.78 specular 0.25 roughness 0.03 }\n";
  const double cell = niceBelow(size / 2.5);
  out += fmt::format(
      "#declare LinxGroundTexture = texture {{ pigment {{ checker srgb <0.86, 0.86, 0.84> srgb "
      "<0.70, 0.71, 0.74> }} finish {{ ambient 0.18 diffuse 0.72 }} }}\n");
  out +=
      "#declare LinxHorizonTexture = texture { pigment { srgb <0.93, 0.95, 0.98> } finish { "
      "ambient 0.18 diffuse 0.72 } }\n";
  out +=
      "#declare LinxStaticTexture = texture { pigment { srgb <0.62, 0.62, 0.64> } finish { "
      "LinxFinish } }\n";
  out +=
      "#declare LinxJointTexture = texture { pigment { srgb <0.18, 0.18, 0.20> } finish { ambient "
      "0.1 diffuse 0.6 specular 0.6 roughness 0.01 } }\n\n";

  // The ground: the scene's planes (on static bodies), or one under the bounds.
  std::vector<Ground> planes;
  bool has_plane = false;
  for (std::size_t i = 0; i < run.bodies.size(); ++i) {
    for (const ShapeDef& s : run.bodies[i].shapes) {
      if (s.type != ShapeType::Plane) continue;
      has_plane = true;
      const Pose& pose = run.frames.empty() ? Pose{} : run.frames.front().poses[i];
      const Vec3 n_shape = s.normal.normalized();
      const Vec3 n = pose.orientation * (s.orientation * n_shape);
      const Vec3 point = pose.toWorld(s.position + s.orientation * (n_shape * s.offset));
      planes.push_back({n.normalized(), n.normalized().dot(point)});
    }
  }
  if (!has_plane && g > 0) {  // just under the lowest point of any shape over the run
    std::optional<double> low;
    for (const Frame& frame : run.frames)
      for (std::size_t i = 0; i < run.bodies.size(); ++i)
        for (const ShapeDef& s : run.bodies[i].shapes)
          if (const auto h = lowest(s, frame.poses[i], up_world))
            low = low ? std::min(*low, *h) : *h;
    if (!low) low = up_world.dot(bounds.center()) - size;
    planes.push_back({up_world, *low - 1e-3 * size});
  }
  for (const Ground& p : planes) {
    // The checker is laid out in the plane's own frame (z along the normal) so it is square on
    // any plane, and half a cell off the plane so the plane is not on a cell boundary. Far from
    // the scene it fades into the colour of the horizon (the inner texture is scaled by 1 / fade
    // as the outer one scales it by fade).
    const Quat q = Quat::FromTwoVectors(Vec3::UnitZ(), p.normal);
    Vec3 centre = q.conjugate() * (camera.target - p.normal * p.offset);
    centre.z() = 0;
    const double fade = 14 * size;
    out += fmt::format(
        "plane {{ z, 0\n  texture {{ spherical texture_map {{\n    [0.0 LinxHorizonTexture]\n"
        "    [0.6 LinxGroundTexture scale {} translate <0, 0, {}>]\n"
        "    [1.0 LinxGroundTexture scale {} translate <0, 0, {}>] }}\n"
        "    scale {} translate {} }}\n  {}\n}}\n",
        num(cell / fade), num(cell / fade / 2), num(cell / fade), num(cell / fade / 2), num(fade),
        vec(centre), matrix(q, p.normal * p.offset));
  }
  if (!planes.empty()) out += "\n";

  // Bodies, each in its body frame.
  int dynamic_index = 0;
  for (std::size_t i = 0; i < run.bodies.size(); ++i) {
    const RunBody& body = run.bodies[i];
    std::string plain, striped;
    if (body.is_static) {
      plain = striped = "texture { LinxStaticTexture }";
    } else {
      const auto& c = kPalette[static_cast<std::size_t>(dynamic_index++) % kPalette.size()];
      plain = fmt::format("texture {{ pigment {{ {} }} finish {{ LinxFinish }} }}", srgb(c));
      // Round shapes get segments around their z axis, so that they are seen to turn.
      striped = fmt::format(
          "texture {{ pigment {{ radial frequency 6 color_map {{ [0.5 {}] [0.5 {}] }} rotate x*90 "
          "}} finish {{ LinxFinish }} }}",
          srgb(c), srgb(c, 0.72));
    }
    std::vector<std::string> objects;
    for (const ShapeDef& s : body.shapes) {
      const bool round = s.type == ShapeType::Sphere || s.type == ShapeType::Cylinder ||
                         s.type == ShapeType::Capsule;
      std::string o = shapeObject(s, round ? striped : plain);
      if (!o.empty()) objects.push_back(std::move(o));
    }
    out += fmt::format("// body {}: {}\n", i, io::povComment(body.name));
    if (objects.empty()) {
      continue;  // planes only (the ground), or nothing to draw
    } else if (objects.size() == 1) {
      out += fmt::format("#declare LinxBody{} = {}\n", i, objects.front());
    } else {
      out += fmt::format("#declare LinxBody{} = union {{\n", i);
      for (const std::string& o : objects) out += "  " + o + "\n";
      out += "}\n";
    }
  }

  // Joint markers: a ball at the anchor, and a rod along the axis of hinges and sliders. Their
  // size follows the thinnest shape of the bodies they join, within a range of the scene's size.
  for (std::size_t j = 0; j < run.joints.size(); ++j) {
    const RunJoint& joint = run.joints[j];
    double thin = 0;
    for (const int b : {joint.body1, joint.body2}) {
      if (b < 0 || static_cast<std::size_t>(b) >= run.bodies.size()) continue;
      for (const ShapeDef& s : run.bodies[static_cast<std::size_t>(b)].shapes) {
        const double h = halfThickness(s);
        if (h > 0) thin = thin > 0 ? std::min(thin, h) : h;
      }
    }
    const double r = std::clamp(1.3 * thin, 0.01 * size, 0.04 * size);
    out += fmt::format("// joint {}: {} ({})\n", j, io::povComment(joint.name),
                       io::povComment(joint.type));
    out += fmt::format("#declare LinxJoint{} = sphere {{ 0, {} texture {{ LinxJointTexture }} }}\n",
                       j, num(r));
    out += fmt::format("#declare LinxJointLinkRadius{} = {};\n", j, num(0.3 * r));
    if (joint.axis1) {
      const bool slider = joint.type == "slider";
      const double half = (slider ? 6 : 2.6) * r, radius = (slider ? 0.3 : 0.4) * r;
      out += fmt::format(
          "#declare LinxJointAxis{} = cylinder {{ {}, {}, {} texture {{ LinxJointTexture }} }}\n",
          j, vec(Vec3(0, 0, -half)), vec(Vec3(0, 0, half)), num(radius));
    }
  }
  return out;
}

std::string povFrame(const Run& run, std::size_t index, const std::string& include_name) {
  const Frame& frame = run.frames.at(index);
  std::string out = fmt::format("// linx render: frame {} (t = {} s)\n#include {}\n\n", index,
                                num(frame.time), io::povString(include_name));
  for (std::size_t i = 0; i < run.bodies.size(); ++i) {
    if (!drawable(run.bodies[i])) continue;
    const Pose& p = frame.poses[i];
    out += fmt::format("object {{ LinxBody{} {} }}\n", i, matrix(p.orientation, p.position));
  }
  for (std::size_t j = 0; j < run.joints.size(); ++j) {
    const RunJoint& joint = run.joints[j];
    const Vec3 anchor = worldPoint(frame, joint.body1, joint.anchor1);
    out += fmt::format("object {{ LinxJoint{} translate {} }}\n", j, vec(anchor));
    // A thin link from the anchor to each body it holds from outside (a pendulum's string).
    for (const int b : {joint.body1, joint.body2}) {
      if (b < 0 || static_cast<std::size_t>(b) >= run.bodies.size()) continue;
      const Vec3 centre = frame.poses[static_cast<std::size_t>(b)].position;
      if ((centre - anchor).norm() > 1.05 * reach(run.bodies[static_cast<std::size_t>(b)]))
        out += fmt::format(
            "cylinder {{ {}, {}, LinxJointLinkRadius{} texture {{ LinxJointTexture }} }}\n",
            vec(anchor), vec(centre), j);
    }
    if (joint.axis1) {
      Vec3 axis = *joint.axis1;
      if (joint.body1 >= 0)
        axis = frame.poses[static_cast<std::size_t>(joint.body1)].orientation * axis;
      if (axis.norm() > 0) {
        const Quat q = Quat::FromTwoVectors(Vec3::UnitZ(), axis.normalized());
        out += fmt::format("object {{ LinxJointAxis{} {} }}\n", j, matrix(q, anchor));
      }
    }
  }
  return out;
}

}  // namespace linx::viz
