#include "step/contact_stage.hpp"

#include "world/state_archive.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "collision/aabb.hpp"
#include "collision/geometry.hpp"
#include "parallel/parallel_for.hpp"
#include "step/assembly.hpp"
#include "step/split_impulse.hpp"

namespace linx::step {

namespace {
/// Pairs for the narrowphase to split over threads (fewer are done on the calling thread).
constexpr std::size_t kParallelPairs = 1024;
/// Contacts for appendRows and store to split over threads.
constexpr std::ptrdiff_t kParallelContacts = 1024;
/// Shapes whose poses and swept boxes are computed by several threads.
constexpr std::ptrdiff_t kParallelShapes = 2048;

/// Identity of a contact across steps: bit 63 (a contact, not a joint), the two global shape
/// indices and the feature id; bit 62 and the low two bits stay free for the rows (a spring
/// contact's normal row, step/split_impulse.hpp; the row slot).
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
  return kContactKey | (h & ~std::uint64_t{3} & ~kContactKey & ~kSpringContactKey);
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
  law.max_push_out = s.max_push_out;
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

/// The box a shape covers during a step: its box now joined with where its linear velocity takes
/// it, grown by what its spin adds and by half the speculative margin (two boxes grown by half
/// overlap within the whole margin). Far tighter than growing the box by the whole sweep in every
/// direction: spheres falling side by side have boxes that overlap only where they could meet.
collision::Aabb sweptBox(const Body& body, const collision::Aabb& tight, double h, double margin) {
  if (body.isStatic()) return tight.expanded(0.5 * margin);
  const Vec3 d = h * body.linearVelocity();
  const double arm = (tight.centre() - body.position()).norm() + 0.5 * tight.extent().norm();
  const double spin = h * body.angularVelocity().norm() * arm;
  const collision::Aabb swept{tight.min + d.cwiseMin(Vec3::Zero()),
                              tight.max + d.cwiseMax(Vec3::Zero())};
  return swept.expanded(0.5 * margin + spin);
}

/// The shape pair of a record, or the pair itself (for searching records by pair).
std::uint64_t pairOf(const ContactRecord& r) {
  return r.pair;
}
std::uint64_t pairOf(std::uint64_t pair) {
  return pair;
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
  if (!(gap > margin)) return true;  // also a NaN depth: its rows stop the step with an error
  const double closing = std::max(0.0, a.velocityAt(p.point).dot(p.normal)) +
                         std::max(0.0, -b.velocityAt(p.point).dot(p.normal));
  return gap <= margin + h * closing;
}
}  // namespace

void ContactStage::setBody(int index, const Body& body) {
  // Prepare every shape first: a shape that throws leaves the stage as it was.
  std::vector<std::shared_ptr<const collision::Geometry>> prepared;
  for (const ShapeDef& shape : body.shapes()) prepared.push_back(collision::prepareGeometry(shape));
  // The shapes go at the end, whatever the slot: the others keep their indices (and the keys of
  // their contacts' warm start).
  const auto slot = static_cast<std::size_t>(index);
  if (slot == first_shape_.size()) first_shape_.push_back(0);
  first_shape_[slot] = static_cast<int>(geometry_.size());
  for (auto& g : prepared) {
    geometry_.push_back(std::move(g));
    shape_body_.push_back(index);
  }
  // A body new in an old slot does not rest where the old one did.
  if (slot < detected_still_.size()) detected_still_[slot] = 0;
}

void ContactStage::removeBody(int index) {
  const auto slot = static_cast<std::size_t>(index);
  for (std::size_t s = static_cast<std::size_t>(first_shape_[slot]);
       s < shape_body_.size() && shape_body_[s] == index; ++s) {
    shape_body_[s] = -1;
    geometry_[s].reset();
    ++removed_shapes_;
  }
  if (slot < detected_still_.size()) detected_still_[slot] = 0;
  if (removed_shapes_ > 64 && 2 * removed_shapes_ > shape_body_.size()) packShapes();
}

void ContactStage::packShapes() {
  std::vector<std::shared_ptr<const collision::Geometry>> geometry;
  std::vector<int> shape_body;
  for (std::size_t b = 0; b < first_shape_.size(); ++b) {
    const int start = static_cast<int>(geometry.size());
    for (auto s = static_cast<std::size_t>(first_shape_[b]);
         s < shape_body_.size() && shape_body_[s] == static_cast<int>(b); ++s) {
      geometry.push_back(std::move(geometry_[s]));
      shape_body.push_back(static_cast<int>(b));
    }
    first_shape_[b] = start;
  }
  geometry_.swap(geometry);
  shape_body_.swap(shape_body);
  removed_shapes_ = 0;
  // The kept points name shapes by their old indices: forget them.
  last_records_.clear();
  previous_.clear();
  detected_ = false;
}

void ContactStage::touching(int body, std::vector<int>& out) const {
  for (const ContactRecord& r : records_) {
    if (r.body_a == body) out.push_back(r.body_b);
    if (r.body_b == body) out.push_back(r.body_a);
  }
}

void ContactStage::detect(std::span<const Body> bodies,
                          std::span<const std::unique_ptr<Joint>> joints,
                          const ContactSettings& settings, double h, int threads) {
  records_.swap(last_records_);  // the last step's, for the pairs of bodies that rest
  records_.clear();
  match_distance_ = settings.margin;
  findResting(bodies, settings, h);
  if (!settings.enabled || geometry_.empty()) return;

  joined_.clear();
  for (const auto& j : joints) {
    if (j->def().collide || j->body2().isWorld() || !j->enabled()) continue;
    const int a = j->body1().index, b = j->body2().index;
    joined_.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(joined_.begin(), joined_.end());

  // Broadphase over every shape's swept box.
  boxes_.resize(geometry_.size());
  std::vector<double>& reach = reach_;
  reach.resize(geometry_.size());
  poses_.resize(geometry_.size());
  parallel::forEach(static_cast<std::ptrdiff_t>(geometry_.size()), threads, kParallelShapes,
                    [&](std::ptrdiff_t is) {
                      const auto s = static_cast<std::size_t>(is);
                      if (shape_body_[s] < 0) {  // removed: a box that overlaps nothing
                        const double nan = std::numeric_limits<double>::quiet_NaN();
                        boxes_[s] = collision::Aabb{Vec3::Constant(nan), Vec3::Constant(nan)};
                        reach[s] = 0.0;
                        return;
                      }
                      const Body& body = bodies[static_cast<std::size_t>(shape_body_[s])];
                      const int local = static_cast<int>(s) -
                                        first_shape_[static_cast<std::size_t>(shape_body_[s])];
                      const ShapeDef& shape = body.shapes()[static_cast<std::size_t>(local)];
                      poses_[s] = shapePose(body, shape);
                      const collision::Aabb tight = collision::shapeAabb(shape, body.pose());
                      reach[s] = sweep(body, tight, h);
                      boxes_[s] = sweptBox(body, tight, h, settings.margin);
                    });
  broadphase_.update(boxes_, threads);

  // Narrowphase, pair by pair. Large sets of pairs are cut into consecutive chunks that threads
  // work on apart; joined in chunk order, the records come out in pair order for any thread count.
  const auto& pairs = broadphase_.pairs();
  const std::size_t chunks =
      threads > 1 && pairs.size() >= kParallelPairs ? 16 * static_cast<std::size_t>(threads) : 1;
  if (chunk_records_.size() < chunks) chunk_records_.resize(chunks);
  if (chunk_points_.size() < chunks) chunk_points_.resize(chunks);
  parallel::forEachTask(static_cast<std::ptrdiff_t>(chunks), threads, [&](std::ptrdiff_t c) {
    const std::size_t begin = pairs.size() * static_cast<std::size_t>(c) / chunks;
    const std::size_t end = pairs.size() * static_cast<std::size_t>(c + 1) / chunks;
    std::vector<ContactRecord>& out = chunk_records_[static_cast<std::size_t>(c)].value;
    out.clear();
    for (std::size_t k = begin; k < end; ++k)
      collidePair(bodies, settings, h, pairs[k].first, pairs[k].second,
                  chunk_points_[static_cast<std::size_t>(c)].value, out);
  });
  // Join in chunk order, each chunk copied to its own place.
  chunk_offset_.assign(chunks + 1, 0);
  for (std::size_t c = 0; c < chunks; ++c)
    chunk_offset_[c + 1] = chunk_offset_[c] + chunk_records_[c].value.size();
  records_.resize(chunk_offset_[chunks]);
  parallel::forEach(static_cast<std::ptrdiff_t>(chunks), threads, 2, [&](std::ptrdiff_t c) {
    const auto& part = chunk_records_[static_cast<std::size_t>(c)].value;
    std::copy(
        part.begin(), part.end(),
        records_.begin() + static_cast<std::ptrdiff_t>(chunk_offset_[static_cast<std::size_t>(c)]));
  });
}

void ContactStage::findResting(std::span<const Body> bodies, const ContactSettings& settings,
                               double h) {
  // A body rests if it had no velocity at the last detect and has none now, and has not moved
  // since (a program may move a body between steps). A pair of resting bodies finds exactly the
  // points it found then: its shapes' poses, swept boxes and reaches are the same, and so are the
  // settings and the step length that its records' laws were made with.
  const bool same = detected_ && settings == detected_settings_ && h == detected_h_ &&
                    detected_pose_.size() == bodies.size();
  resting_.resize(bodies.size());
  detected_pose_.resize(bodies.size());
  detected_still_.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    const bool still = b.isStatic() || !b.isMoving();
    const Pose& pose = b.pose();
    resting_[i] = same && still && detected_still_[i] &&
                  pose.position == detected_pose_[i].position &&
                  pose.orientation.coeffs() == detected_pose_[i].orientation.coeffs();
    detected_pose_[i] = pose;
    detected_still_[i] = still;
  }
  detected_ = settings.enabled;
  detected_settings_ = settings;
  detected_h_ = h;
}

void ContactStage::collidePair(std::span<const Body> bodies, const ContactSettings& settings,
                               double h, int i, int j, std::vector<collision::ContactPoint>& points,
                               std::vector<ContactRecord>& out) const {
  const int body_i = shape_body_[static_cast<std::size_t>(i)];
  const int body_j = shape_body_[static_cast<std::size_t>(j)];
  if (body_i == body_j) return;
  const Body& bi = bodies[static_cast<std::size_t>(body_i)];
  const Body& bj = bodies[static_cast<std::size_t>(body_j)];
  if (!bi.isDynamic() && !bj.isDynamic()) return;  // nothing can respond
  const int local_i = i - first_shape_[static_cast<std::size_t>(body_i)];
  const int local_j = j - first_shape_[static_cast<std::size_t>(body_j)];
  const ShapeDef& si = bi.shapes()[static_cast<std::size_t>(local_i)];
  const ShapeDef& sj = bj.shapes()[static_cast<std::size_t>(local_j)];
  if ((si.group & sj.mask) == 0 || (sj.group & si.mask) == 0) return;
  if (std::binary_search(joined_.begin(), joined_.end(),
                         std::pair{std::min(body_i, body_j), std::max(body_i, body_j)}))
    return;

  if (resting_[static_cast<std::size_t>(body_i)] && resting_[static_cast<std::size_t>(body_j)]) {
    // Neither body moved since the last step: its points, as they were (the narrowphase took a
    // third of the 210-box pyramid's step after it fell asleep).
    const std::uint64_t pair =
        (static_cast<std::uint64_t>(i) << 32) | static_cast<std::uint32_t>(j);
    const auto [first, last] =
        std::equal_range(last_records_.begin(), last_records_.end(), pair,
                         [](const auto& x, const auto& y) { return pairOf(x) < pairOf(y); });
    out.insert(out.end(), first, last);
    return;
  }
  const collision::ShapeInstance a{&si, geometry_[static_cast<std::size_t>(i)].get(),
                                   poses_[static_cast<std::size_t>(i)]};
  const collision::ShapeInstance b{&sj, geometry_[static_cast<std::size_t>(j)].get(),
                                   poses_[static_cast<std::size_t>(j)]};
  const double margin =
      settings.margin + reach_[static_cast<std::size_t>(i)] + reach_[static_cast<std::size_t>(j)];
  points.clear();
  collision::collide(a, b, margin, points);
  const joints::ContactLaw law = combine(si, sj, settings, h);
  for (const collision::ContactPoint& p : points) {
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
    out.push_back(r);
  }
}

void ContactStage::appendRows(std::span<const Body> bodies, double h, std::vector<Row>& rows,
                              std::vector<double>& lambda, bool warm_start, int threads,
                              bool bounce, std::span<const StartVelocity> start) {
  // All normal rows first, then all friction rows: a Gauss-Seidel sweep then settles the normal
  // impulses of a whole pile before friction, whose bounds follow them, is solved against them.
  // Each contact writes its own three rows, so the contacts are split over the threads.
  const std::size_t first_normal = rows.size();
  const std::size_t first_friction = first_normal + records_.size();
  // Appended as copies of one blank row: value-initializing each (rep stos) cost as much as
  // writing them (perf, 210-box pyramid); contactRows then writes every field in place.
  static const Row blank{};
  rows.insert(rows.end(), 3 * records_.size(), blank);
  lambda.resize(rows.size(), 0.0);
  if (warm_start) findPrevious();
  // A contact spring's push is a force (the laws of this step's records are made with these).
  const bool spring = detected_settings_.stiffness && detected_settings_.damping;
  const auto count = static_cast<std::ptrdiff_t>(records_.size());
  parallel::forEach(count, threads, kParallelContacts, [&](std::ptrdiff_t index) {
    const auto c = static_cast<std::size_t>(index);
    ContactRecord& r = records_[c];
    const Body& a = bodies[static_cast<std::size_t>(r.body_a)];
    const Body& b = bodies[static_cast<std::size_t>(r.body_b)];
    joints::ContactLaw law = r.law;
    if (!bounce) law.restitution = 0.0;
    r.row = static_cast<int>(first_normal + c);
    r.friction_row = static_cast<int>(first_friction + 2 * c);
    const std::array<std::size_t, 3> at{first_normal + c, first_friction + 2 * c,
                                        first_friction + 2 * c + 1};
    double start_approach = std::numeric_limits<double>::quiet_NaN();
    if (law.restitution > 0.0 && !start.empty()) {
      const auto pointVelocity = [&](int body) {
        if (body < 0) return Vec3(Vec3::Zero());
        const StartVelocity& s = start[static_cast<std::size_t>(body)];
        return Vec3(s.v +
                    s.w.cross(r.point.point - bodies[static_cast<std::size_t>(body)].position()));
      };
      start_approach = -r.point.normal.dot(pointVelocity(r.body_b) - pointVelocity(r.body_a));
    }
    joints::contactRows(r.point, stateOf(bodies, BodyId{r.body_a}),
                        stateOf(bodies, BodyId{r.body_b}), law, h, rows[at[0]],
                        std::span<Row, 2>(&rows[at[1]], 2), r.t1, r.t2, start_approach);
    if (spring) {  // not split: it bounces, or pushes, whichever is faster (contactRows' rule)
      Row& n = rows[at[0]];
      if (n.speed > 0.0 && n.phi < 0.0) {
        if (n.speed > -(n.erp / h) * n.phi)
          n.phi = 0.0;
        else
          n.speed = 0.0;
      }
    }
    for (std::size_t k = 0; k < 3; ++k) {
      Row& row = rows[at[k]];
      row.body_a = a.isStatic() ? -1 : r.body_a;
      row.body_b = b.isStatic() ? -1 : r.body_b;
      row.key |= r.key;
      if (k == 0 && spring) row.key |= kSpringContactKey;  // its push stays in the velocity
      if (row.normal >= 0) row.normal = r.row;
    }
    if (warm_start) {
      if (const Impulse* old = previousImpulse(c, a)) {
        lambda[at[0]] = old->normal;
        lambda[at[1]] = old->friction.dot(r.t1);  // the old tangential impulse, projected
        lambda[at[2]] = old->friction.dot(r.t2);  // on the new tangents
      }
    }
  });
}

void ContactStage::findPrevious() {
  // Both lists are in shape-pair order: one merge, not a binary search per point (which cost 6 %
  // of the 210-box pyramid's step).
  previous_range_.resize(records_.size());
  std::size_t p = 0;
  for (std::size_t c = 0; c < records_.size(); ++c) {
    const std::uint64_t pair = records_[c].pair;
    if (c > 0 && records_[c - 1].pair == pair) {
      previous_range_[c] = previous_range_[c - 1];
      continue;
    }
    while (p < previous_.size() && previous_[p].pair < pair) ++p;
    std::size_t end = p;
    while (end < previous_.size() && previous_[end].pair == pair) ++end;
    previous_range_[c] = {p, end};
  }
}

const ContactStage::Impulse* ContactStage::previousImpulse(std::size_t c, const Body& a) const {
  // The same point (key) if the pair had it, else the pair's nearest point within the margin.
  const ContactRecord& r = records_[c];
  const auto [first, last] = previous_range_[c];
  for (std::size_t k = first; k < last; ++k)
    if (previous_[k].key == r.key) return &previous_[k].impulse;
  const Vec3 local = a.pose().toLocal(r.point.point);
  const Impulse* best = nullptr;
  double best_distance = match_distance_;
  for (std::size_t k = first; k < last; ++k) {
    const double d = (previous_[k].local - local).norm();
    if (d < best_distance) {
      best_distance = d;
      best = &previous_[k].impulse;
    }
  }
  return best;
}

void ContactStage::store(std::span<const Body> bodies, std::span<const double> lambda, int threads,
                         std::span<const double> reported) {
  // Records are in shape-pair order (the broadphase's), so previous_ comes out sorted by pair.
  stored_.clear();
  for (std::size_t c = 0; c < records_.size(); ++c)
    if (records_[c].row >= 0) stored_.push_back(static_cast<int>(c));
  previous_.resize(stored_.size());
  contacts_.resize(stored_.size());
  parallel::forEach(
      static_cast<std::ptrdiff_t>(stored_.size()), threads, kParallelContacts,
      [&](std::ptrdiff_t index) {
        const auto out = static_cast<std::size_t>(index);
        const ContactRecord& r = records_[static_cast<std::size_t>(stored_[out])];
        const auto k = static_cast<std::size_t>(r.row);
        const auto f = static_cast<std::size_t>(r.friction_row);
        const Impulse impulse{lambda[k], lambda[f] * r.t1 + lambda[f + 1] * r.t2};
        const Pose& pose = bodies[static_cast<std::size_t>(r.body_a)].pose();
        previous_[out] = Previous{r.pair, r.key, pose.toLocal(r.point.point), impulse};
        const Impulse shown =
            reported.empty() ? impulse
                             : Impulse{reported[k], reported[f] * r.t1 + reported[f + 1] * r.t2};
        contacts_[out] = Contact{bodies[static_cast<std::size_t>(r.body_a)].id(),
                                 bodies[static_cast<std::size_t>(r.body_b)].id(),
                                 r.shape_a,
                                 r.shape_b,
                                 r.point.point,
                                 r.point.normal,
                                 r.point.depth,
                                 shown.normal,
                                 shown.friction,
                                 r.point.feature};
      });
}

namespace {

void persistRecord(state::Archive& a, ContactRecord& r) {
  a.fields(r.body_a, r.body_b, r.shape_a, r.shape_b, r.point.point, r.point.normal, r.point.depth,
           r.point.feature, r.law.friction, r.law.restitution, r.law.erp, r.law.cfm, r.law.slop,
           r.law.restitution_threshold, r.law.max_push_out, r.key, r.pair, r.t1, r.t2, r.row,
           r.friction_row);
}

}  // namespace

void ContactStage::persist(state::Archive& a) {
  a.each(records_, persistRecord);
  a.each(last_records_, persistRecord);
  a.fields(resting_, detected_pose_, detected_still_, detected_h_, detected_);
  ContactSettings& s = detected_settings_;
  a.fields(s.enabled, s.margin, s.slop, s.erp, s.cfm, s.stiffness, s.damping,
           s.restitution_threshold, s.max_push_out, s.hertz, s.damping_ratio);
  a.each(contacts_, [](state::Archive& a, Contact& c) {
    a.fields(c.body1.index, c.body1.generation, c.body2.index, c.body2.generation, c.shape1,
             c.shape2, c.point, c.normal, c.depth, c.normal_impulse, c.friction_impulse, c.feature);
  });
  a.each(previous_, [](state::Archive& a, Previous& p) {
    a.fields(p.pair, p.key, p.local, p.impulse.normal, p.impulse.friction);
  });
  a.fields(stored_, match_distance_);
}

}  // namespace linx::step
