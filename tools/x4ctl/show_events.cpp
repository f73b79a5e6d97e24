// SPDX-License-Identifier: GPL-2.0
// x4ctl: the port's events as `x4ctl watch` shows them, as text and JSON (show.hpp).
#include <cstdio>
#include <string>

#include "json.hpp"
#include "show.hpp"

namespace x4ctl {

namespace {

// The names of an event's type and how, as JSON and text use them; "" if
// this x4ctl does not know them (a newer module).
const char *event_type_name(x4step::event_type t) {
  static const char *const names[] = {"move_started", "move_ended", "brake",
                                      "switch",       "controller", "port_gone"};
  const unsigned i = static_cast<unsigned>(t) - 1;
  return i < 6 ? names[i] : "";
}

const char *event_how_name(const x4step::event &e) {
  static const char *const kinds[] = {"loaded", "endless", "goto", "home"};
  static const char *const ends[] = {"completed", "braked",    "stopped",    "limit",
                                     "homed",     "ref_found", "ref_travel", "ref_passed"};
  static const char *const sources[] = {"request", "key", "close", "emergency"};
  static const char *const switches[] = {"limit_pos", "limit_neg", "ref"};
  static const char *const changes[] = {"opened", "closed", "released"};
  const unsigned h = e.how - 1;
  switch (e.type) {
    case x4step::event_type::move_started:
      return h < 4 ? kinds[h] : "";
    case x4step::event_type::move_ended:
      return h < 8 ? ends[h] : "";
    case x4step::event_type::brake:
      return h < 4 ? sources[h] : "";
    case x4step::event_type::switch_hit:
      return h < 3 ? switches[h] : "";
    case x4step::event_type::controller:
      return h < 3 ? changes[h] : "";
    default:
      return "";
  }
}

std::string seconds(std::chrono::steady_clock::time_point t) {
  const long long ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
  char s[40];
  std::snprintf(s, sizeof s, "%lld.%06lld", ns / 1000000000, ns % 1000000000 / 1000);
  return s;
}

std::string axes_list(x4step::axis_set axes, const char *sep) {
  std::string s;
  for (x4step::axis a : axes) s += (s.empty() ? "" : sep) + std::to_string(a.number());
  return s;
}

}  // namespace

std::string event_text(const x4step::event &e) {
  using x4step::event_type;
  const unsigned how = e.how;
  std::string what, detail;
  switch (e.type) {
    case event_type::move_started: {
      static const char *const kinds[] = {"X4Step move", "endless move", "goto", "reference run"};
      what = "move started";
      detail = how >= 1 && how <= 4 ? kinds[how - 1] : "";
      break;
    }
    case event_type::move_ended: {
      static const char *const ends[] = {"completed",
                                         "braked",
                                         "stopped",
                                         "at a limit switch",
                                         "homed",
                                         "REF found",
                                         "reference travel exceeded",
                                         "braked off the reference switch"};
      what = "move ended";
      detail = how >= 1 && how <= 8 ? ends[how - 1] : "";
      break;
    }
    case event_type::brake:
      what = "brake";
      detail = how == 1   ? "requested by the controller"
               : how == 2 ? "by " + key_name(static_cast<int>(e.value))
               : how == 3 ? "the controller closed while moving"
               : how == 4 ? std::string("emergency ") + (e.value ? "stop" : "brake") +
                                " (x4ctl stop/brake, any reader)"
                          : "";
      break;
    case event_type::switch_hit: {
      static const char *const kinds[] = {"E+", "E-", "REF"};
      what = "switch";
      if (how >= 1 && how <= 3)
        detail = std::string(kinds[how - 1]) + " on " + input_name(static_cast<int>(e.value));
      if (e.ambiguous) detail += ", ambiguous";
      break;
    }
    case event_type::controller: {
      static const char *const changes[] = {"opened", "closed", "released the port"};
      what = "controller";
      detail = how >= 1 && how <= 3 ? changes[how - 1] : "";
      break;
    }
    case event_type::port_gone:
      what = "port gone";
      break;
    default:
      what = "event type " + std::to_string(static_cast<unsigned>(e.type));
      break;
  }
  if (detail.empty() && how && e.type != event_type::port_gone) detail = "how " + std::to_string(how);
  std::string s = "#" + std::to_string(e.seq) + " " + seconds(e.time) + " " + what;
  if (!e.axes.empty()) s += ": axes " + axes_list(e.axes, " ");
  if (!detail.empty()) s += (e.axes.empty() ? ": " : ", ") + detail;
  step_counts pos{};
  for (int i = 0; i < x4step::axes; i++) pos[i] = e.position[i];
  return s + "; at " + steps_text(pos);
}

std::string event_json(const x4step::event &e) {
  const long long ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(e.time.time_since_epoch()).count();
  const char *type = event_type_name(e.type);
  const char *how = event_how_name(e);
  json_object o = json_document().add("seq", e.seq).add("time_ns", ns);
  if (*type)
    o.add("type", type);
  else
    o.add("type", static_cast<unsigned>(e.type));
  o.raw("axes", "[" + axes_list(e.axes, ",") + "]");
  if (*how)
    o.add("how", how);
  else
    o.add("how", e.how);
  return o.add("value", e.value)
      .add("ambiguous", e.ambiguous)
      .raw("position",
           json_array(e.position.begin(), e.position.end(), [](long v) { return std::to_string(v); }))
      .str();
}

std::string missed_text(std::uint64_t n) {
  return "missed " + std::to_string(n) + (n == 1 ? " event" : " events") + " (the module keeps the last 256)";
}

std::string missed_json(std::uint64_t n) { return json_document().add("missed", n).str(); }

}  // namespace x4ctl
