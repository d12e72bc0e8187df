// The rows the accurate integrator switches (docs/integrators.md, "Limits, motors and friction"):
// a limit met is an event its steps end on, a plastic impact, then an equality while it pushes;
// it opens where its force falls to zero. A velocity motor or joint friction holds its target
// rate while its force is within its bound and slips at the bound past it. Checked against the
// pendulum's closed form before and after an impact, the free fall's, static balance on a limit,
// a motor's spin-up and its saturation under a growing load, and dry friction's closed forms.
#include "support.hpp"

#include <gtest/gtest.h>

#include "jacobi_sn.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>

namespace linx {
namespace {

constexpr double kG = 9.81;

WorldSettings settingsFor(IntegratorType type, double h) {
  WorldSettings s;
  s.timestep = h;
  s.integrator.type = type;
  return s;
}

int eventsOf(const World& w) {
  return w.lastIntegratorReport().events;
}

// A uniform rod (1 kg, 1 m, 2 cm square, no shapes) hinged at its end to the world at the origin
// about y. `hanging`: along -z, else along +x (horizontal); at rest, or turning at w about y.
struct Rod {
  World world;
  BodyId body;
  JointId hinge;
  double mass = 1.0, length = 1.0;
  // About the pivot: the rod's own inertia about y and its mass at half its length.
  double pivotInertia() const { return mass / 12.0 * (length * length + 4e-4) + mass * 0.25; }
  // omega_n^2 = m g d / I_p.
  double naturalRate() const { return std::sqrt(mass * kG * 0.5 * length / pivotInertia()); }
};

Rod makeRod(const WorldSettings& s, bool hanging, double w) {
  Rod r{World(s), {}, {}};
  const double d = 0.5 * r.length;
  BodyDef def = test::boxBody("rod", r.mass,
                              hanging ? Vec3(0.02, 0.02, r.length) : Vec3(r.length, 0.02, 0.02),
                              hanging ? Vec3(0, 0, -d) : Vec3(d, 0, 0));
  def.shapes.clear();
  def.angular_velocity = Vec3(0, w, 0);
  def.linear_velocity = Vec3(0, w, 0).cross(def.position);
  r.body = r.world.createBody(def);
  r.hinge = r.world.createJoint(
      "hinge",
      JointDef{.name = "hinge", .body1 = r.body, .anchor = Vec3::Zero(), .axis = Vec3::UnitY()});
  return r;
}

double angle(const Rod& r) {
  return r.world.jointCoordinates(r.hinge)[0];
}

// A hanging rod swung up from the bottom at the rate that would take it to 1.2 rad meets an upper
// limit at 0.8 rad: free, sin(theta / 2) = k0 sn(omega_n t, k0), k0 = sin(1.2 / 2), until it
// arrives at t*; the plastic impact stops it there, and gravity pulls it straight off the limit,
// so that from t* it swings as a pendulum released from rest at 0.8 rad: sin(theta / 2) =
// kL sn(K(kL) - omega_n (t - t*), kL). An error in t* shows in the whole later motion (omega dt).
// One period later it comes back to the limit at zero speed (a graze), and must pass it by.
TEST(LimitEvents, PendulumStopsOnALimitAndSwingsBackFromIt) {
  const double theta0 = 1.2, bound = 0.8;
  Rod probe = makeRod(settingsFor(IntegratorType::Accurate, 0.01), true, 0.0);
  const double wn = probe.naturalRate();
  const double k0 = std::sin(0.5 * theta0), kl = std::sin(0.5 * bound);
  // Energy: 1/2 I_p w0^2 = m g d (1 - cos theta0).
  const double w0 = wn * std::sqrt(2.0 * (1.0 - std::cos(theta0)));
  Rod r = makeRod(settingsFor(IntegratorType::Accurate, 0.01), true, w0);
  r.world.joint(r.hinge).setLimits(JointLimits{.lower = -3.0, .upper = bound});
  const auto free = [&](double t) { return 2.0 * std::asin(k0 * bench::jacobiSn(wn * t, k0)); };
  // t*: where the free motion reaches the bound, by bisection on its rising quarter period.
  double lo = 0.0, hi = test::ellipticK(k0) / wn;
  for (int i = 0; i < 200; ++i) (free(0.5 * (lo + hi)) < bound ? lo : hi) = 0.5 * (lo + hi);
  const double arrival = 0.5 * (lo + hi);
  const double kK = test::ellipticK(kl);
  const auto after = [&](double t) {
    return 2.0 * std::asin(kl * bench::jacobiSn(kK - wn * (t - arrival), kl));
  };
  const double d = 0.5 * r.length;
  const double energy_after = -r.mass * kG * d * std::cos(bound);  // at rest on the bound

  // (lowest: of the frames, as the closed form's at the same times)
  double before_error = 0.0, after_error = 0.0, highest = -1.0, lowest = 1.0, expected_lowest = 1.0;
  double drift = 0.0;
  int events = 0, impact_events = 0;
  const double duration = test::runLength(3.0, 2.2);
  while (r.world.time() < duration - 1e-9) {
    r.world.step();
    const double t = r.world.time(), a = angle(r);
    events += eventsOf(r.world);
    highest = std::max(highest, a);
    if (t < arrival) {
      before_error = std::max(before_error, std::abs(a - free(t)));
    } else {
      if (impact_events == 0) impact_events = events;
      after_error = std::max(after_error, std::abs(a - after(t)));
      lowest = std::min(lowest, a);
      expected_lowest = std::min(expected_lowest, after(t));
      drift = std::max(drift, std::abs(r.world.energy().total() - energy_after));
    }
  }
  std::printf(
      "t* %.9f s; before %.3g rad, after %.3g rad off the closed forms; highest %.12f, "
      "lowest %.12f; energy after %.3g J; events %d (%d at the impact)\n",
      arrival, before_error, after_error, highest, lowest, drift, events, impact_events);
  EXPECT_LT(before_error, 1e-8);
  EXPECT_LT(after_error, 1e-7);  // the impact's time within about 1e-8 s
  EXPECT_LT(highest, bound + 1e-9);
  EXPECT_NEAR(lowest, expected_lowest, 1e-7);
  EXPECT_NEAR(expected_lowest, -bound, 1e-3);  // the frames sample the swing's far end
  EXPECT_LT(drift, 1e-8);
  EXPECT_EQ(impact_events, 2);  // met (held), then left at once: gravity pulls it off
  EXPECT_LT(r.world.jointError(r.hinge), 1e-11);
}

// A rod released horizontal falls onto an upper limit at 1 rad, where gravity still presses it:
// up to the impact its energy stays, and its angle follows the energy integral
// t(theta) = int_0^theta dphi / sqrt(2 c sin phi), c = m g d / I_p; after it, it rests on the
// limit, which takes the weight's torque about the pivot (static balance), and the accurate
// integrator keeps moving it.
TEST(LimitEvents, RodFallsOntoALimitAndRestsOnIt) {
  Rod r = makeRod(settingsFor(IntegratorType::Accurate, 0.01), false, 0.0);
  const double bound = 1.0;
  r.world.joint(r.hinge).setLimits(JointLimits{.lower = -1.0, .upper = bound});
  const double c = r.naturalRate() * r.naturalRate();
  // The time to fall to theta, by Simpson's rule in u = sqrt(phi) (dphi = 2 u du, regular at 0).
  const auto timeTo = [&](double theta) {
    const int n = 4000;
    const double top = std::sqrt(theta), du = top / n;
    const auto f = [&](double u) {
      return u == 0.0 ? 2.0 / std::sqrt(2.0 * c) : 2.0 * u / std::sqrt(2.0 * c * std::sin(u * u));
    };
    double sum = f(0.0) + f(top);
    for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(i * du);
    return sum * du / 3.0;
  };
  const double arrival = timeTo(bound);
  const double e0 = r.world.energy().total();
  double path_error = 0.0, drift = 0.0;
  int events = 0;
  while (r.world.time() < 1.0 - 1e-9) {
    r.world.step();
    events += eventsOf(r.world);
    const double t = r.world.time(), a = angle(r);
    ASSERT_LT(a, bound + 1e-9) << "t " << t;
    if (t < arrival) {
      path_error = std::max(path_error, std::abs(timeTo(a) - t));
      drift = std::max(drift, std::abs(r.world.energy().total() - e0));
    }
  }
  const Body& b = r.world.body(r.body);
  const Vec3 weight = r.mass * r.world.settings().gravity;
  const JointReaction reaction = r.world.jointReaction(r.hinge);
  const Vec3 torque = -b.position().cross(weight);  // about the pivot, against the weight's
  std::printf(
      "t* %.6f s; path %.3g s off the energy integral, energy %.3g J before; at rest "
      "%.3g rad off, rate %.3g rad/s; torque %.12f of %.12f N m; events %d\n",
      arrival, path_error, drift, bound - angle(r), b.angularVelocity().norm(), reaction.torque.y(),
      torque.y(), events);
  EXPECT_LT(path_error, 1e-8);
  EXPECT_LT(drift, 1e-9);
  EXPECT_NEAR(angle(r), bound, 1e-11);
  EXPECT_LT(b.angularVelocity().norm(), 1e-11);
  EXPECT_NEAR(reaction.torque.y(), torque.y(), 1e-9);
  EXPECT_NEAR((reaction.force + weight).norm(), 0.0, 1e-9);
  EXPECT_EQ(events, 1);  // met and held; never left
  EXPECT_EQ(r.world.lastIntegratorReport().bodies, 1);
}

// A block on a vertical slider falls 0.1 m onto its lower limit. The accurate integrator follows
// the free fall z = -g t^2 / 2 (its fifth order is exact on it), ends a step on the bound at
// t* = sqrt(0.2 / g), and the block rests there. Under "auto" the frame of the impact takes the
// step (its one accurate step would end past the bound), and the block rests on the limit after
// it, on the accurate integrator again once its wait is over.
TEST(LimitEvents, BlockFallsOntoASliderLimit) {
  for (const IntegratorType type : {IntegratorType::Accurate, IntegratorType::Auto}) {
    World w(settingsFor(type, 0.01));
    BodyDef def = test::boxBody("block", 2.0, Vec3(0.1, 0.1, 0.1), Vec3::Zero());
    def.shapes.clear();
    const BodyId block = w.createBody(def);
    const JointId slider =
        w.createJoint("slider", JointDef{.name = "slider", .body1 = block, .axis = Vec3::UnitZ()});
    const double drop = 0.1;
    w.joint(slider).setLimits(JointLimits{.lower = -drop, .upper = 1.0});
    const double arrival = std::sqrt(2.0 * drop / kG);
    double fall_error = 0.0, deepest = 0.0;
    int events = 0, accurate_frames = 0, frames = 0;
    while (w.time() < 0.6 - 1e-9) {
      w.step();
      ++frames;
      events += eventsOf(w);
      if (w.lastIntegratorReport().bodies == 1) ++accurate_frames;
      const double t = w.time(), z = w.jointCoordinates(slider)[0];
      deepest = std::min(deepest, z);
      if (t < arrival) fall_error = std::max(fall_error, std::abs(z + 0.5 * kG * t * t));
    }
    const double z = w.jointCoordinates(slider)[0];
    std::printf(
        "%s: fall %.3g m off; deepest %.15f; at rest %.3g m off; %d of %d frames "
        "accurate, %d events\n",
        std::string(integratorTypeName(type)).c_str(), fall_error, deepest, z + drop,
        accurate_frames, frames, events);
    EXPECT_LT(fall_error, 1e-12);
    EXPECT_NEAR(z, -drop, 1e-10);
    EXPECT_GT(deepest, -drop - 1e-9);
    EXPECT_LT(w.body(block).linearVelocity().norm(), 1e-9);
    EXPECT_EQ(w.lastIntegratorReport().bodies, 1);  // resting on the limit, accurately
    if (type == IntegratorType::Accurate) {
      EXPECT_EQ(accurate_frames, frames);
      EXPECT_EQ(events, 1);
    } else {
      EXPECT_LT(accurate_frames, frames);  // the impact's frame, and a wait, took the step
      EXPECT_GT(accurate_frames, frames / 2);
    }
  }
}

// States from elsewhere: a rod that starts 0.2 rad past its stop, turning back towards its range
// at 0.5 rad/s while gravity presses it further, is put on the stop by the first frame (the
// projection with the limit held, which takes its rate along the limit too) and rests there; one
// that rested on the stop under the step (which holds it to its solver's tolerance)
// and is then handed to the accurate integrator stays on it, its energy unchanged.
TEST(LimitEvents, StatesPastOrOnALimitFromElsewhereRestOnIt) {
  {
    Rod r = makeRod(settingsFor(IntegratorType::Accurate, 0.01), false, -0.5);
    r.world.joint(r.hinge).setLimits(JointLimits{.lower = -1.0, .upper = -0.2});
    double worst = 0.0;
    for (int i = 0; i < 50; ++i) {
      r.world.step();
      worst = std::max(worst, std::abs(angle(r) + 0.2));
    }
    std::printf("started past: %.3g rad off the bound at most, %.3g rad/s\n", worst,
                r.world.body(r.body).angularVelocity().norm());
    EXPECT_LT(worst, 1e-11);
    EXPECT_LT(r.world.body(r.body).angularVelocity().norm(), 1e-11);
  }
  {
    Rod r = makeRod(settingsFor(IntegratorType::Step, 0.01), false, 0.0);
    r.world.joint(r.hinge).setLimits(JointLimits{.lower = -1.0, .upper = 1.0});
    for (int i = 0; i < 100; ++i) r.world.step();
    const double from_step = angle(r) - 1.0, e0 = r.world.energy().total();
    r.world.settings().integrator.type = IntegratorType::Accurate;
    double worst = 0.0;
    int accurate_frames = 0;
    for (int i = 0; i < 50; ++i) {
      r.world.step();
      worst = std::max(worst, std::abs(angle(r) - 1.0));
      accurate_frames += r.world.lastIntegratorReport().bodies;
    }
    std::printf("from the step (%.3g rad off): %.3g rad off the bound at most; energy %.3g J\n",
                from_step, worst, r.world.energy().total() - e0);
    EXPECT_EQ(accurate_frames, 50);
    EXPECT_LT(worst, std::max(1e-11, 2.0 * std::abs(from_step)));
    EXPECT_NEAR(r.world.energy().total(), e0, 1e-9);
  }
}

// A saved state carries the held limits: the rod of RodFallsOntoALimitAndRestsOnIt saved while it
// rests on its limit moves on from the restored state exactly as from the state it was saved
// from (bit for bit), holding the limit without meeting it again (no event). A held set that is
// not sorted is a damaged state and refused.
TEST(LimitEvents, ASavedStateCarriesTheHeldLimits) {
  Rod r = makeRod(settingsFor(IntegratorType::Accurate, 0.01), false, 0.0);
  r.world.joint(r.hinge).setLimits(JointLimits{.lower = -1.0, .upper = 1.0});
  for (int i = 0; i < 50; ++i) r.world.step();  // on the limit since 0.375 s
  ASSERT_NEAR(angle(r), 1.0, 1e-11);
  const WorldState saved = r.world.saveState();
  std::vector<Vec3> path;
  for (int i = 0; i < 20; ++i) {
    r.world.step();
    path.push_back(r.world.body(r.body).position());
  }
  r.world.restoreState(saved);
  int events = 0;
  for (int i = 0; i < 20; ++i) {
    r.world.step();
    events += eventsOf(r.world);
    EXPECT_EQ(r.world.body(r.body).position(), path[static_cast<std::size_t>(i)]) << "frame " << i;
  }
  EXPECT_EQ(events, 0);
  // Two limits held (the same key twice) would be no set the integrator writes.
  // (The state of one held limit: find its key, a count of 1 followed by it, and write it twice.)
  WorldState bad = saved;
  bool damaged = false;
  for (std::size_t at = 0; at + 40 <= bad.bytes.size() && !damaged; ++at) {
    std::uint64_t count = 0, bodies = 0;
    std::memcpy(&count, bad.bytes.data() + at, 8);
    std::memcpy(&bodies, bad.bytes.data() + at + 16, 8);
    if (count != 1 || bodies != 1) continue;
    std::uint64_t key = 0;
    std::memcpy(&key, bad.bytes.data() + at + 8, 8);
    if (key >> 8 != 1 || (key & 0xff) != 17) continue;  // the first joint's upper limit
    const std::uint64_t two = 2;
    std::memcpy(bad.bytes.data() + at, &two, 8);
    bad.bytes.insert(bad.bytes.begin() + static_cast<std::ptrdiff_t>(at + 16),
                     bad.bytes.begin() + static_cast<std::ptrdiff_t>(at + 8),
                     bad.bytes.begin() + static_cast<std::ptrdiff_t>(at + 16));
    damaged = true;
  }
  ASSERT_TRUE(damaged) << "no held limit found in the state";
  EXPECT_THROW(r.world.restoreState(bad), std::invalid_argument);
}

// A cube (3 kg, 0.4 m, I = m s^2 / 6 about its axis; no gravity) on a hinge, its velocity motor
// aiming at 3 rad/s with at most 0.5 N m: it spins up at the bound, theta = T t^2 / (2 I), until
// its rate meets the target at t = 3 I / T = 0.48 s (an event inside a frame), then turns at
// 3 rad/s exactly, the motor giving no torque.
TEST(MotorEvents, WheelSpinsUpAtItsBoundThenLocks) {
  World w(settingsFor(IntegratorType::Accurate, 0.01));
  w.settings().gravity.setZero();
  const double m = 3.0, size = 0.4, inertia = m * size * size / 6.0, target = 3.0, torque = 0.5;
  const BodyId wheel =
      w.createBody(test::boxBody("wheel", m, Vec3(size, size, size), Vec3::Zero()));
  const JointId axle = w.createJoint(
      "hinge",
      JointDef{.name = "axle", .body1 = wheel, .anchor = Vec3::Zero(), .axis = Vec3::UnitZ()});
  w.joint(axle).setMotor(JointMotor{.target_velocity = target, .max_force = torque});
  const double lock = target * inertia / torque;
  const auto exact = [&](double t) {
    return t < lock ? 0.5 * torque / inertia * t * t
                    : 0.5 * torque / inertia * lock * lock + target * (t - lock);
  };
  double worst = 0.0, after = 0.0;
  int events = 0;
  while (w.time() < 1.0 - 1e-9) {
    w.step();
    events += eventsOf(w);
    worst = std::max(worst, std::abs(w.jointCoordinates(axle)[0] - exact(w.time())));
    if (w.time() > lock) after = std::max(after, w.jointReaction(axle).torque.norm());
  }
  std::printf(
      "spin-up: %.3g rad off the closed form, rate %.15f, torque after the lock %.3g N m, "
      "events %d\n",
      worst, w.body(wheel).angularVelocity().z(), after, events);
  EXPECT_LT(worst, 1e-10);
  EXPECT_NEAR(w.body(wheel).angularVelocity().z(), target, 1e-12);
  EXPECT_LT(after, 1e-9);
  EXPECT_EQ(events, 1);  // locked at 0.48 s
}

// A hanging rod turned up at 0.5 rad/s by a velocity motor of at most half its weight's largest
// torque: locked, theta = w t and the motor gives m g d sin(theta), until that reaches the bound
// at theta* = 30 degrees (t* = pi / 3 s); there it slips, I_p theta'' = F - m g d sin(theta),
// which fine fourth-order Runge-Kutta follows from (theta*, w), for 1.4 s (the rod swings back
// through theta* before its rate meets the target again).
TEST(MotorEvents, ArmLiftedAtConstantRateSlipsWhereGravityOutweighsTheMotor) {
  const double rate = 0.5;
  Rod r = makeRod(settingsFor(IntegratorType::Accurate, 0.01), true, rate);
  const double d = 0.5 * r.length, weight = r.mass * kG * d, bound = 0.5 * weight;
  const double ip = r.pivotInertia();
  r.world.joint(r.hinge).setMotor(JointMotor{.target_velocity = rate, .max_force = bound});
  const double slip_angle = std::asin(bound / weight), slip_time = slip_angle / rate;
  double theta = slip_angle, theta_rate = rate, t_ref = slip_time;  // the reference after t*
  const auto advanceTo = [&](double t) {
    const auto acc = [&](double q) { return (bound - weight * std::sin(q)) / ip; };
    while (t_ref < t - 1e-12) {
      const double h = std::min(1e-5, t - t_ref);
      const double k1q = theta_rate, k1v = acc(theta);
      const double k2q = theta_rate + 0.5 * h * k1v, k2v = acc(theta + 0.5 * h * k1q);
      const double k3q = theta_rate + 0.5 * h * k2v, k3v = acc(theta + 0.5 * h * k2q);
      const double k4q = theta_rate + h * k3v, k4v = acc(theta + h * k3q);
      theta += h / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
      theta_rate += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
      t_ref += h;
    }
  };
  double locked_error = 0.0, torque_error = 0.0, slipping_error = 0.0, highest = 0.0;
  // (torque_error: frames wholly before t*)
  int events = 0;
  while (r.world.time() < slip_time + 1.4 - 1e-9) {
    r.world.step();
    events += eventsOf(r.world);
    const double t = r.world.time(), a = angle(r);
    highest = std::max(highest, a);
    if (t < slip_time) {
      locked_error = std::max(locked_error, std::abs(a - rate * t));
      // The motor's torque about the axis on the rod holds its weight's, m g d sin(theta), on
      // the mean over the frame (what a joint reports): m g d (cos theta0 - cos theta1) / (w h).
      const double h = r.world.settings().timestep, before = rate * (t - h);
      const double mean = weight * (std::cos(before) - std::cos(rate * t)) / (rate * h);
      torque_error =
          std::max(torque_error, std::abs(r.world.jointReaction(r.hinge).torque.y() - mean));
    } else {
      advanceTo(t);
      slipping_error = std::max(slipping_error, std::abs(a - theta));
    }
  }
  std::printf(
      "lifted: locked %.3g rad off w t, motor torque %.3g N m off m g d sin(theta); "
      "slipping from t* = %.6f s %.3g rad off the reference; highest %.6f rad; events "
      "%d\n",
      locked_error, torque_error, slip_time, slipping_error, highest, events);
  EXPECT_LT(locked_error, 1e-10);
  EXPECT_LT(torque_error, 1e-8);
  EXPECT_LT(slipping_error, 1e-7);        // the slip's start within about 1e-7 s
  EXPECT_GT(highest, slip_angle + 0.05);  // it swung on past theta*
  EXPECT_EQ(events, 2);  // locked at the start (its rate on the target), slipping at t*
}

// Joint friction (a velocity row aiming at zero) under the accurate integrator, against the
// closed forms test_joint_friction checks with the step: a 2 kg block on a rail tilted along
// (1, 0, 2) with 5 N of friction slides at a = -g cos(a) + f / m (s = a t^2 / 2, the motion's
// own); with 30 N it is held and the joint carries its weight; a cube spun at 3 rad/s on an axle
// with 0.2 N m of friction stops at t = I w0 / T after turning I w0^2 / (2 T), and stays.
TEST(FrictionEvents, DryFrictionSlidesHoldsAndStopsAtTheClosedForms) {
  const auto rail = [&](const Vec3& axis, double friction) {
    World w(settingsFor(IntegratorType::Accurate, 0.01));
    const BodyId block =
        w.createBody(test::boxBody("block", 2.0, Vec3(0.1, 0.1, 0.1), Vec3(0, 0, 1)));
    const JointId slider =
        w.createJoint("slider", JointDef{.name = "rail",
                                         .body1 = block,
                                         .axis = axis,
                                         .coordinates = {CoordinateDef{.friction = friction}}});
    return std::pair{std::move(w), slider};
  };
  {
    const Vec3 axis = Vec3(1, 0, 2).normalized();
    auto [w, slider] = rail(axis, 5.0);
    const double a = -kG * axis.z() + 5.0 / 2.0;
    double worst = 0.0;
    while (w.time() < 1.0 - 1e-9) {
      w.step();
      worst =
          std::max(worst, std::abs(w.jointCoordinates(slider)[0] - 0.5 * a * w.time() * w.time()));
    }
    std::printf("sliding: %.3g m off a t^2 / 2\n", worst);
    EXPECT_LT(worst, 1e-12);
  }
  {
    auto [w, slider] = rail(Vec3::UnitZ(), 30.0);
    for (int n = 0; n < 100; ++n) w.step();
    std::printf("held at %.3g m, reaction %.12f N\n", w.jointCoordinates(slider)[0],
                w.jointReaction(slider).force.z());
    EXPECT_LT(std::abs(w.jointCoordinates(slider)[0]), 1e-12);
    EXPECT_NEAR(w.jointReaction(slider).force.z(), 2.0 * kG, 1e-9);
  }
  {
    World w(settingsFor(IntegratorType::Accurate, 0.01));
    w.settings().gravity.setZero();
    const double m = 3.0, size = 0.4, inertia = m * size * size / 6.0, w0 = 3.0, torque = 0.2;
    BodyDef def = test::boxBody("wheel", m, Vec3(size, size, size), Vec3::Zero());
    def.angular_velocity = Vec3(0, 0, w0);
    const BodyId wheel = w.createBody(def);
    const JointId axle =
        w.createJoint("hinge", JointDef{.name = "axle",
                                        .body1 = wheel,
                                        .anchor = Vec3::Zero(),
                                        .axis = Vec3::UnitZ(),
                                        .coordinates = {CoordinateDef{.friction = torque}}});
    const double stop = inertia * w0 / torque, turned = inertia * w0 * w0 / (2.0 * torque);
    double worst = 0.0;
    int events = 0;
    while (w.time() < stop + 0.5 - 1e-9) {
      w.step();
      events += eventsOf(w);
      const double t = std::min(w.time(), stop);
      worst = std::max(
          worst, std::abs(w.jointCoordinates(axle)[0] - (w0 * t - 0.5 * torque / inertia * t * t)));
    }
    std::printf(
        "spun down: %.3g rad off w0 t - T t^2 / (2 I), stopped after %.12f rad (%.12f), "
        "rate %.3g, events %d\n",
        worst, w.jointCoordinates(axle)[0], turned, w.body(wheel).angularVelocity().norm(), events);
    EXPECT_LT(worst, 1e-10);
    EXPECT_NEAR(w.jointCoordinates(axle)[0], turned, 1e-10);
    EXPECT_LT(w.body(wheel).angularVelocity().norm(), 1e-12);
    EXPECT_EQ(events, 1);  // locked at the stop
  }
}

}  // namespace
}  // namespace linx
