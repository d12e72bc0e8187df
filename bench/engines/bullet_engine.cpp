// Bullet 3.24 (Debian libbullet-dev, double precision: pkg-config bullet-float64) adapters.
//
// Two variants:
//   * rigid bodies + typed constraints (btHingeConstraint, btSliderConstraint,
//     btPoint2PointConstraint, btFixedConstraint) in a btDiscreteDynamicsWorld stepped by the
//     btSequentialImpulseConstraintSolver at its default 10 iterations; every scene;
//   * btMultiBody (Featherstone, reduced coordinates) in a btMultiBodyDynamicsWorld with the
//     btMultiBodyConstraintSolver, for scenes whose joints are hinges forming trees (no loops),
//     each rooted at the world (fixed base) or at a free body (floating base); hinge limits are
//     btMultiBodyJointLimitConstraint, motors btMultiBodyJointMotor. Bodies outside any tree (and
//     static bodies, the ground) are ordinary btRigidBody objects in the same world.
//
// Both use Bullet's own collision detection (btDbvtBroadphase + btDefaultCollisionConfiguration)
// and its default contact and solver parameters (10 iterations, ERP 0.2, split impulse, warm
// starting 0.85, one friction direction per contact point, collision margins). What we set:
//   * inertia from Scene::Body::inertia (never from the shape); the ground is a btStaticPlaneShape;
//   * every body's friction sqrt(mu), because Bullet combines a pair's frictions by product;
//   * sleeping (deactivation) is Bullet's default in scenes with contacts, and off in mechanisms
//     without any (chains, slider-crank), where nothing would ever come to rest;
//   * btMultiBody: linear and angular damping 0 (Bullet's default is 0.04); its other defaults
//   stay,
//     notably the clamp of every joint and base velocity at 100 (rad/s, m/s).
#include "engine.hpp"

#include <BulletCollision/CollisionShapes/btEmptyShape.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace bench {
namespace {

btVector3 bt(const Vec3& v) {
  return btVector3(v.x(), v.y(), v.z());
}
btQuaternion bt(const Quat& q) {
  return btQuaternion(q.x(), q.y(), q.z(), q.w());
}
Vec3 eig(const btVector3& v) {
  return Vec3(v.x(), v.y(), v.z());
}
Quat eig(const btQuaternion& q) {
  return Quat(q.w(), q.x(), q.y(), q.z()).normalized();
}

/// Whether any contact can occur: a dynamic body with a shape, and something else with a shape or
/// a ground plane. Mechanisms without contacts (the chains, the slider-crank) run with sleeping
/// off.
bool hasContacts(const Scene& s) {
  int shaped = 0, dynamic_shaped = 0;
  for (const Body& b : s.bodies) {
    if (b.shape.kind == Shape::Kind::None) continue;
    ++shaped;
    if (!b.is_static) ++dynamic_shaped;
  }
  return dynamic_shaped > 0 && (s.ground_z.has_value() || shaped >= 2);
}

/// A rotation whose column `column` (0 = x, 2 = z) is the unit vector n: the joint frame of
/// btSliderConstraint (slides along x) and btHingeConstraint (turns about z).
btMatrix3x3 frameAlong(const btVector3& n, int column) {
  btVector3 p, q;
  btPlaneSpace1(n, p, q);  // p, q, n right-handed
  btMatrix3x3 m;
  if (column == 2) {
    m.setValue(p.x(), q.x(), n.x(), p.y(), q.y(), n.y(), p.z(), q.z(), n.z());
  } else {
    m.setValue(n.x(), p.x(), q.x(), n.y(), p.y(), q.y(), n.z(), p.z(), q.z());
  }
  return m;
}

/// Collision shapes shared by every body with the same geometry (as Bullet users do).
class ShapeCache {
 public:
  btCollisionShape* get(const Shape& s) {
    switch (s.kind) {
      case Shape::Kind::None:
        return nullptr;
      case Shape::Kind::Sphere:
        return find(0, s.radius, 0, 0, [&] { return new btSphereShape(s.radius); });
      case Shape::Kind::Box:
        return find(1, s.half_extents.x(), s.half_extents.y(), s.half_extents.z(),
                    [&] { return new btBoxShape(bt(s.half_extents)); });
      case Shape::Kind::Capsule:  // btCapsuleShapeZ: height = distance between the sphere centres
        return find(2, s.radius, s.half_length, 0,
                    [&] { return new btCapsuleShapeZ(s.radius, 2.0 * s.half_length); });
    }
    return nullptr;
  }
  btCollisionShape* empty() {
    if (!empty_) empty_ = std::make_unique<btEmptyShape>();
    return empty_.get();
  }
  btCollisionShape* plane(double z) {
    planes_.push_back(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), z));
    return planes_.back().get();
  }

 private:
  template <class Make>
  btCollisionShape* find(int kind, double a, double b, double c, Make make) {
    auto& slot = shapes_[std::make_tuple(kind, a, b, c)];
    if (!slot) slot.reset(make());
    return slot.get();
  }
  std::map<std::tuple<int, double, double, double>, std::unique_ptr<btCollisionShape>> shapes_;
  std::unique_ptr<btCollisionShape> empty_;
  std::vector<std::unique_ptr<btCollisionShape>> planes_;
};

/// Which bodies the btMultiBody variant turns into trees, and how.
struct TreePlan {
  struct Link {
    int body;    // scene body of this link
    int parent;  // scene body of its parent, -1: the world (fixed base)
    int joint;   // scene joint between them
  };
  struct Tree {
    int base = -1;            // scene body of the floating base, -1: fixed base at the world
    std::vector<Link> links;  // parents before children
  };
  std::vector<Tree> trees;
  std::string why_not;  // non-empty: the scene cannot be expressed as hinge trees
};

TreePlan planTrees(const Scene& s) {
  TreePlan plan;
  const int n = static_cast<int>(s.bodies.size());
  const int world = n;  // static bodies are merged into the world node
  auto node = [&](int b) { return b < 0 || s.bodies[b].is_static ? world : b; };
  std::vector<int> up(n + 1);
  for (int i = 0; i <= n; ++i) up[i] = i;
  auto find = [&](int x) {
    while (up[x] != x) x = up[x] = up[up[x]];
    return x;
  };
  std::vector<std::vector<std::pair<int, int>>> adj(n + 1);  // (joint, other node)
  std::vector<bool> is_body2(n + 1, false);
  for (int j = 0; j < static_cast<int>(s.joints.size()); ++j) {
    const Joint& jt = s.joints[j];
    if (jt.kind != Joint::Kind::Hinge) {
      plan.why_not =
          "btMultiBody variant: hinge trees only (this scene has a slider, ball or fixed joint)";
      return plan;
    }
    const int a = node(jt.body1), b = node(jt.body2);
    if (find(a) == find(b)) {
      plan.why_not = "btMultiBody variant: the joints form a closed loop";
      return plan;
    }
    up[find(a)] = find(b);
    adj[a].push_back({j, b});
    adj[b].push_back({j, a});
    is_body2[b] = true;
  }
  std::vector<bool> seen(n + 1, false);
  // Breadth-first from `root`, appending links in parent-before-child order.
  auto grow = [&](int root, TreePlan::Tree& tree, int only_child_joint) {
    std::vector<int> queue{root};
    seen[root] = true;
    for (std::size_t k = 0; k < queue.size(); ++k) {
      const int p = queue[k];
      for (auto [j, c] : adj[p]) {
        if (seen[c]) continue;
        if (p == world && j != only_child_joint) continue;
        seen[c] = true;
        tree.links.push_back({c, p == world ? -1 : p, j});
        queue.push_back(c);
      }
    }
  };
  // One fixed-base multibody per hinge hanging from the world (or a static body).
  seen[world] = true;
  for (auto [j, c] : adj[world]) {
    if (seen[c]) continue;
    TreePlan::Tree tree;
    grow(world, tree, j);
    plan.trees.push_back(std::move(tree));
  }
  // One floating-base multibody per remaining jointed component, rooted at a body that is never
  // a joint's body2 (the scene lists joints parent first), else at its lowest-index body.
  for (int pass = 0; pass < 2; ++pass) {
    for (int b = 0; b < n; ++b) {
      if (seen[b] || adj[b].empty() || (pass == 0 && is_body2[b])) continue;
      TreePlan::Tree tree;
      tree.base = b;
      grow(b, tree, -1);
      plan.trees.push_back(std::move(tree));
    }
  }
  return plan;
}

/// Above this many bodies the variants refuse the scene (see the message in the constructor).
constexpr std::size_t kMaxBodies = 20000;
/// btContactSolverInfo's default m_numIterations, the main table's.
constexpr int kDefaultIterations = 10;

class BulletEngine final : public Engine {
 public:
  BulletEngine(const Scene& scene, bool featherstone, int iterations = kDefaultIterations)
      : scene_(scene), h_(scene.timestep) {
    if (!scene.springs.empty()) throw Unsupported("Bullet: the scene's springs are not mapped");
    if (scene.bodies.size() > kMaxBodies) {
      throw Unsupported(
          "Bullet: more than 20,000 bodies; with its default btDbvtBroadphase, 64,000 poured "
          "spheres held 4.1 M broadphase pairs (11 GB) after 40 steps, at ~20 s/step");
    }
    const bool contacts = hasContacts(scene);
    const double mu_body = std::sqrt(scene.friction);  // Bullet multiplies the two frictions
    config_ = std::make_unique<btDefaultCollisionConfiguration>();
    dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
    broadphase_ = std::make_unique<btDbvtBroadphase>();
    if (featherstone) {
      auto* solver = new btMultiBodyConstraintSolver;
      solver_.reset(solver);
      auto* w =
          new btMultiBodyDynamicsWorld(dispatcher_.get(), broadphase_.get(), solver, config_.get());
      world_.reset(w);
      mbworld_ = w;
    } else {
      solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
      world_ = std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(),
                                                         solver_.get(), config_.get());
    }
    world_->setGravity(bt(scene.gravity));
    world_->getSolverInfo().m_numIterations = iterations;

    const int n = static_cast<int>(scene.bodies.size());
    where_.assign(n, Where{});

    TreePlan plan;
    if (featherstone) {
      plan = planTrees(scene);
      if (!plan.why_not.empty()) throw Unsupported(plan.why_not);
      for (std::size_t t = 0; t < plan.trees.size(); ++t) {
        const TreePlan::Tree& tree = plan.trees[t];
        if (tree.base >= 0) where_[tree.base] = Where{static_cast<int>(t), -1};
        for (std::size_t k = 0; k < tree.links.size(); ++k)
          where_[tree.links[k].body] = Where{static_cast<int>(t), static_cast<int>(k)};
      }
    }

    // Ordinary rigid bodies: everything outside the trees.
    rigid_.resize(n);
    for (int i = 0; i < n; ++i) {
      if (where_[i].tree >= 0) continue;
      const Body& b = scene.bodies[i];
      btCollisionShape* shape = shapes_.get(b.shape);
      const bool shapeless = shape == nullptr;
      if (shapeless) shape = shapes_.empty();
      const double mass = b.is_static ? 0.0 : b.mass;
      const btVector3 inertia = b.is_static ? btVector3(0, 0, 0) : bt(b.inertia);
      btRigidBody::btRigidBodyConstructionInfo ci(mass, nullptr, shape, inertia);
      ci.m_startWorldTransform = btTransform(bt(b.orientation), bt(b.position));
      ci.m_friction = mu_body;
      auto body = std::make_unique<btRigidBody>(ci);
      if (!b.is_static) {
        body->setLinearVelocity(bt(b.velocity));
        body->setAngularVelocity(bt(b.angular_velocity));
        if (!contacts) body->setActivationState(DISABLE_DEACTIVATION);
      }
      if (shapeless) {
        world_->addRigidBody(body.get(), 0, 0);  // never in a broadphase pair
      } else {
        world_->addRigidBody(body.get());
      }
      rigid_[i] = std::move(body);
    }
    if (scene.ground_z) {
      btRigidBody::btRigidBodyConstructionInfo ci(0.0, nullptr, shapes_.plane(*scene.ground_z));
      ci.m_friction = mu_body;
      ground_ = std::make_unique<btRigidBody>(ci);
      world_->addRigidBody(ground_.get());
    }

    if (featherstone) {
      buildTrees(plan, contacts, mu_body);
    } else {
      buildConstraints();
    }
  }

  ~BulletEngine() override {
    for (auto& c : mbconstraints_) mbworld_->removeMultiBodyConstraint(c.get());
    for (auto& c : constraints_) world_->removeConstraint(c.get());
    for (auto& c : colliders_) world_->removeCollisionObject(c.get());
    for (auto& t : trees_) mbworld_->removeMultiBody(t.mb.get());
    for (auto& b : rigid_)
      if (b) world_->removeRigidBody(b.get());
    if (ground_) world_->removeRigidBody(ground_.get());
    mbconstraints_.clear();
    constraints_.clear();
    colliders_.clear();
    trees_.clear();
    rigid_.clear();
    ground_.reset();
    world_.reset();
    solver_.reset();
    broadphase_.reset();
    dispatcher_.reset();
    config_.reset();
  }

  void step() override {
    world_->stepSimulation(h_, 0);  // maxSubSteps = 0: exactly one internal step of h
    ++steps_;
  }

  Pose pose(int i) const override {
    const Where w = where_[i];
    if (w.tree < 0) {
      const btTransform& tr = rigid_[i]->getWorldTransform();
      return Pose{eig(tr.getOrigin()), eig(tr.getRotation())};
    }
    const Tree& t = trees_[w.tree];
    if (t.posed_at != steps_) updatePoses(t);
    return t.poses[w.link + 1];
  }

  // btRigidBody: its frame is the centre of mass's, and both velocities are in the world frame.
  // btMultiBody: see updatePoses.
  Twist velocity(int i) const override {
    const Where w = where_[i];
    if (w.tree < 0) {
      if (!rigid_[i] || scene_.bodies[static_cast<std::size_t>(i)].is_static) return Twist{};
      return Twist{eig(rigid_[i]->getLinearVelocity()), eig(rigid_[i]->getAngularVelocity())};
    }
    const Tree& t = trees_[w.tree];
    if (t.posed_at != steps_) updatePoses(t);
    return t.twists[w.link + 1];
  }

 private:
  struct Where {
    int tree = -1;  // index into trees_, -1: a btRigidBody
    int link = -1;  // -1: the base
  };
  struct Tree {
    std::unique_ptr<btMultiBody> mb;
    mutable std::vector<Pose> poses;  // [0] base, [k + 1] link k
    mutable btAlignedObjectArray<btQuaternion> world_to_local;
    mutable btAlignedObjectArray<btVector3> origin;
    mutable std::vector<Twist> twists;  // [0] base, [k + 1] link k
    mutable btAlignedObjectArray<btVector3> omega, vel;
    mutable long posed_at = -1;
  };

  btRigidBody& rigidOrWorld(int b) {
    if (b >= 0) return *rigid_[b];
    if (!world_body_) {  // a static body outside the world, frame = world frame
      btRigidBody::btRigidBodyConstructionInfo ci(0.0, nullptr, shapes_.empty());
      world_body_ = std::make_unique<btRigidBody>(ci);
    }
    return *world_body_;
  }

  void buildConstraints() {
    for (const Joint& j : scene_.joints) {
      // body1 is always Bullet's A and body2 its B, the world included (a static body outside the
      // world, rather than the one-body constructors that make the body A), so that the joint
      // coordinate has one sign convention whichever body is the world.
      btRigidBody& a = rigidOrWorld(j.body1);
      btRigidBody& b = rigidOrWorld(j.body2);
      const btTransform& ta = a.getWorldTransform();
      const btTransform& tb = b.getWorldTransform();
      const btVector3 anchor = bt(j.anchor), axis = bt(j.axis);
      std::unique_ptr<btTypedConstraint> c;
      switch (j.kind) {
        case Joint::Kind::Hinge: {
          const btTransform frame(frameAlong(axis, 2), anchor);
          auto h =
              std::make_unique<btHingeConstraint>(a, b, ta.inverse() * frame, tb.inverse() * frame);
          // With useReferenceFrameA = false (the default), btHingeConstraint's angle, limits and
          // motor velocity are those of A relative to B, the opposite of the scene's coordinate.
          if (j.limits) h->setLimit(-j.limits->upper, -j.limits->lower);
          if (j.motor)  // the hinge motor takes an impulse per step
            h->enableAngularMotor(true, -j.motor->target_velocity, j.motor->max_force * h_);
          c = std::move(h);
          break;
        }
        case Joint::Kind::Slider: {
          const btTransform frame(frameAlong(axis, 0), anchor);
          auto sl = std::make_unique<btSliderConstraint>(a, b, ta.inverse() * frame,
                                                         tb.inverse() * frame, true);
          if (j.limits) {
            sl->setLowerLinLimit(j.limits->lower);
            sl->setUpperLinLimit(j.limits->upper);
          }  // else: lower > upper by default, a free slide; rotation stays locked (0, 0)
          if (j.motor) {  // the slider motor takes a force
            sl->setPoweredLinMotor(true);
            sl->setTargetLinMotorVelocity(j.motor->target_velocity);
            sl->setMaxLinMotorForce(j.motor->max_force);
          }
          c = std::move(sl);
          break;
        }
        case Joint::Kind::Ball:
          c = std::make_unique<btPoint2PointConstraint>(a, b, ta.inverse() * anchor,
                                                        tb.inverse() * anchor);
          break;
        case Joint::Kind::Fixed: {
          const btTransform frame(btMatrix3x3::getIdentity(), anchor);
          c = std::make_unique<btFixedConstraint>(a, b, ta.inverse() * frame, tb.inverse() * frame);
          break;
        }
      }
      world_->addConstraint(c.get(), true);  // true: the two bodies never collide
      constraints_.push_back(std::move(c));
    }
  }

  void buildTrees(const TreePlan& plan, bool contacts, double mu_body) {
    const auto& bodies = scene_.bodies;
    // The pose of a parent: a scene body, or the world (identity) for -1 and static bodies.
    auto posOf = [&](int b) {
      return b < 0 || bodies[b].is_static ? Vec3(Vec3::Zero()) : bodies[b].position;
    };
    auto rotOf = [&](int b) {
      return b < 0 || bodies[b].is_static ? Quat(Quat::Identity()) : bodies[b].orientation;
    };
    auto omegaOf = [&](int b) {
      return b < 0 || bodies[b].is_static ? Vec3(Vec3::Zero()) : bodies[b].angular_velocity;
    };
    auto linkOf = [&](int b) { return b < 0 || bodies[b].is_static ? -1 : where_[b].link; };

    for (const TreePlan::Tree& plan_tree : plan.trees) {
      const int nl = static_cast<int>(plan_tree.links.size());
      const bool fixed = plan_tree.base < 0;
      const Body* base = fixed ? nullptr : &bodies[plan_tree.base];
      Tree tree;
      tree.mb = std::make_unique<btMultiBody>(nl, fixed ? 0.0 : base->mass,
                                              fixed ? btVector3(0, 0, 0) : bt(base->inertia), fixed,
                                              /*canSleep*/ contacts);
      btMultiBody& mb = *tree.mb;
      if (fixed) {
        mb.setBasePos(btVector3(0, 0, 0));
        mb.setWorldToBaseRot(btQuaternion::getIdentity());
      } else {
        mb.setBasePos(bt(base->position));
        mb.setWorldToBaseRot(bt(base->orientation).inverse());
      }
      for (int k = 0; k < nl; ++k) {
        const TreePlan::Link& l = plan_tree.links[k];
        const Joint& j = scene_.joints[l.joint];
        const Body& c = bodies[l.body];
        // The link's coordinate is body2's rotation relative to body1 about the axis; with the
        // tree's parent being body2, the same coordinate is a rotation about the opposite axis.
        const Vec3 axis = l.body == j.body2 ? j.axis : Vec3(-j.axis);
        const Quat qp = rotOf(l.parent), qc = c.orientation;
        const Vec3 xp = posOf(l.parent);
        mb.setupRevolute(k, c.mass, bt(c.inertia), linkOf(l.parent), bt(qc.conjugate() * qp),
                         bt(qc.conjugate() * axis), bt(qp.conjugate() * (j.anchor - xp)),
                         bt(qc.conjugate() * (c.position - j.anchor)),
                         /*disableParentCollision*/ true);
      }
      mb.finalizeMultiDof();
      mb.setLinearDamping(0.0);  // btMultiBody's defaults are 0.04
      mb.setAngularDamping(0.0);
      mb.setHasSelfCollision(true);  // links collide unless joined (parent-child pairs)
      if (!fixed) {
        mb.setBaseVel(bt(base->velocity));
        mb.setBaseOmega(bt(base->angular_velocity));
      }
      for (int k = 0; k < nl; ++k) {
        const TreePlan::Link& l = plan_tree.links[k];
        const Joint& j = scene_.joints[l.joint];
        const Vec3 axis = l.body == j.body2 ? j.axis : Vec3(-j.axis);
        mb.setJointVel(k, (bodies[l.body].angular_velocity - omegaOf(l.parent)).dot(axis));
      }
      mbworld_->addMultiBody(&mb);

      // Colliders: base (floating) and links with a shape.
      auto addCollider = [&](int link, int body) {
        const Body& b = bodies[body];
        btCollisionShape* shape = shapes_.get(b.shape);
        if (!shape) return;
        auto col = std::make_unique<btMultiBodyLinkCollider>(&mb, link);
        col->setCollisionShape(shape);
        col->setWorldTransform(btTransform(bt(b.orientation), bt(b.position)));
        col->setFriction(mu_body);
        mbworld_->addCollisionObject(col.get(), btBroadphaseProxy::DefaultFilter,
                                     btBroadphaseProxy::AllFilter);
        if (link < 0) {
          mb.setBaseCollider(col.get());
        } else {
          mb.getLink(link).m_collider = col.get();
        }
        colliders_.push_back(std::move(col));
      };
      if (!fixed) addCollider(-1, plan_tree.base);
      for (int k = 0; k < nl; ++k) addCollider(k, plan_tree.links[k].body);
      // Bullet finds a multibody constraint's simulation island through the multibody's colliders
      // (btMultiBodyJointLimitConstraint::getIslandIdA); with none, limits and motors are silently
      // ignored. A shapeless tree with limits or motors gets one empty collider outside any pair.
      bool has_collider = mb.getBaseCollider() != nullptr, has_constraint = false;
      for (int k = 0; k < nl; ++k) {
        has_collider = has_collider || mb.getLink(k).m_collider != nullptr;
        const Joint& j = scene_.joints[plan_tree.links[k].joint];
        has_constraint = has_constraint || j.limits || j.motor;
      }
      if (has_constraint && !has_collider && nl > 0) {
        auto col = std::make_unique<btMultiBodyLinkCollider>(&mb, 0);
        col->setCollisionShape(shapes_.empty());
        col->setWorldTransform(btTransform(bt(bodies[plan_tree.links[0].body].orientation),
                                           bt(bodies[plan_tree.links[0].body].position)));
        mbworld_->addCollisionObject(col.get(), 0, 0);
        mb.getLink(0).m_collider = col.get();
        colliders_.push_back(std::move(col));
      }

      // A link hinged to a static scene body must not collide with it either.
      for (int k = 0; k < nl; ++k) {
        const Joint& j = scene_.joints[plan_tree.links[k].joint];
        for (int other : {j.body1, j.body2}) {
          if (other >= 0 && bodies[other].is_static && mb.getLink(k).m_collider)
            rigid_[other]->setIgnoreCollisionCheck(mb.getLink(k).m_collider, true);
        }
      }

      // Limits and motors.
      for (int k = 0; k < nl; ++k) {
        const Joint& j = scene_.joints[plan_tree.links[k].joint];
        if (j.limits) {
          auto lim = std::make_unique<btMultiBodyJointLimitConstraint>(&mb, k, j.limits->lower,
                                                                       j.limits->upper);
          mbworld_->addMultiBodyConstraint(lim.get());
          mbconstraints_.push_back(std::move(lim));
        }
        if (j.motor) {  // the motor takes an impulse per step
          auto mot = std::make_unique<btMultiBodyJointMotor>(&mb, k, j.motor->target_velocity,
                                                             j.motor->max_force * h_);
          mbworld_->addMultiBodyConstraint(mot.get());
          mbconstraints_.push_back(std::move(mot));
        }
      }
      tree.poses.resize(nl + 1);
      trees_.push_back(std::move(tree));
    }
  }

  /// The world poses of a tree's base and links from its joint state (the recursion of
  /// btMultiBody::forwardKinematics, without writing into the multibody), and their velocities:
  /// btMultiBody::compTreeLinkVelocities gives each link's angular velocity and its frame
  /// origin's velocity in the link's frame, from the base's velocity and the joint rates through
  /// the same cached parent-to-link rotations and offsets that the poses come from; a link's frame
  /// origin is its centre of mass, so turned by the link's orientation they are the world-frame
  /// twist at the centre of mass, at the positions pose() reports (checked on the 10-link chain:
  /// the kinetic energy agrees with the one from the poses' differences over a step to within the
  /// differences' own error, and both show the total energy growing).
  void updatePoses(const Tree& t) const {
    const btMultiBody& mb = *t.mb;
    const int nl = mb.getNumLinks();
    t.world_to_local.resize(nl + 1);
    t.origin.resize(nl + 1);
    t.world_to_local[0] = mb.getWorldToBaseRot();
    t.origin[0] = mb.getBasePos();
    for (int k = 0; k < nl; ++k) {
      const int p = mb.getParent(k);
      t.world_to_local[k + 1] = mb.getParentToLocalRot(k) * t.world_to_local[p + 1];
      t.origin[k + 1] =
          t.origin[p + 1] + quatRotate(t.world_to_local[k + 1].inverse(), mb.getRVector(k));
    }
    for (int k = 0; k <= nl; ++k)
      t.poses[k] = Pose{eig(t.origin[k]), eig(t.world_to_local[k].inverse())};
    t.omega.resize(nl + 1);
    t.vel.resize(nl + 1);
    t.twists.resize(static_cast<std::size_t>(nl + 1));
    mb.compTreeLinkVelocities(&t.omega[0], &t.vel[0]);
    for (int k = 0; k <= nl; ++k) {
      const btQuaternion to_world = t.world_to_local[k].inverse();
      t.twists[static_cast<std::size_t>(k)] =
          Twist{eig(quatRotate(to_world, t.vel[k])), eig(quatRotate(to_world, t.omega[k]))};
    }
    t.posed_at = steps_;
  }

  const Scene& scene_;
  double h_;
  long steps_ = 0;
  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btDbvtBroadphase> broadphase_;
  std::unique_ptr<btConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  btMultiBodyDynamicsWorld* mbworld_ = nullptr;  // world_, when featherstone
  ShapeCache shapes_;
  std::vector<Where> where_;
  std::vector<std::unique_ptr<btRigidBody>> rigid_;  // per scene body; null when in a tree
  std::unique_ptr<btRigidBody> ground_;
  std::unique_ptr<btRigidBody> world_body_;
  std::vector<std::unique_ptr<btTypedConstraint>> constraints_;
  std::vector<Tree> trees_;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders_;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> mbconstraints_;
};

/// Rigid bodies and typed constraints, sequential impulses at `iterations`.
Variant sequentialImpulse(const Scene& scene, int iterations) {
  const bool contacts = hasContacts(scene);
  const bool defaults = iterations == kDefaultIterations;
  std::string settings("btRigidBody + joints, sequential impulse ");
  settings += std::to_string(iterations);
  if (contacts) {
    settings += " it, ERP 0.2, split impulse, 4 pts/pair, sleeping on";
    if (defaults) settings += " (defaults)";
  } else {
    settings += defaults ? " it, ERP 0.2 (defaults), sleeping off" : " it, ERP 0.2, sleeping off";
  }
  Variant v{"Bullet", std::move(settings),
            [iterations](const Scene& s) -> std::unique_ptr<Engine> {
              return std::make_unique<BulletEngine>(s, false, iterations);
            },
            false};
  std::string knob("sequential impulse, btContactSolverInfo::m_numIterations = ");
  knob += std::to_string(iterations);
  v.knob = std::move(knob);
  return v;
}

}  // namespace

std::vector<Variant> bulletVariants(const Scene& scene) {
  std::vector<Variant> v;
  v.push_back(sequentialImpulse(scene, kDefaultIterations));
  if (!scene.joints.empty()) {  // trees of hinges; make() says why not for other joint sets
    v.push_back(Variant{
        "Bullet",
        std::string("btMultiBody, btMultiBodyConstraintSolver 10 it, damping 0 (default 0.04)") +
            (hasContacts(scene) ? ", sleeping on" : ", sleeping off"),
        [](const Scene& s) -> std::unique_ptr<Engine> {
          return std::make_unique<BulletEngine>(s, true);
        },
        false});
  }
  return v;
}

// Bullet's default row is the sequential-impulse solver, swept; btMultiBody (trees of hinges)
// runs none of the Pareto table's scenes.
std::vector<Variant> bulletSweep(const Scene& scene, const std::vector<int>& counts) {
  std::vector<Variant> v;
  for (int iterations : counts) v.push_back(sequentialImpulse(scene, iterations));
  return v;
}

}  // namespace bench
