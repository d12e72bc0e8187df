// scene.json of a run (docs/scene-format.md, "Outputs"): the resolved scene, in the bodies' frames,
// for the tools that draw a run (linx render, --vtk, linx view). Shapes are taken from the built
// world, so that bodies whose centre of mass came from their shapes' densities are drawn where
// they are simulated.
#include <linx/scene.hpp>

#include <nlohmann/json.hpp>

#include "collision/geometry.hpp"

namespace linx {

namespace {

using json = nlohmann::ordered_json;

json vec(const Vec3& v) {
  return json::array({v.x(), v.y(), v.z()});
}

json quat(const Quat& q) {
  return json::array({q.w(), q.x(), q.y(), q.z()});
}

json triangles(const std::vector<std::array<int, 3>>& tris) {
  json out = json::array();
  for (const auto& t : tris) out.push_back(json::array({t[0], t[1], t[2]}));
  return out;
}

json vertices(const std::vector<Vec3>& points) {
  json out = json::array();
  for (const Vec3& p : points) out.push_back(vec(p));
  return out;
}

json shape(const ShapeDef& s) {
  json j;
  j["type"] = shapeTypeName(s.type);
  switch (s.type) {
    case ShapeType::Sphere:
      j["radius"] = s.radius;
      break;
    case ShapeType::Box:
      j["size"] = vec(s.size);
      break;
    case ShapeType::Ellipsoid:
      j["radii"] = vec(s.radii);
      break;
    case ShapeType::Capsule:
    case ShapeType::Cylinder:
      j["radius"] = s.radius;
      j["length"] = s.length;
      break;
    case ShapeType::Plane:
      j["normal"] = vec(s.normal);
      j["offset"] = s.offset;
      break;
    case ShapeType::Convex: {
      // The hull's faces are convex polygons, counter-clockwise from outside: fans of triangles.
      const auto hull = collision::Geometry::convexHull(s.points);
      std::vector<std::array<int, 3>> tris;
      for (const collision::HullFace& f : hull->faces()) {
        for (std::size_t k = 1; k + 1 < f.vertices.size(); ++k)
          tris.push_back({f.vertices[0], f.vertices[k], f.vertices[k + 1]});
      }
      j["vertices"] = vertices(hull->vertices());
      j["triangles"] = triangles(tris);
      break;
    }
    case ShapeType::Mesh:
      j["vertices"] = vertices(s.points);
      j["triangles"] = triangles(s.triangles);
      break;
  }
  j["position"] = vec(s.position);
  j["orientation"] = quat(s.orientation);
  return j;
}

// A world point or direction in the frame of body `id` at its current pose (the world's own frame
// for kWorldBody).
Vec3 localPoint(const World& world, BodyId id, const Vec3& p) {
  if (id.isWorld()) return p;
  const Pose& pose = world.body(id).pose();
  return pose.orientation.conjugate() * (p - pose.position);
}

Vec3 localDirection(const World& world, BodyId id, const Vec3& d) {
  if (id.isWorld()) return d;
  return world.body(id).orientation().conjugate() * d;
}

}  // namespace

std::string runSceneJson(const Scene& scene, const World& world, int every) {
  json root;
  root["format"] = "linx-run";
  root["version"] = 1;
  root["source"] = scene.file;
  root["every"] = every;
  root["gravity"] = vec(scene.settings.gravity);
  root["timestep"] = scene.settings.timestep;
  root["duration"] = scene.duration;
  if (scene.view) {
    const SceneView& v = *scene.view;
    json view;
    if (v.eye) view["eye"] = vec(*v.eye);
    if (v.target) view["target"] = vec(*v.target);
    const double g = scene.settings.gravity.norm();
    view["up"] = vec(v.up ? *v.up : g > 0 ? Vec3(-scene.settings.gravity / g) : Vec3::UnitZ());
    view["fov"] = v.fov;
    root["view"] = view;
  }

  json bodies = json::array();
  for (int i = 0; i < world.bodyCount(); ++i) {
    const Body& b = world.body(BodyId{i});
    json body;
    body["name"] = b.name();
    body["static"] = b.isStatic();
    body["mass"] = b.isStatic() ? 0.0 : b.mass();
    json shapes = json::array();
    for (const ShapeDef& s : b.shapes()) shapes.push_back(shape(s));
    body["shapes"] = shapes;
    bodies.push_back(body);
  }
  root["bodies"] = bodies;

  json joints = json::array();
  for (int i = 0; i < world.jointCount(); ++i) {
    const Joint& joint = world.joint(JointId{i});
    const JointDef& def = joint.def();
    const Vec3 anchor = def.anchor.value_or(world.body(def.body1).position());
    json j;
    j["name"] = def.name;
    j["type"] = joint.type();
    j["body1"] = world.body(def.body1).name();
    j["body2"] = def.body2.isWorld() ? std::string("world") : world.body(def.body2).name();
    const JointTypeInfo* info = findJointType(joint.type());
    // A distance or spring joint joins two points; the others meet at one.
    const Vec3 anchor2 =
        info && info->usesAnchor2()
            ? def.anchor2.value_or(def.body2.isWorld() ? anchor : world.body(def.body2).position())
            : anchor;
    j["anchor1"] = vec(localPoint(world, def.body1, anchor));
    j["anchor2"] = vec(localPoint(world, def.body2, anchor2));
    if (info && info->usesAxis()) {
      // A universal joint's two arms; otherwise one axis seen from both bodies.
      const Vec3 axis = def.axis.normalized();
      const Vec3 axis2 = info->usesAxis2() ? def.axis2.normalized() : axis;
      j["axis1"] = vec(localDirection(world, def.body1, axis));
      j["axis2"] = vec(localDirection(world, def.body2, axis2));
    }
    joints.push_back(j);
  }
  root["joints"] = joints;
  return root.dump(1) + "\n";
}

}  // namespace linx
