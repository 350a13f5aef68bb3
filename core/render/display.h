// The display transform of rendered colours: gamma 2.2, then 8 bits. A single sample's bytes
// come from a table of the transform's steps instead of three powf calls per pixel (185 M
// instructions of a one-thread 1274x794 render's 3.23 G; the table takes 84 M), with the
// bytes powf gives.
#pragma once
#include <array>
#include <cstdint>
#include <glm/vec3.hpp>

namespace gs {

// Display-space colour of a linear one: min(linear, 1) ^ (1 / 2.2) per channel.
glm::vec3 display_colour(const glm::vec3& linear);

// A display-space value's byte: clamped to [0, 1], scaled to 255 and rounded half up.
uint8_t display_byte(float display);
std::array<uint8_t, 3> display_bytes(const glm::vec3& display);

// display_byte of display_colour, channel by channel: the same bytes, by the table.
std::array<uint8_t, 3> linear_bytes(const glm::vec3& linear);

// One channel's byte from a linear value, as linear_bytes gives it (for the tests).
uint8_t linear_byte(float linear);

// The smallest linear value in [0, 1] whose byte is at least k, for k in 1..255; entry 0 is 0.
const std::array<float, 256>& linear_byte_steps();

}  // namespace gs
