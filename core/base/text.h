// Numbers as people read them in notes, tables and reports.
#pragma once
#include <cmath>
#include <cstdio>
#include <string>

namespace gs {

// A count rounded to a whole number, with thousands separators: 59672 -> "59,672".
inline std::string count_text(double count) {
  char digits[64];
  std::snprintf(digits, sizeof digits, "%.0f", std::fabs(count));
  std::string out = count <= -0.5 ? "-" : "";
  const std::string whole = digits;
  for (size_t i = 0; i < whole.size(); ++i) {
    if (i > 0 && (whole.size() - i) % 3 == 0) out += ',';
    out += whole[i];
  }
  return out;
}

}  // namespace gs
