// Camera motions, each checked against geometry worked out here: distances to the pivot,
// angles to the up vector, displacements along the camera's own axes.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "core/render/camera_control.h"
#include "core/base/error.h"

namespace gs {
namespace {

constexpr float kPi = 3.14159265f;

Camera test_camera() {
  Camera c;
  c.eye = {4.0f, -3.0f, 2.0f};
  c.target = {0.5f, 0.25f, 0.75f};
  c.up = {0.0f, 0.0f, 1.0f};
  c.fov = 40.0f;
  return c;
}

void expect_near(const glm::vec3& a, const glm::vec3& b, float tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

float degrees_to_up(const Camera& c) {
  const float cosine = glm::dot(c.forward(), glm::normalize(c.up));
  return std::acos(std::clamp(cosine, -1.0f, 1.0f)) * 180.0f / kPi;
}

TEST(Orbit, KeepsTheDistanceToThePivotAndTheUpVector) {
  const Camera c = test_camera();
  const glm::vec3 pivot{1.0f, 2.0f, 0.5f};
  const float eye_distance = glm::length(c.eye - pivot);
  const float target_distance = glm::length(c.target - pivot);
  for (float yaw : {-2.0f, -0.3f, 0.0f, 0.7f, 3.0f})
    for (float pitch : {-0.4f, 0.0f, 0.25f}) {
      const Camera o = orbit(c, pivot, yaw, pitch);
      EXPECT_NEAR(glm::length(o.eye - pivot), eye_distance, 1e-5f * eye_distance);
      EXPECT_NEAR(glm::length(o.target - pivot), target_distance, 1e-5f * eye_distance);
      // Rigid: the eye-target distance is kept too.
      EXPECT_NEAR(glm::length(o.target - o.eye), glm::length(c.target - c.eye), 1e-5f);
      EXPECT_EQ(o.up, c.up);
      EXPECT_EQ(o.fov, c.fov);
    }
}

TEST(Orbit, YawTurnsAboutUpByTheAngle) {
  // Pivot at the origin, up z: a yaw is a rotation of the eye in the xy plane, height kept.
  Camera c;
  c.eye = {3.0f, 0.0f, 1.0f};
  c.target = {0.0f, 0.0f, 1.0f};
  c.up = {0.0f, 0.0f, 1.0f};
  const Camera o = orbit(c, glm::vec3(0.0f), kPi / 2.0f, 0.0f);
  expect_near(o.eye, {0.0f, 3.0f, 1.0f}, 1e-5f);
  expect_near(o.target, {0.0f, 0.0f, 1.0f}, 1e-5f);
  // Positive yaw swings the view toward the camera's left.
  const Camera small = orbit(c, c.eye, 0.1f, 0.0f);
  EXPECT_LT(glm::dot(small.forward(), c.right()), 0.0f);
}

TEST(Orbit, PitchTiltsAboutRightByTheAngle) {
  // Looking along -x from (3,0,0) at the origin; a pitch of 30 degrees about the pivot at the
  // origin tilts the view toward up: the eye goes down to 3 * (cos 30, 0, -sin 30).
  Camera c;
  c.eye = {3.0f, 0.0f, 0.0f};
  c.target = {0.0f, 0.0f, 0.0f};
  c.up = {0.0f, 0.0f, 1.0f};
  const float a = kPi / 6.0f;
  const Camera o = orbit(c, glm::vec3(0.0f), 0.0f, a);
  expect_near(o.eye, {3.0f * std::cos(a), 0.0f, -3.0f * std::sin(a)}, 1e-5f);
  EXPECT_NEAR(degrees_to_up(o), 60.0f, 1e-3f);
}

TEST(Orbit, PitchStopsAboutOneDegreeShortOfThePoles) {
  const Camera c = test_camera();
  const glm::vec3 pivot = c.target;
  for (float pitch : {10.0f, 3.0f, -3.0f, -10.0f}) {
    const Camera o = orbit(c, pivot, 0.2f, pitch);
    const float angle = degrees_to_up(o);
    EXPECT_GE(angle, 0.99f) << pitch;
    EXPECT_LE(angle, 179.01f) << pitch;
    EXPECT_NEAR(std::min(angle, 180.0f - angle), 1.0f, 1e-2f) << pitch;
    EXPECT_NO_THROW(parse_camera(to_string(o))) << to_string(o);
    // Many small steps in one direction end at the same margin, never beyond.
    Camera walked = c;
    for (int k = 0; k < 200; ++k) walked = orbit(walked, pivot, 0.0f, pitch / 50.0f);
    const float walked_angle = degrees_to_up(walked);
    EXPECT_GE(std::min(walked_angle, 180.0f - walked_angle), 0.99f);
    EXPECT_NO_THROW(parse_camera(to_string(walked))) << to_string(walked);
  }
  // Back from the pole: a pitch the other way is taken in full.
  const Camera top = orbit(c, pivot, 0.0f, 10.0f);
  const Camera back = orbit(top, pivot, 0.0f, -0.5f);
  EXPECT_NEAR(degrees_to_up(back), degrees_to_up(top) + 0.5f * 180.0f / kPi, 1e-2f);
}

TEST(Pan, MovesEyeAndTargetByOneVectorInTheImagePlane) {
  const Camera c = test_camera();
  const float distance = glm::length(c.target - c.eye);
  const float height = 2.0f * distance * std::tan(c.fov * kPi / 360.0f);
  const Camera p = pan(c, 0.25f, -0.1f);
  const glm::vec3 move = p.eye - c.eye;
  expect_near(p.target - c.target, move, 1e-5f);
  EXPECT_NEAR(glm::dot(move, c.forward()), 0.0f, 1e-5f);
  expect_near(move, (0.25f * c.right() - 0.1f * c.true_up()) * height, 1e-5f);
  EXPECT_EQ(p.up, c.up);
}

TEST(Dolly, ShortensTheDistanceByTheFactorAndNeverPassesTheTarget) {
  const Camera c = test_camera();
  const float distance = glm::length(c.target - c.eye);
  const Camera half = dolly(c, 0.5f);
  EXPECT_NEAR(glm::length(half.target - half.eye), 0.5f * distance, 1e-5f);
  expect_near(half.forward(), c.forward(), 1e-6f);
  EXPECT_EQ(half.target, c.target);
  const Camera back = dolly(c, -1.0f);
  EXPECT_NEAR(glm::length(back.target - back.eye), 2.0f * distance, 1e-5f);
  for (float factor : {1.0f, 1.5f, 100.0f}) {
    const Camera d = dolly(c, factor);
    EXPECT_GT(glm::dot(d.target - d.eye, c.target - c.eye), 0.0f) << factor;
    EXPECT_NO_THROW(parse_camera(to_string(d)));
  }
  // Repeated steps approach the target but never reach it.
  Camera near = c;
  for (int k = 0; k < 500; ++k) near = dolly(near, 0.9f);
  EXPECT_NE(near.eye, near.target);
  EXPECT_GT(glm::dot(near.target - near.eye, c.target - c.eye), 0.0f);
  EXPECT_NO_THROW(parse_camera(to_string(near)));
}

TEST(Fly, MovesByExactAmountsAlongTheCamerasAxes) {
  Camera c;
  c.eye = {0.0f, -5.0f, 1.0f};
  c.target = {0.0f, 0.0f, 1.0f};
  c.up = {0.0f, 0.0f, 1.0f};
  // forward +y, right +x, up +z.
  const Camera f = fly(c, {2.0f, 0.0f, 0.0f});
  EXPECT_EQ(f.eye, glm::vec3(0.0f, -3.0f, 1.0f));
  EXPECT_EQ(f.target, glm::vec3(0.0f, 2.0f, 1.0f));
  const Camera r = fly(c, {0.0f, 1.5f, 0.0f});
  EXPECT_EQ(r.eye, glm::vec3(1.5f, -5.0f, 1.0f));
  EXPECT_EQ(r.target, glm::vec3(1.5f, 0.0f, 1.0f));
  const Camera u = fly(c, {0.0f, 0.0f, -0.5f});
  EXPECT_EQ(u.eye, glm::vec3(0.0f, -5.0f, 0.5f));
  EXPECT_EQ(u.target, glm::vec3(0.0f, 0.0f, 0.5f));
  // A general camera: the move is the combination of its unit axes.
  const Camera g = test_camera();
  const glm::vec3 step{0.3f, -0.7f, 1.1f};
  const Camera m = fly(g, step);
  const glm::vec3 expected = 0.3f * g.forward() - 0.7f * g.right() + 1.1f * g.true_up();
  expect_near(m.eye - g.eye, expected, 1e-5f);
  expect_near(m.target - g.target, expected, 1e-5f);
  EXPECT_NEAR(glm::length(m.eye - g.eye), glm::length(step), 1e-5f);
}

}  // namespace
}  // namespace gs
