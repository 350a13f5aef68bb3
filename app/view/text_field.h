// An ImGui text input's buffer, which the program also fills (a camera, a path, a budget).
#pragma once
#include <imgui.h>

#include <array>
#include <cstdio>
#include <string>

namespace gs::app {

template <size_t kSize>
class TextField {
 public:
  void set(const std::string& text) { std::snprintf(text_.data(), kSize, "%s", text.c_str()); }
  const char* c_str() const { return text_.data(); }
  // The input widget; true when the text was edited.
  bool input(const char* label) { return ImGui::InputText(label, text_.data(), kSize); }

 private:
  std::array<char, kSize> text_{};
};

}  // namespace gs::app
