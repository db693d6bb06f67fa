// warp/seen.h: which quads of one keyframe show surfaces another keyframe
// sees (the opt-in background cull).
#include <gtest/gtest.h>

#include <vector>

#include "warp/seen.h"

namespace hw::warp {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A keyframe of the plane z = 0 seen from `eye` (looking down −z), every
// pixel covered, eye depth exact.
keyframe::Keyframe planeKeyframe(const glm::dvec3& eye, int size) {
  keyframe::Keyframe k;
  k.camera = Camera::lookAt(eye, eye + glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0), 60 * kPi / 180,
                            size, size, 0.1, 100);
  k.eyeZ.resize(size, size);
  k.covered.resize(size, size);
  k.eyeZ.fill(static_cast<float>(eye.z));
  k.covered.fill(1);
  return k;
}

keyframe::QuadMesh halves(int size) {
  keyframe::QuadMesh m;
  m.width = m.height = size;
  keyframe::Quad left, right;
  left.rect = {0, 0, size / 2, size};
  right.rect = {size / 2, 0, size, size};
  m.quads = {left, right};
  return m;
}

TEST(QuadsSeenBy, AKeyframeSeesAllOfItsOwnQuads) {
  const keyframe::Keyframe k = planeKeyframe({0, 0, 5}, 32);
  std::vector<std::uint8_t> seen;
  quadsSeenBy(k, halves(32), k, SeenOptions{}, seen);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0], 1);
  EXPECT_EQ(seen[1], 1);
}

TEST(QuadsSeenBy, AnOccluderInTheSeersViewHidesTheQuadBehindIt) {
  const keyframe::Keyframe own = planeKeyframe({0, 0, 5}, 32);
  keyframe::Keyframe seer = own;
  // Something at depth 2 in front of the right half's middle (a small
  // occluder inside a big quad: found by the grid samples, not the corners).
  for (int y = 12; y < 20; ++y)
    for (int x = 22; x < 28; ++x) seer.eyeZ(x, y) = 2.0f;
  std::vector<std::uint8_t> seen;
  quadsSeenBy(own, halves(32), seer, SeenOptions{}, seen);
  EXPECT_EQ(seen[0], 1);
  EXPECT_EQ(seen[1], 0);
}

TEST(QuadsSeenBy, SurfacesOutsideTheSeersViewOrNotDrawnAreNotSeen) {
  const keyframe::Keyframe own = planeKeyframe({0, 0, 5}, 32);
  // Moved right by half the view's half-width: part of the left half is outside.
  const keyframe::Keyframe moved = planeKeyframe({1.5, 0, 5}, 32);
  std::vector<std::uint8_t> seen;
  quadsSeenBy(own, halves(32), moved, SeenOptions{}, seen);
  EXPECT_EQ(seen[0], 0);
  EXPECT_EQ(seen[1], 1);
  keyframe::Keyframe empty = own;
  empty.covered.fill(0);
  quadsSeenBy(own, halves(32), empty, SeenOptions{}, seen);
  EXPECT_EQ(seen[0], 0);
  EXPECT_EQ(seen[1], 0);
}

TEST(QuadsSeenBy, ADifferentDepthIsAnotherSurface) {
  const keyframe::Keyframe own = planeKeyframe({0, 0, 5}, 32);
  keyframe::Keyframe seer = own;
  seer.eyeZ.fill(5.2f);  // 4 % farther: beyond the 0.5 % tolerance
  std::vector<std::uint8_t> seen;
  quadsSeenBy(own, halves(32), seer, SeenOptions{}, seen);
  EXPECT_EQ(seen[0], 0);
  SeenOptions loose;
  loose.relTolerance = 0.05;
  quadsSeenBy(own, halves(32), seer, loose, seen);
  EXPECT_EQ(seen[0], 1);
}

}  // namespace
}  // namespace hw::warp
