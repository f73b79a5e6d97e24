// SPDX-License-Identifier: GPL-2.0
// A JSON string literal, for the tools' --json output (x4ctl, x4trace).
#pragma once

#include <cstdio>
#include <string>

namespace x4tools {

inline std::string json_string(const std::string &s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20) {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\u%04x", c);
      out += esc;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

}  // namespace x4tools
