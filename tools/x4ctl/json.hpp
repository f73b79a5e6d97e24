// SPDX-License-Identifier: GPL-2.0
// x4ctl: the one style of every --json output. Each top-level object (one
// per line) starts with "schema": json_schema; booleans are JSON booleans,
// numbers are numbers, names are strings. Errors under --json are such an
// object too, {"schema":1,"error":{"message":...,"errno":N or null}}, on
// standard output, so that a reader of stdout always gets JSON; the exit
// status is the same as without --json.
#ifndef X4CTL_JSON_HPP
#define X4CTL_JSON_HPP

#include <cmath>
#include <cstdio>
#include <string>
#include <type_traits>

#include "../json_string.hpp"

namespace x4ctl {

/// The version of x4ctl's JSON: a later x4ctl raises it when it changes or
/// removes a field (adding fields keeps it).
constexpr int json_schema = 1;

/// A JSON object built field by field.
class json_object {
 public:
  json_object &add(const std::string &key, bool v) { return raw(key, v ? "true" : "false"); }
  template <typename T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>, int> = 0>
  json_object &add(const std::string &key, T v) {
    return raw(key, std::to_string(v));
  }
  /// A real number (without this overload a double would become a bool).
  json_object &add(const std::string &key, double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", std::isfinite(v) ? v : 0.0);
    return raw(key, buf);
  }
  json_object &add(const std::string &key, const std::string &v) { return raw(key, x4tools::json_string(v)); }
  json_object &add(const std::string &key, const char *v) { return add(key, std::string(v)); }
  json_object &add(const std::string &key, const json_object &v) { return raw(key, v.str()); }
  /// A value that is JSON already (an array, null).
  json_object &raw(const std::string &key, const std::string &json) {
    body_ += (body_.empty() ? "" : ",") + x4tools::json_string(key) + ":" + json;
    return *this;
  }
  std::string str() const { return "{" + body_ + "}"; }

 private:
  std::string body_;
};

/// A top-level object: {"schema":1} to add the rest to.
inline json_object json_document() { return json_object().add("schema", json_schema); }

/// A JSON array of the JSON texts in [first, last), each made by to_json.
template <typename It, typename F>
std::string json_array(It first, It last, F to_json) {
  std::string s;
  for (; first != last; ++first) s += (s.empty() ? "" : ",") + to_json(*first);
  return "[" + s + "]";
}

/// {"message":...,"errno":N}; err 0: no errno known (null).
inline json_object json_error_object(const std::string &message, int err) {
  return json_object().add("message", message).raw("errno", err ? std::to_string(err) : "null");
}

/// The top-level error object.
inline std::string json_error(const std::string &message, int err) {
  return json_document().add("error", json_error_object(message, err)).str();
}

}  // namespace x4ctl

#endif  // X4CTL_JSON_HPP
