#include "world/contact_stage.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "collision/aabb.hpp"
#include "collision/geometry.hpp"
#include "world/assembly.hpp"

namespace linx::world {

namespace {
/// Identity of a contact across steps: bit 63 (a contact, not a joint), the two global shape
/// indices and the feature id; the low two bits stay free for the row slot.
std::uint64_t contactKey(int shape_a, int shape_b, std::uint32_t feature) {
  // The pair and the whole 32-bit feature do not fit in 61 bits: mix them (splitmix64 steps), so
  // that two points share a key only by a 2^-61 chance (and then merely share a warm start).
  auto mix = [](std::uint64_t x) {
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9u;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebu;
    return x ^ (x >> 31);
  };
  const std::uint64_t pair =
      (static_cast<std::uint64_t>(static_cast<std::uint32_t>(shape_a)) << 32) |
      static_cast<std::uint32_t>(shape_b);
  const std::uint64_t h = mix(mix(pair) ^ feature);
  return (std::uint64_t{1} << 63) | (h & ~std::uint64_t{3} & ~(std::uint64_t{1} << 63));
}

/// The pair's law: friction sqrt(mu_a mu_b) (a frictionless side makes the pair frictionless),
/// restitution max(e_a, e_b) (a bouncy ball bounces on any floor); erp/cfm from the settings.
joints::ContactLaw combine(const ShapeDef& a, const ShapeDef& b, const ContactSettings& s,
                           double h) {
  joints::ContactLaw law;
  law.friction = std::sqrt(a.friction * b.friction);
  law.restitution = std::max(a.restitution, b.restitution);
  if (s.stiffness && s.damping) {
    const SoftRow soft = springDamper(*s.stiffness, *s.damping, h);
    law.erp = soft.erp;
    law.cfm = soft.cfm;
  } else {
    law.erp = s.erp;
    law.cfm = s.cfm;
  }
  law.slop = s.slop;
  law.restitution_threshold = s.restitution_threshold;
  return law;
}

/// The shape frame in the world.
Pose shapePose(const Body& body, const ShapeDef& shape) {
  return Pose{body.pose().toWorld(shape.position),
              (body.orientation() * shape.orientation).normalized()};
}

/// How far a point of the shape can move in a step of length h: |v| h + |w| h times the largest
/// distance of the shape's box from the centre of mass. Unbounded shapes are static (zero speed).
double sweep(const Body& body, const collision::Aabb& box, double h) {
  if (body.isStatic()) return 0.0;
  const double reach = (box.centre() - body.position()).norm() + 0.5 * box.extent().norm();
  return h * (body.linearVelocity().norm() + body.angularVelocity().norm() * reach);
}

/// Whether a point found within the swept margin can matter this step: it touches, lies within
/// the speculative margin, or a body moves toward the other fast enough to close the gap in one
/// step, even if the other stopped dead (gravity is in the velocities already). The swept margin
/// of the broadphase bounds each body's whole speed in any direction; spheres falling side by side
/// move across their normal and need no row between them. In a poured pile this drops three in
/// four speculative points, with the same penetration.
bool mayTouch(const Body& a, const Body& b, const collision::ContactPoint& p, double margin,
              double h) {
  const double gap = -p.depth;
  if (gap <= margin) return true;
  const double closing = std::max(0.0, a.velocityAt(p.point).dot(p.normal)) +
                         std::max(0.0, -b.velocityAt(p.point).dot(p.normal));
  return gap <= margin + h * closing;
}
}  // namespace

void ContactStage::addBody(const Body& body) {
  // Prepare every shape first: a shape that throws leaves the stage as it was.
  std::vector<std::shared_ptr<const collision::Geometry>> prepared;
  for (const ShapeDef& shape : body.shapes()) prepared.push_back(collision::prepareGeometry(shape));
  const int index = static_cast<int>(first_shape_.size());
  first_shape_.push_back(static_cast<int>(geometry_.size()));
  for (auto& g : prepared) {
    geometry_.push_back(std::move(g));
    shape_body_.push_back(index);
  }
}

void ContactStage::touching(int body, std::vector<int>& out) const {
  for (const ContactRecord& r : records_) {
    if (r.body_a == body) out.push_back(r.body_b);
    if (r.body_b == body) out.push_back(r.body_a);
  }
}

void ContactStage::detect(std::span<const Body> bodies,
                          std::span<const std::unique_ptr<Joint>> joints,
                          const ContactSettings& settings, double h) {
  records_.clear();
  match_distance_ = settings.margin;
  if (!settings.enabled || geometry_.empty()) return;

  joined_.clear();
  for (const auto& j : joints) {
    if (j->def().collide || j->body2().isWorld()) continue;
    const int a = j->body1().index, b = j->body2().index;
    joined_.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(joined_.begin(), joined_.end());

  // Broadphase over every shape, boxes grown by the margin and the step's sweep.
  boxes_.resize(geometry_.size());
  std::vector<double>& reach = reach_;
  reach.resize(geometry_.size());
  poses_.resize(geometry_.size());
  for (std::size_t s = 0; s < geometry_.size(); ++s) {
    const Body& body = bodies[static_cast<std::size_t>(shape_body_[s])];
    const int local = static_cast<int>(s) - first_shape_[static_cast<std::size_t>(shape_body_[s])];
    const ShapeDef& shape = body.shapes()[static_cast<std::size_t>(local)];
    poses_[s] = shapePose(body, shape);
    const collision::Aabb tight = collision::shapeAabb(shape, body.pose());
    reach[s] = sweep(body, tight, h);
    boxes_[s] = tight.expanded(0.5 * settings.margin + reach[s]);
  }
  broadphase_.update(boxes_);

  for (const auto& [i, j] : broadphase_.pairs()) {
    const int body_i = shape_body_[static_cast<std::size_t>(i)];
    const int body_j = shape_body_[static_cast<std::size_t>(j)];
    if (body_i == body_j) continue;
    const Body& bi = bodies[static_cast<std::size_t>(body_i)];
    const Body& bj = bodies[static_cast<std::size_t>(body_j)];
    if (bi.isStatic() && bj.isStatic()) continue;
    const int local_i = i - first_shape_[static_cast<std::size_t>(body_i)];
    const int local_j = j - first_shape_[static_cast<std::size_t>(body_j)];
    const ShapeDef& si = bi.shapes()[static_cast<std::size_t>(local_i)];
    const ShapeDef& sj = bj.shapes()[static_cast<std::size_t>(local_j)];
    if ((si.group & sj.mask) == 0 || (sj.group & si.mask) == 0) continue;
    if (std::binary_search(joined_.begin(), joined_.end(),
                           std::pair{std::min(body_i, body_j), std::max(body_i, body_j)}))
      continue;

    const collision::ShapeInstance a{&si, geometry_[static_cast<std::size_t>(i)].get(),
                                     poses_[static_cast<std::size_t>(i)]};
    const collision::ShapeInstance b{&sj, geometry_[static_cast<std::size_t>(j)].get(),
                                     poses_[static_cast<std::size_t>(j)]};
    const double margin =
        settings.margin + reach[static_cast<std::size_t>(i)] + reach[static_cast<std::size_t>(j)];
    points_.clear();
    collision::collide(a, b, margin, points_);
    const joints::ContactLaw law = combine(si, sj, settings, h);
    for (const collision::ContactPoint& p : points_) {
      if (!mayTouch(bi, bj, p, settings.margin, h)) continue;
      ContactRecord r;
      r.body_a = body_i;
      r.body_b = body_j;
      r.shape_a = local_i;
      r.shape_b = local_j;
      r.point = p;
      r.law = law;
      r.key = contactKey(i, j, p.feature);
      r.pair = (static_cast<std::uint64_t>(i) << 32) | static_cast<std::uint32_t>(j);
      records_.push_back(r);
    }
  }
}

void ContactStage::appendRows(std::span<const Body> bodies, double h, std::vector<Row>& rows,
                              std::vector<double>& lambda, bool warm_start) {
  // All normal rows first, then all friction rows: a Gauss-Seidel sweep then settles the normal
  // impulses of a whole pile before friction, whose bounds follow them, is solved against them.
  const std::size_t first_normal = rows.size();
  const std::size_t first_friction = first_normal + records_.size();
  rows.resize(first_normal + 3 * records_.size());
  lambda.resize(rows.size(), 0.0);
  std::array<Row, 3> made;
  for (std::size_t c = 0; c < records_.size(); ++c) {
    ContactRecord& r = records_[c];
    const Body& a = bodies[static_cast<std::size_t>(r.body_a)];
    const Body& b = bodies[static_cast<std::size_t>(r.body_b)];
    made.fill(Row{});
    joints::contactRows(r.point, stateOf(bodies, BodyId{r.body_a}),
                        stateOf(bodies, BodyId{r.body_b}), r.law, h, made, r.t1, r.t2);
    r.row = static_cast<int>(first_normal + c);
    r.friction_row = static_cast<int>(first_friction + 2 * c);
    const std::array<std::size_t, 3> at{first_normal + c, first_friction + 2 * c,
                                        first_friction + 2 * c + 1};
    for (std::size_t k = 0; k < 3; ++k) {
      Row& row = rows[at[k]];
      row = made[k];
      row.body_a = a.isStatic() ? -1 : r.body_a;
      row.body_b = b.isStatic() ? -1 : r.body_b;
      row.key |= r.key;
      if (row.normal >= 0) row.normal = r.row;
    }
    if (warm_start) {
      if (const Impulse* old = previousImpulse(r, a)) {
        lambda[at[0]] = old->normal;
        lambda[at[1]] = old->friction.dot(r.t1);  // the old tangential impulse, projected
        lambda[at[2]] = old->friction.dot(r.t2);  // on the new tangents
      }
    }
  }
}

const ContactStage::Impulse* ContactStage::previousImpulse(const ContactRecord& r,
                                                           const Body& a) const {
  if (const auto it = cache_.find(r.key); it != cache_.end()) return &it->second;
  const auto [first, last] =
      std::equal_range(previous_.begin(), previous_.end(), Previous{r.pair, {}, {}},
                       [](const Previous& x, const Previous& y) { return x.pair < y.pair; });
  const Vec3 local = a.pose().toLocal(r.point.point);
  const Impulse* best = nullptr;
  double best_distance = match_distance_;
  for (auto it = first; it != last; ++it) {
    const double d = (it->local - local).norm();
    if (d < best_distance) {
      best_distance = d;
      best = &it->impulse;
    }
  }
  return best;
}

void ContactStage::store(std::span<const Body> bodies, std::span<const double> lambda) {
  cache_.clear();
  previous_.clear();
  contacts_.clear();
  for (const ContactRecord& r : records_) {
    if (r.row < 0) continue;
    const auto k = static_cast<std::size_t>(r.row);
    const auto f = static_cast<std::size_t>(r.friction_row);
    const Impulse impulse{lambda[k], lambda[f] * r.t1 + lambda[f + 1] * r.t2};
    cache_[r.key] = impulse;
    previous_.push_back(Previous{
        r.pair, bodies[static_cast<std::size_t>(r.body_a)].pose().toLocal(r.point.point), impulse});
    contacts_.push_back(Contact{BodyId{r.body_a}, BodyId{r.body_b}, r.shape_a, r.shape_b,
                                r.point.point, r.point.normal, r.point.depth, impulse.normal,
                                impulse.friction, r.point.feature});
  }
}

}  // namespace linx::world
