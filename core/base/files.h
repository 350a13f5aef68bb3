// Whole files in and out, and JSON records as gridscope writes them. Every failure is an
// InputError naming the file: "PATH: problem".
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace gs {

std::vector<char> read_file(const std::string& path);
// Throws when the file cannot be written completely.
void write_file(const std::string& path, std::span<const char> bytes);
// Indented JSON with a final newline.
void write_json(const std::string& path, const nlohmann::json& json);

// The value, or null when there is none (a figure a structure cannot measure).
inline nlohmann::json value_or_null(const std::optional<uint64_t>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

}  // namespace gs
