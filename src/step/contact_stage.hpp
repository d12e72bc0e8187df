// The contact stage of a step: shapes -> broadphase -> narrowphase -> contact rows, and the
// contact impulses kept from one step to the next (warm starting by feature id).
//
// Which pairs are tested: shapes of two different bodies, not both unmovable, whose collision
// filters accept each other ((group1 & mask2) and (group2 & mask1) non-zero), and whose bodies are
// not joined by a joint (unless the joint says `collide`). The broadphase boxes are grown by the
// speculative margin plus what the body's speed covers in the step, so that a contact exists
// before two fast shapes meet.
#pragma once

#include <linx/body.hpp>
#include <linx/contact.hpp>
#include <linx/joint.hpp>
#include <linx/row.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "collision/broadphase.hpp"
#include "collision/narrowphase.hpp"
#include "joints/contact_joint.hpp"
#include "parallel/task_output.hpp"
#include "step/assembly.hpp"

namespace linx::state {
class Archive;
}

namespace linx::step {

/// One contact point of this step between body a's shape and body b's shape.
struct ContactRecord {
  int body_a = 0, body_b = 0;    ///< body indices (either may be static, never the world)
  int shape_a = 0, shape_b = 0;  ///< shape indices within the bodies
  collision::ContactPoint point;
  joints::ContactLaw law;
  std::uint64_t key = 0;   ///< identity across steps: the shape pair and the feature
  std::uint64_t pair = 0;  ///< the two global shape indices
  Vec3 t1 = Vec3::Zero(), t2 = Vec3::Zero();  ///< tangents of the friction rows
  int row = -1;           ///< index of its normal row in the row list (-1: no rows)
  int friction_row = -1;  ///< index of its first friction row (the second follows)
};

class ContactStage {
 public:
  /// Prepares the shapes of a body created in slot `index` (hulls, meshes): a new slot
  /// (bodies are added in order) or one that removeBody freed. Throws std::invalid_argument for
  /// shapes that cannot be prepared, leaving the stage as it was.
  void setBody(int index, const Body& body);
  /// Drops the shapes of the body in slot `index` (World::removeBody): they meet nothing from
  /// then on. The other shapes keep their indices and their contacts' warm start, until removed
  /// shapes outnumber the rest and the shapes are packed again (one step without warm start).
  void removeBody(int index);

  /// Finds this step's contact points from the bodies' current poses and velocities, the
  /// narrowphase split over `threads` (the records are the same for any count).
  void detect(std::span<const Body> bodies, std::span<const std::unique_ptr<Joint>> joints,
              const ContactSettings& settings, double h, int threads = 1);

  /// Appends three rows per contact (normal, two friction) and their warm-start impulses. With
  /// `bounce` false the normal rows leave restitution out (the soft step applies it after its
  /// substeps, from the records' laws). `start`: the bodies' velocities before the step's forces,
  /// whose approach a bounce reflects (empty: their current ones).
  void appendRows(std::span<const Body> bodies, double h, std::vector<Row>& rows,
                  std::vector<double>& lambda, bool warm_start, int threads = 1, bool bounce = true,
                  std::span<const StartVelocity> start = {});

  /// Keeps the solved impulses for the next step's warm start and the contacts() report, which
  /// takes `reported` instead when given (the soft step's impulses over all its substeps).
  void store(std::span<const Body> bodies, std::span<const double> lambda, int threads = 1,
             std::span<const double> reported = {});

  std::span<const ContactRecord> records() const { return records_; }
  /// Appends the bodies that touched `body` in the last step.
  void touching(int body, std::vector<int>& out) const;
  std::span<const Contact> contacts() const { return contacts_; }

  /// Reads or writes what carries to the next step (World::saveState): the last step's records
  /// and contacts, what its detect saw of resting bodies, and the impulses kept for warm starts.
  void persist(state::Archive& archive);

 private:
  struct Impulse {
    double normal = 0.0;
    Vec3 friction = Vec3::Zero();  // world-frame tangential impulse on body b
  };

  std::vector<std::shared_ptr<const collision::Geometry>> geometry_;  // per shape, flattened
  std::vector<int> first_shape_;    // body i's shapes start at first_shape_[i] in geometry_
  std::vector<int> shape_body_;     // the body of each flattened shape, -1 for a removed one
  std::size_t removed_shapes_ = 0;  // entries of shape_body_ that are -1
  void packShapes();
  std::vector<collision::Aabb> boxes_;
  std::vector<Pose> poses_;    // per shape: its frame in the world this step
  std::vector<double> reach_;  // per shape: how far its points travel in the step (m)
  collision::SweepAndPrune broadphase_;
  std::vector<std::pair<int, int>> joined_;  // body pairs joined by a non-colliding joint, sorted
  // The narrowphase of shape pair (i, j): appends its records to out (points: scratch).
  void collidePair(std::span<const Body> bodies, const ContactSettings& settings, double h, int i,
                   int j, std::vector<collision::ContactPoint>& points,
                   std::vector<ContactRecord>& out) const;
  // Per chunk of pairs: scratch points and the records found.
  std::vector<parallel::TaskOutput<std::vector<collision::ContactPoint>>> chunk_points_;
  std::vector<parallel::TaskOutput<std::vector<ContactRecord>>> chunk_records_;
  std::vector<std::size_t> chunk_offset_;  // where each chunk's records go in records_
  std::vector<ContactRecord> records_;
  std::vector<ContactRecord> last_records_;  // the last detect's, in pair order
  // Bodies that rest (no velocity at the last detect nor now, the same pose): their pairs reuse
  // the last detect's records. What the last detect saw, to tell:
  std::vector<std::uint8_t> resting_;
  std::vector<Pose> detected_pose_;
  std::vector<std::uint8_t> detected_still_;
  ContactSettings detected_settings_;
  double detected_h_ = 0.0;
  bool detected_ = false;
  void findResting(std::span<const Body> bodies, const ContactSettings& settings, double h);
  std::vector<Contact> contacts_;
  // The last step's points by shape pair (sorted), in body a's frame: a point is matched by its
  // key, and a point whose feature id changed (a manifold that switched its reference face) to
  // the nearest old point of its pair.
  struct Previous {
    std::uint64_t pair;
    std::uint64_t key;
    Vec3 local;
    Impulse impulse;
  };
  std::vector<Previous> previous_;
  std::vector<int> stored_;  // store(): the records that got rows
  // Per record: its pair's points in previous_ (found by findPrevious before the rows are built).
  std::vector<std::pair<std::size_t, std::size_t>> previous_range_;
  void findPrevious();
  /// The warm-start impulse of record c, if the last step had its point.
  const Impulse* previousImpulse(std::size_t c, const Body& a) const;
  double match_distance_ = 0.0;
};

}  // namespace linx::step
