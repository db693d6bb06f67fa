// The viewer's fly controls over a long session ("precision where
// it matters"): 10,000 updates of mouse look and movement keep the camera
// basis orthonormal, yaw and pitch bounded, and a closed or retraced motion
// returns to where it started (app/fly_pose.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "app/fly_pose.h"

namespace hw::app {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kUpdates = 10000;

Camera base() {
  Camera c;
  c.width = 640;
  c.height = 480;
  c.nearPlane = 0.1;
  c.farPlane = 500;
  return c;
}

// Orthonormal, right-handed (U × V = −W: GL eye space looks down −Z), U horizontal.
void expectBasis(const Camera& c, int update) {
  const double tol = 1e-12;
  EXPECT_NEAR(glm::length(c.right), 1.0, tol) << "update " << update;
  EXPECT_NEAR(glm::length(c.up), 1.0, tol) << "update " << update;
  EXPECT_NEAR(glm::length(c.forward), 1.0, tol) << "update " << update;
  EXPECT_NEAR(glm::dot(c.right, c.up), 0.0, tol) << "update " << update;
  EXPECT_NEAR(glm::dot(c.right, c.forward), 0.0, tol) << "update " << update;
  EXPECT_NEAR(glm::dot(c.up, c.forward), 0.0, tol) << "update " << update;
  EXPECT_NEAR(glm::length(glm::cross(c.right, c.up) + c.forward), 0.0, tol) << "update " << update;
  EXPECT_NEAR(c.right.y, 0.0, tol) << "update " << update;
  EXPECT_GT(c.up.y, 0.0) << "update " << update;
}

double angleDiff(double a, double b) { return std::remainder(a - b, 2 * kPi); }

TEST(FlyPose, FullCircleOfTenThousandStepsCloses) {
  // Turn 2π/N and step forward every update: the eye walks a regular
  // N-gon and must come back to its start, the view to its start direction.
  FlyPose p;
  p.eye = {3.0, 1.7, -2.0};
  p.yaw = 0.3;
  p.pitch = 0.0;
  const FlyPose start = p;
  const double step = 0.01;  // scene units: a 100-unit circumference
  for (int i = 0; i < kUpdates; ++i) {
    flyUpdate(p, 2 * kPi / kUpdates, 0.0, {0, 0, 1}, step);
    ASSERT_LE(std::abs(p.yaw), kPi) << "update " << i;
    if (i % 97 == 0) expectBasis(flyCamera(p, base()), i);
  }
  // Path length 100: rounding of 10,000 steps is ~1e-13 per unit.
  EXPECT_LT(glm::length(p.eye - start.eye), 1e-10) << p.eye.x << " " << p.eye.y << " " << p.eye.z;
  EXPECT_LT(std::abs(angleDiff(p.yaw, start.yaw)), 1e-11);
  EXPECT_EQ(p.pitch, 0.0);
  const Camera a = flyCamera(start, base()), b = flyCamera(p, base());
  EXPECT_LT(glm::length(a.forward - b.forward), 1e-11);
}

TEST(FlyPose, RetracedMotionReturnsToStart) {
  // 10,000 updates of mixed turning and movement, then the exact inverse
  // inputs in reverse order. Pitch deltas are kept away from the clamp so
  // every update is invertible.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> turn(-0.02, 0.02), speed(0.0, 0.05);
  std::uniform_int_distribution<int> key(-1, 1);
  struct Input {
    double dYaw, dPitch;
    glm::dvec3 move;
    double step;
  };
  std::vector<Input> inputs;
  FlyPose p;
  p.eye = {-40.0, 2.0, 125.0};
  p.yaw = -2.5;
  const FlyPose start = p;
  double travelled = 0;
  for (int i = 0; i < kUpdates / 2; ++i) {
    Input in{turn(rng), 0.004 * std::sin(i * 0.013), {key(rng), key(rng), key(rng)}, speed(rng)};
    const glm::dvec3 before = p.eye;
    flyUpdate(p, in.dYaw, in.dPitch, in.move, in.step);
    ASSERT_LT(std::abs(p.pitch), kMaxFlyPitch - 0.1) << "update " << i << ": test would clamp";
    travelled += glm::length(p.eye - before);
    inputs.push_back(in);
  }
  ASSERT_GT(glm::length(p.eye - start.eye), 1.0);  // it did go somewhere
  for (int i = static_cast<int>(inputs.size()) - 1; i >= 0; --i) {
    const Input& in = inputs[static_cast<std::size_t>(i)];
    flyUpdate(p, 0.0, 0.0, -in.move, in.step);
    flyUpdate(p, -in.dYaw, -in.dPitch, {0, 0, 0}, 0.0);
  }
  EXPECT_LT(glm::length(p.eye - start.eye), 1e-12 * (travelled + glm::length(start.eye)) * 100)
      << "travelled " << travelled;
  EXPECT_LT(std::abs(angleDiff(p.yaw, start.yaw)), 1e-12);
  EXPECT_LT(std::abs(p.pitch - start.pitch), 1e-12);
}

TEST(FlyPose, LongRandomSessionStaysBounded) {
  // Wild input: yaw deltas biased to one side (≈1,500 rad in total, so an
  // unwrapped yaw would grow without bound), pitch swings that hit both
  // clamps, all movement keys.
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> dyaw(-0.2, 0.5), dpitch(-0.3, 0.3), speed(0.0, 2.0);
  std::uniform_int_distribution<int> key(-1, 1);
  FlyPose p;
  p.eye = {1e3, 50.0, -1e3};
  double yawSum = 0, maxStep = 0, travelled = 0;
  int clampedUp = 0, clampedDown = 0;
  for (int i = 0; i < kUpdates; ++i) {
    const double dy = dyaw(rng), dp = dpitch(rng), s = speed(rng);
    const glm::dvec3 move(key(rng), key(rng), key(rng));
    const glm::dvec3 before = p.eye;
    yawSum += dy;
    flyUpdate(p, dy, dp, move, s);
    ASSERT_TRUE(std::isfinite(p.yaw) && std::isfinite(p.pitch)) << "update " << i;
    ASSERT_TRUE(std::isfinite(p.eye.x) && std::isfinite(p.eye.y) && std::isfinite(p.eye.z));
    ASSERT_GT(p.yaw, -kPi) << "update " << i;
    ASSERT_LE(p.yaw, kPi) << "update " << i;
    ASSERT_LE(std::abs(p.pitch), kMaxFlyPitch) << "update " << i;
    clampedUp += p.pitch == kMaxFlyPitch;
    clampedDown += p.pitch == -kMaxFlyPitch;
    // A step moves at most √5 · s: right is orthogonal to forward and +Y,
    // and |forward + Y| = √(2 + 2 sin pitch) ≤ 2.
    const double d = glm::length(p.eye - before);
    ASSERT_LE(d, std::sqrt(5.0) * s * (1 + 1e-12)) << "update " << i;
    maxStep = std::max(maxStep, d);
    travelled += d;
    expectBasis(flyCamera(p, base()), i);
    if (HasFailure()) return;
  }
  EXPECT_GT(yawSum, 1000.0);
  EXPECT_GT(clampedUp, 0);
  EXPECT_GT(clampedDown, 0);
  EXPECT_GT(maxStep, 1.0);
  EXPECT_LE(glm::length(p.eye - glm::dvec3(1e3, 50.0, -1e3)), travelled);
}

TEST(FlyPose, CameraRoundTripAndAgreesWithLookAt) {
  for (double yaw : {-3.0, -1.0, 0.0, 0.5, 2.0, kPi}) {
    for (double pitch : {-1.5, -0.3, 0.0, 0.7, 1.5}) {
      FlyPose p;
      p.eye = {2.0, -1.0, 5.0};
      p.yaw = yaw;
      p.pitch = pitch;
      const Camera c = flyCamera(p, base());
      const FlyPose q = flyPoseFromCamera(c);
      EXPECT_LT(glm::length(q.eye - p.eye), 1e-15);
      EXPECT_LT(std::abs(angleDiff(q.yaw, yaw)), 1e-12) << yaw << " " << pitch;
      EXPECT_NEAR(q.pitch, pitch, 1e-12);
      // The viewer built its camera with Camera::lookAt before; same basis.
      const Camera l = Camera::lookAt(p.eye, p.eye + flyForward(yaw, pitch), {0, 1, 0},
                                      c.fovYRadians, c.width, c.height, c.nearPlane, c.farPlane);
      EXPECT_LT(glm::length(l.right - c.right), 1e-14);
      EXPECT_LT(glm::length(l.up - c.up), 1e-14);
      EXPECT_LT(glm::length(l.forward - c.forward), 1e-14);
    }
  }
}

TEST(FlyPose, BasisDoesNotDependOnEyeMagnitude) {
  // lookAt(eye, eye + forward) loses |eye|·ε of the direction; flyCamera
  // does not (eye at 1e9 units, far outside any scene, still exact).
  FlyPose p;
  p.yaw = 0.4;
  p.pitch = 0.2;
  const Camera nearOrigin = flyCamera(p, base());
  p.eye = {1e9, -1e9, 1e9};
  const Camera far = flyCamera(p, base());
  EXPECT_EQ(nearOrigin.forward, far.forward);
  EXPECT_EQ(nearOrigin.right, far.right);
  EXPECT_EQ(nearOrigin.up, far.up);
}

}  // namespace
}  // namespace hw::app
