// Camera motions of the viewer, as pure functions of a camera: orbit around a
// pivot, pan, dolly, fly; the viewer maps mouse and keys to them.
#pragma once
#include <glm/vec3.hpp>

#include "core/scene/camera.h"

namespace gs {

// Rotates eye and target about `pivot`: yaw about the camera's up axis, pitch about its
// right axis (radians). The distance from eye to pivot is kept; pitch stops short of the
// poles so the up vector stays valid.
Camera orbit(const Camera& camera, const glm::vec3& pivot, float yaw, float pitch);
// Moves eye and target together in the image plane by (dx, dy) fractions of the view's
// height at the target's distance (so a drag across the viewport moves the scene with it).
Camera pan(const Camera& camera, float dx, float dy);
// Moves the eye toward the target by `factor` of their distance (factor > 0: closer; the
// eye never reaches the target).
Camera dolly(const Camera& camera, float factor);
// Moves eye and target along the view direction (forward), right and up by world units.
Camera fly(const Camera& camera, const glm::vec3& forward_right_up);

}  // namespace gs
