// SPDX-License-Identifier: LGPL-2.1-or-later
// The G-code interpreter (gcode.hpp): a line is read into a block (words,
// comments), checked against the modal-group rules, and executed in the
// NIST RS274/NGC order of execution. A line's canonical commands are
// collected first and given to the sink only once the whole line is
// accepted, so a refused line moves nothing.
//
// Internally every length is in millimetres and every position in machine
// coordinates (program + G5x + G92 + tool length offset); the program's
// words are scaled on reading, the sink's values on output.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <istream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "gcode.hpp"

namespace x4step::gcode {

error::error(std::string file, int line, int column, const std::string &message)
    : std::runtime_error(file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + message),
      file_(std::move(file)),
      line_(line),
      column_(column),
      message_(message) {}

namespace {

constexpr double mm_per_inch = 25.4;
// LinuxCNC's arc tolerances, in program units: a radius below `radius` is
// zero (and an R arc may miss its end point by that much); start and end
// radii may differ by up to spiral_abs, or by up to 100 spiral_abs when
// they differ by at most spiral_rel of the radius (a spiral that a CAM
// system's rounding made).
// Bounds that keep numbers inside an int, and an arc of P turns sane.
constexpr int tool_max = 99999;
constexpr int turns_max = 10000;

struct arc_tolerances {
  double radius, spiral_abs;
};
constexpr arc_tolerances inch_tol{0.00005, 2 * 0.001 * 1.4142135623730951};
constexpr arc_tolerances mm_tol{0.00005 * 25.4, 2 * 0.01 * 1.4142135623730951};
constexpr double spiral_rel = 0.001;

// Modal groups of G codes (NIST 3.4; LinuxCNC's group 4 for G90.1/G91.1).
enum group : int {
  g_nonmodal = 0,
  g_motion = 1,
  g_plane = 2,
  g_distance = 3,
  g_arc_distance = 4,
  g_feed_mode = 5,
  g_units = 6,
  g_cutter = 7,
  g_tool_length = 8,
  g_retract = 10,
  g_coord = 12,
  g_path = 13,
  n_groups = 14
};

// A G code's group; -1: a known RS274/NGC code outside the subset; -2: unknown.
int g_group(int code10) {
  switch (code10) {
    case 40:
    case 100:
    case 280:
    case 281:
    case 300:
    case 301:
    case 530:
    case 920:
    case 921:
      return g_nonmodal;
    case 0:
    case 10:
    case 20:
    case 30:
    case 382:
    case 383:
    case 384:
    case 385:
    case 730:
    case 800:
    case 810:
    case 820:
    case 830:
    case 850:
    case 890:
      return g_motion;
    case 980:
    case 990:
      return g_retract;
    case 170:
    case 180:
    case 190:
      return g_plane;
    case 900:
    case 910:
      return g_distance;
    case 901:
    case 911:
      return g_arc_distance;
    case 930:
    case 940:
      return g_feed_mode;
    case 200:
    case 210:
      return g_units;
    case 400:
      return g_cutter;
    case 430:
    case 431:
    case 490:
      return g_tool_length;
    case 540:
    case 550:
    case 560:
    case 570:
    case 580:
    case 590:
    case 591:
    case 592:
    case 593:
      return g_coord;
    case 610:
    case 611:
    case 640:
      return g_path;
    case 50:
    case 51:
    case 52:
    case 53:
    case 55:
    case 56:
    case 70:
    case 80:
    case 330:
    case 331:
    case 410:
    case 411:
    case 420:
    case 421:
    case 432:
    case 520:
    case 710:
    case 711:
    case 712:
    case 720:
    case 721:
    case 722:
    case 740:
    case 760:
    case 922:
    case 923:
    case 950:
    case 960:
    case 970:
    case 171:
    case 181:
    case 191:
      return -1;
    default:
      if (code10 >= 810 && code10 <= 890 && code10 % 10 == 0) return -1;
      return -2;
  }
}

// M groups (NIST): 4 stopping, 6 tool change, 7 spindle, 8 coolant.
enum mgroup : int { m_stop = 0, m_tool = 1, m_spindle = 2, m_coolant = 3, n_mgroups = 4 };

int m_group(int code) {
  switch (code) {
    case 0:
    case 1:
    case 2:
    case 30:
      return m_stop;
    case 6:
      return m_tool;
    case 3:
    case 4:
    case 5:
      return m_spindle;
    case 7:
    case 8:
    case 9:
      return m_coolant;
    default:
      return -1;
  }
}

std::string g_name(int code10) {
  char b[16];
  if (code10 % 10)
    std::snprintf(b, sizeof b, "G%d.%d", code10 / 10, code10 % 10);
  else
    std::snprintf(b, sizeof b, "G%d", code10 / 10);
  return b;
}

constexpr double pow10_table[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                  1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// One line's words. Letters index 0..25; col 0: absent.
struct block {
  std::array<double, 26> val;
  std::array<int, 26> col;
  int g[n_groups];  // code * 10, or -1
  int g_col[n_groups];
  int m[n_mgroups];
  int m_col[n_mgroups];
  bool mist_and_flood;  // M7 and M8 together
  int n_m;
  int first_col;  // column of the first word
  bool has_msg;
  bool msg_debug;  // (DEBUG,...) rather than (MSG,...)
  std::string msg;

  bool has(char c) const { return col[c - 'A'] != 0; }
  double v(char c) const { return val[c - 'A']; }
  int at(char c) const { return col[c - 'A']; }
};

// What to do about a code outside the subset, where there is a way.
std::string unsupported_g(int code10) {
  std::string what = g_name(code10) + " is not supported by this interpreter";
  if (code10 == 740 || code10 == 760 || (code10 >= 840 && code10 <= 880))
    return what +
           ": expand canned cycles in your post processor (of the cycles, G73 G81 G82 G83 G85 G89 are)";
  if (code10 >= 410 && code10 <= 421)
    return what + ": let the CAM system compensate the tool radius (compensation \"in computer\")";
  return what;
}

// A character outside G-code: the whole UTF-8 sequence it starts, not half of it.
std::string unexpected(std::string_view s, size_t i) {
  size_t e = i + 1;
  if (static_cast<unsigned char>(s[i]) >= 0xc0)
    while (e < s.size() && (static_cast<unsigned char>(s[e]) & 0xc0) == 0x80 && e - i < 4) ++e;
  if (static_cast<unsigned char>(s[i]) >= 0x80 && e - i == 1) {
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02x", static_cast<unsigned char>(s[i]));
    return std::string("unexpected byte ") + hex + " (not ASCII nor UTF-8)";
  }
  return "unexpected character '" + std::string(s.substr(i, e - i)) + "'";
}

// A canonical command held until its line is accepted.
struct event {
  enum kind {
    traverse,
    feed,
    probe_ev,
    arc_feed,
    dwell,
    units_ev,
    plane_ev,
    path_ev,
    spindle_ev,
    coolant_ev,
    select_tool_ev,
    change_tool_ev,
    tlo_ev,
    pause_ev,
    message_ev,
    warning_ev,
    end_ev
  } k;
  straight s;
  gcode::arc a;
  double d[3];
  int i;
  pose from;  // probe_ev: where the move starts (output units)
  int col;    // probe_ev: the column its errors name
};

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
inline char upper(char c) { return (c >= 'a' && c <= 'z') ? char(c - 'a' + 'A') : c; }

}  // namespace

// What a line changes: copied before each line and put back if the line
// is refused, so that a refused line changes nothing (execute_line() goes
// on after it: MDI, a streaming bridge).
struct modal_state {
  units prog_units = units::mm;
  double k = 1;  // mm per program unit
  plane pl = plane::xy;
  bool incremental = false;
  bool arc_absolute = false;  // G90.1
  feed_mode fmode = feed_mode::units_per_minute;
  int motion = 800;  // LinuxCNC starts in G80: axis words alone are refused
  int cs = 0;        // G54 + cs
  path_mode pmode = path_mode::blend;
  double feed = 0;  // as programmed (program units / min, or 1/min)
  double speed = 0;
  spindle_dir sdir = spindle_dir::off;
  bool mist = false, flood = false;
  int tool_selected = 0, tool_loaded = 0;
  bool ended = false;
  // Canned cycles (program units, as LinuxCNC keeps them): G98 (false) or
  // G99; the level the first cycle of a series started from; the last R,
  // Z, P and Q (a repeated cycle may leave them out).
  bool retract_r = true;
  bool il_set = false;
  double il = 0;
  double cycle_r = 0, cycle_z = 0, cycle_p = 0, cycle_q = 0;

  // Positions and offsets, mm (degrees for A B C), machine coordinates.
  pose pos{};
  std::array<pose, 9> g5x{};
  pose g92{};
  pose tlo{};
  pose g28{}, g30{};
};

struct interpreter::impl : modal_state {
  sink *out;
  options opt;
  std::map<int, tool> tools;
  bool have_tool_table = false;
  std::vector<error> warnings;  // this line's, given on once it is accepted

  // The file being run and the line being read, for errors.
  std::string file;
  int line_no = 0;

  double out_scale;  // mm per machine unit
  std::vector<event> events;
  block b;

  impl(sink *s, options o) : out(s), opt(o) {
    prog_units = o.initial_units;
    k = prog_units == units::inch ? mm_per_inch : 1.0;
    out_scale = o.machine_units == units::inch ? mm_per_inch : 1.0;
    for (int a = 0; a < n_axes; ++a) pos[size_t(a)] = o.start[size_t(a)] * (a < 3 ? out_scale : 1.0);
    const coordinate_state &c = o.coordinates;
    for (size_t i = 0; i < g5x.size(); ++i) g5x[i] = to_mm(c.g5x[i]);
    cs = c.system >= 0 && c.system < int(g5x.size()) ? c.system : 0;
    g28 = to_mm(c.g28);
    g30 = to_mm(c.g30);
    g92 = to_mm(c.g92);
    events.reserve(16);
  }

  [[noreturn]] void fail(int col, const std::string &what) const {
    throw error(file, line_no, col < 1 ? 1 : col, what);
  }

  // ---- reading -------------------------------------------------------

  // A number after a letter: [+-] digits [. digits], blanks allowed
  // between its characters as LinuxCNC allows them.
  double read_number(std::string_view s, size_t &i, char letter, int letter_col) {
    size_t n = s.size();
    while (i < n && is_space(s[i])) ++i;
    bool neg = false;
    if (i < n && (s[i] == '+' || s[i] == '-')) {
      neg = s[i] == '-';
      ++i;
      while (i < n && is_space(s[i])) ++i;
    }
    if (i < n && s[i] == '#') fail(int(i) + 1, "numbered parameters (#) are not supported");
    if (i < n && s[i] == '[') fail(int(i) + 1, "expressions ([ ]) are not supported");
    std::uint64_t mant = 0;
    int digits = 0, decimals = 0;
    bool dot = false, slow = false;
    for (; i < n; ++i) {
      char c = s[i];
      if (c >= '0' && c <= '9') {
        if (digits < 19) {
          if (mant || c != '0') {
            mant = mant * 10 + std::uint64_t(c - '0');
            ++digits;
            if (dot) ++decimals;
          }
        } else {
          slow = true;
        }
      } else if (c == '.') {
        if (dot) break;
        dot = true;
      } else if (is_space(c)) {
        // LinuxCNC drops blanks before reading: "X1 0" is X10.
        size_t j = i;
        while (j < n && is_space(s[j])) ++j;
        if (j < n && ((s[j] >= '0' && s[j] <= '9') || (s[j] == '.' && !dot)))
          i = j - 1;
        else
          break;
      } else {
        break;
      }
      if (c == '0' && !mant && dot) ++decimals;  // zeros between the point and the first digit
    }
    // Was there a digit at all?
    bool any = false;
    for (size_t j = size_t(letter_col); j < i; ++j)
      if (s[j] >= '0' && s[j] <= '9') {
        any = true;
        break;
      }
    if (!any) {
      std::string w(1, letter);
      fail(letter_col, "bad number after " + w + " (a value must follow the letter)");
    }
    double v;
    if (!slow && mant < (std::uint64_t(1) << 53) && decimals <= 22) {
      v = double(mant) / pow10_table[decimals];
    } else {
      std::string t;
      for (size_t j = size_t(letter_col); j < i; ++j)
        if (!is_space(s[j]) && s[j] != '+' && s[j] != '-') t += s[j];
      v = std::strtod(t.c_str(), nullptr);
    }
    return neg ? -v : v;
  }

  // Reads a line into b. Returns false for a line with nothing to do.
  bool parse(std::string_view s) {
    b.col.fill(0);
    for (int g = 0; g < n_groups; ++g) b.g[g] = -1;
    for (int m = 0; m < n_mgroups; ++m) b.m[m] = -1;
    b.mist_and_flood = false;
    b.n_m = 0;
    b.first_col = 0;
    b.has_msg = false;
    b.msg_debug = false;
    size_t i = 0, n = s.size();
    while (i < n && is_space(s[i])) ++i;
    if (i < n && s[i] == '/') {
      if (opt.block_delete) return false;
      ++i;
    }
    bool any_word = false;
    while (i < n) {
      char c = s[i];
      if (is_space(c)) {
        ++i;
        continue;
      }
      int col = int(i) + 1;
      if (c == ';') break;
      if (c == '(') {
        size_t j = i + 1;
        while (j < n && s[j] != ')') {
          if (s[j] == '(') fail(int(j) + 1, "nested comment: '(' inside a comment");
          ++j;
        }
        if (j >= n) fail(col, "comment not closed: ')' missing");
        comment(s.substr(i + 1, j - i - 1), col);
        i = j + 1;
        continue;
      }
      char L = upper(c);
      if (L < 'A' || L > 'Z') {
        if (c == '#') fail(col, "numbered parameters (#) are not supported");
        if (c == '[') fail(col, "expressions ([ ]) are not supported");
        if (c == '%') fail(col, "'%' must stand alone on its line");
        fail(col, unexpected(s, i));
      }
      switch (L) {
        case 'O':
          fail(col,
               "O-word subroutines and control flow are not supported: have the post processor write plain "
               "moves");
        case 'E':
        case 'U':
        case 'V':
        case 'W':
          fail(col, std::string(1, L) + " words are not supported (axes are X Y Z A B C)");
        default:
          break;
      }
      ++i;
      double v = read_number(s, i, L, col);
      if (!b.first_col) b.first_col = col;
      if (L == 'N') {
        if (any_word) fail(col, "N word (line number) must begin the line");
        if (v < 0) fail(col, "negative line number");
        any_word = true;
        continue;
      }
      any_word = true;
      if ((L == 'G' || L == 'M') && !(std::fabs(v) < 10000)) fail(col, std::string("unknown ") + L + " code");
      if (L == 'G') {
        int code10 = int(std::lround(v * 10));
        if (std::fabs(v * 10 - code10) > 1e-6 || v < 0) fail(col, "unknown G code");
        int g = g_group(code10);
        if (g == -2) fail(col, "unknown G code " + g_name(code10));
        if (g == -1) fail(col, unsupported_g(code10));
        if (b.g[g] >= 0)
          fail(col, g_name(code10) + " and " + g_name(b.g[g]) + " are in the same modal group (group " +
                        std::to_string(g) + ")");
        b.g[g] = code10;
        b.g_col[g] = col;
        continue;
      }
      if (L == 'M') {
        int code = int(std::lround(v));
        if (std::fabs(v - code) > 1e-9 || v < 0) fail(col, "unknown M code");
        int g = m_group(code);
        if (g < 0) fail(col, "M" + std::to_string(code) + " is not supported by this interpreter");
        if (++b.n_m > 4) fail(col, "more than four M codes on one line");
        if (b.m[g] >= 0) {
          bool both = g == m_coolant && ((b.m[g] == 7 && code == 8) || (b.m[g] == 8 && code == 7));
          if (!both)
            fail(col, "M" + std::to_string(code) + " and M" + std::to_string(b.m[g]) +
                          " are in the same modal group");
          b.mist_and_flood = true;
          continue;
        }
        b.m[g] = code;
        b.m_col[g] = col;
        continue;
      }
      int idx = L - 'A';
      if (b.col[idx]) fail(col, std::string("multiple ") + L + " words on one line");
      b.col[idx] = col;
      b.val[idx] = v;
    }
    return any_word || b.has_msg;
  }

  void comment(std::string_view c, int col) {
    size_t i = 0;
    while (i < c.size() && is_space(c[i])) ++i;
    auto word = [&](const char *w) {
      size_t n = std::strlen(w);
      if (c.size() - i < n) return false;
      for (size_t j = 0; j < n; ++j)
        if (upper(c[i + j]) != w[j]) return false;
      return true;
    };
    bool debug = word("DEBUG");
    if (!debug && !word("MSG")) return;
    i += debug ? 5 : 3;
    while (i < c.size() && is_space(c[i])) ++i;
    if (i >= c.size() || c[i] != ',') return;
    if (b.has_msg) fail(col, "more than one (MSG,...) or (DEBUG,...) on one line");
    b.has_msg = true;
    b.msg_debug = debug;
    b.msg.assign(c.substr(i + 1));
  }

  // ---- checks (NIST 3.4, LinuxCNC's check_g_codes / check_other_codes) --

  // Whether a word is used by a code in the block or by the modal motion.
  void check_words(int eff_motion) {
    int g0 = b.g[g_nonmodal];
    bool axis = false;
    int axis_col = 0;
    for (char c : {'X', 'Y', 'Z', 'A', 'B', 'C'})
      if (b.has(c)) {
        axis = true;
        if (!axis_col || b.at(c) < axis_col) axis_col = b.at(c);
      }
    bool g0_axes = g0 == 100 || g0 == 280 || g0 == 300 || g0 == 920;
    bool motion_in_block = b.g[g_motion] >= 0;
    if (g0_axes && motion_in_block && b.g[g_motion] != 800 && axis)
      fail(b.g_col[g_motion],
           g_name(b.g[g_motion]) + " and " + g_name(g0) + " both use axis values: one of them per line");
    if (axis && !g0_axes && b.g[g_tool_length] != 431) {
      if (eff_motion == 800) {
        if (motion_in_block)
          fail(axis_col, "axis values with G80: G80 takes none");
        else
          fail(axis_col, "axis values without a G code that uses them (no motion mode is active: G80)");
      }
    }
    if (b.g[g_tool_length] == 431 && (motion_in_block || g0_axes) && axis)
      fail(b.g_col[g_tool_length], "G43.1 and a motion both use axis values: one of them per line");
    if (is_probe(b.g[g_motion]) && !axis)
      fail(b.g_col[g_motion], g_name(b.g[g_motion]) + " needs an axis word (where the probe move ends)");
    if (g0 == 920 && !axis) fail(b.g_col[g_nonmodal], "G92 needs at least one axis word");
    if (g0 == 100 && !axis) fail(b.g_col[g_nonmodal], "G10 needs at least one axis word");
    if (g0 == 530) {
      if (eff_motion != 0 && eff_motion != 10) fail(b.g_col[g_nonmodal], "G53 needs G0 or G1");
      if (incremental_after()) fail(b.g_col[g_nonmodal], "G53 with G91: G53 takes absolute values only");
    }
    bool runs = (axis || motion_in_block) && !g0_axes;  // the motion mode moves on this line
    bool arc = (eff_motion == 20 || eff_motion == 30) && runs;
    bool cycle = is_cycle(eff_motion) && runs;
    bool dwell_cycle = cycle && (eff_motion == 820 || eff_motion == 890);
    bool peck_cycle = cycle && (eff_motion == 730 || eff_motion == 830);
    for (char c : {'I', 'J', 'K'})
      if (b.has(c) && !arc) fail(b.at(c), std::string(1, c) + " word with no G2 or G3 to use it");
    if (b.has('R') && !arc && !cycle) fail(b.at('R'), "R word with no G2, G3 or canned cycle to use it");
    if (b.has('L') && g0 != 100 && !cycle) fail(b.at('L'), "L word with no G10 or canned cycle to use it");
    if (b.has('P') && !(g0 == 40 || g0 == 100 || arc || dwell_cycle || b.g[g_path] == 640))
      fail(b.at('P'), "P word with no G4, G10, G2/G3, G82/G89 or G64 to use it");
    if (b.has('Q') && b.g[g_path] != 640 && !peck_cycle)
      fail(b.at('Q'), "Q word with no G64, G73 or G83 to use it");
    if (cycle)
      for (char c : {'A', 'B', 'C'})
        if (b.has(c))
          fail(b.at(c), std::string(1, c) + " word in a canned cycle: rotary axes stay put in cycles");
    if (b.has('H') && b.g[g_tool_length] != 430) fail(b.at('H'), "H word with no G43 to use it");
    if (b.has('D')) fail(b.at('D'), "D word: cutter radius compensation (G41/G42) is not supported");
    if (g0 == 40 && !b.has('P')) fail(b.g_col[g_nonmodal], "G4 needs P (the dwell time, seconds)");
    if (g0 == 40 && b.v('P') < 0) fail(b.at('P'), "negative dwell time");
    if (b.has('F') && b.v('F') < 0) fail(b.at('F'), "negative feed rate");
    if (b.has('S') && b.v('S') < 0) fail(b.at('S'), "negative spindle speed");
    if (b.has('T')) {
      double t = b.v('T');
      if (t < 0 || t != std::floor(t) || t > tool_max)
        fail(b.at('T'), "T must be a tool number (a whole number 0.." + std::to_string(tool_max) + ")");
    }
    if (g0 == 100) {
      if (!b.has('L')) fail(b.g_col[g_nonmodal], "G10 needs L2 or L20");
      double l = b.v('L');
      if (l != 2 && l != 20) fail(b.at('L'), "only G10 L2 and G10 L20 are supported");
      if (!b.has('P')) fail(b.g_col[g_nonmodal], "G10 L2/L20 needs P (the coordinate system 0..9)");
      double p = b.v('P');
      if (p < 0 || p > 9 || p != std::floor(p)) fail(b.at('P'), "G10 P must be a coordinate system 0..9");
      if (b.has('R')) fail(b.at('R'), "G10 R (a rotation of the coordinate system) is not supported");
    }
  }

  static bool is_cycle(int m) { return m == 730 || (m >= 810 && m <= 890); }
  static bool is_probe(int m) { return m >= 382 && m <= 385; }

  bool incremental_after() const { return b.g[g_distance] >= 0 ? b.g[g_distance] == 910 : incremental; }

  // ---- execution ------------------------------------------------------

  double scale(int a) const { return a < 3 ? k : 1.0; }
  const arc_tolerances &tol() const { return prog_units == units::inch ? inch_tol : mm_tol; }

  // The offsets from program to machine coordinates.
  double offset(int a) const { return g5x[size_t(cs)][size_t(a)] + g92[size_t(a)] + tlo[size_t(a)]; }

  // The end point of a move: axis words in program coordinates (or in
  // machine coordinates with G53), the rest stays.
  pose target(bool g53) const {
    pose t = pos;
    static const char letters[] = "XYZABC";
    for (int a = 0; a < n_axes; ++a) {
      char c = letters[a];
      if (!b.has(c)) continue;
      double v = b.v(c) * scale(a);
      if (g53)
        t[size_t(a)] = v;
      else if (incremental)
        t[size_t(a)] = pos[size_t(a)] + v;
      else
        t[size_t(a)] = v + offset(a);
    }
    return t;
  }

  pose to_mm(const pose &p) const {
    pose o = p;
    for (int a = 0; a < 3; ++a) o[size_t(a)] = p[size_t(a)] * out_scale;
    return o;
  }
  pose to_out(const pose &p) const {
    pose o = p;
    for (int a = 0; a < 3; ++a) o[size_t(a)] = p[size_t(a)] / out_scale;
    return o;
  }

  void emit_straight(event::kind kind, const pose &end) {
    event e{};
    e.k = kind;
    e.s.end = to_out(end);
    e.s.mode = fmode;
    e.s.feed = kind == event::feed ? out_feed() : 0.0;
    events.push_back(e);
    pos = end;
  }

  double out_feed() const { return fmode == feed_mode::inverse_time ? feed : feed * k / out_scale; }

  void simple(event::kind kind, double d0 = 0, double d1 = 0, double d2 = 0, int i = 0) {
    event e{};
    e.k = kind;
    e.d[0] = d0;
    e.d[1] = d1;
    e.d[2] = d2;
    e.i = i;
    events.push_back(e);
  }

  void execute() {
    int eff_motion = b.g[g_motion] >= 0 ? b.g[g_motion] : motion;
    check_words(eff_motion);
    int g0 = b.g[g_nonmodal];

    // 1. message
    if (b.has_msg) simple(event::message_ev);
    // 2. feed rate mode
    if (b.g[g_feed_mode] >= 0) {
      feed_mode m = b.g[g_feed_mode] == 930 ? feed_mode::inverse_time : feed_mode::units_per_minute;
      if (m != fmode) feed = 0;  // LinuxCNC: a new mode wants a new F
      fmode = m;
    }
    // 3. F, 4. S
    if (b.has('F')) feed = b.v('F');
    if (b.has('S')) {
      speed = b.v('S');
      if (sdir != spindle_dir::off) simple(event::spindle_ev, speed, 0, 0, int(sdir));
    }
    // 5. T, 6. M6
    if (b.has('T')) {
      tool_selected = int(b.v('T'));
      simple(event::select_tool_ev, 0, 0, 0, tool_selected);
    }
    if (b.m[m_tool] == 6) {
      tool_loaded = tool_selected;
      simple(event::change_tool_ev, 0, 0, 0, tool_loaded);
    }
    // 7. spindle, 8. coolant
    if (b.m[m_spindle] >= 0) {
      sdir = b.m[m_spindle] == 3   ? spindle_dir::cw
             : b.m[m_spindle] == 4 ? spindle_dir::ccw
                                   : spindle_dir::off;
      simple(event::spindle_ev, speed, 0, 0, int(sdir));
    }
    if (b.m[m_coolant] >= 0) {
      if (b.m[m_coolant] == 9) {
        mist = flood = false;
      } else {
        if (b.m[m_coolant] == 7 || b.mist_and_flood) mist = true;
        if (b.m[m_coolant] == 8 || b.mist_and_flood) flood = true;
      }
      simple(event::coolant_ev, mist, flood);
    }
    // 10. dwell
    if (g0 == 40) simple(event::dwell, b.v('P'));
    // 11. plane
    if (b.g[g_plane] >= 0) {
      pl = b.g[g_plane] == 170 ? plane::xy : b.g[g_plane] == 180 ? plane::zx : plane::yz;
      simple(event::plane_ev, 0, 0, 0, int(pl));
    }
    // 12. units
    if (b.g[g_units] >= 0) {
      prog_units = b.g[g_units] == 200 ? units::inch : units::mm;
      k = prog_units == units::inch ? mm_per_inch : 1.0;
      simple(event::units_ev, 0, 0, 0, int(prog_units));
    }
    // 13. cutter compensation: G40 is the only state there is.
    // 14. tool length
    if (b.g[g_tool_length] >= 0) tool_length();
    // 15. coordinate system
    if (b.g[g_coord] >= 0) {
      int c = b.g[g_coord];
      cs = c <= 590 ? (c - 540) / 10 : 6 + (c - 591);
    }
    // 16. path control
    if (b.g[g_path] >= 0) {
      pmode = b.g[g_path] == 610   ? path_mode::exact_path
              : b.g[g_path] == 611 ? path_mode::exact_stop
                                   : path_mode::blend;
      double p = b.has('P') ? b.v('P') * k / out_scale : 0, q = b.has('Q') ? b.v('Q') * k / out_scale : 0;
      if (b.has('P') && b.v('P') < 0) fail(b.at('P'), "negative G64 P tolerance");
      if (b.has('Q') && b.v('Q') < 0) fail(b.at('Q'), "negative G64 Q tolerance");
      simple(event::path_ev, p, q, 0, int(pmode));
    }
    // 17. distance modes
    if (b.g[g_distance] >= 0) incremental = b.g[g_distance] == 910;
    if (b.g[g_arc_distance] >= 0) arc_absolute = b.g[g_arc_distance] == 901;
    // 19. home, coordinate data, axis offsets
    bool moved_by_nonmodal = false;
    switch (g0) {
      case 280:
      case 300:
        home(g0 == 280 ? g28 : g30);
        moved_by_nonmodal = true;
        break;
      case 281:
        g28 = pos;
        break;
      case 301:
        g30 = pos;
        break;
      case 100:
        g10();
        break;
      case 920:
        for (int a = 0; a < n_axes; ++a)
          if (b.has("XYZABC"[a]))
            g92[size_t(a)] =
                pos[size_t(a)] - tlo[size_t(a)] - g5x[size_t(cs)][size_t(a)] - b.v("XYZABC"[a]) * scale(a);
        break;
      case 921:
        g92.fill(0);
        break;
      default:
        break;
    }
    // 20. motion
    // 18. canned cycle return level
    if (b.g[g_retract] >= 0) retract_r = b.g[g_retract] == 990;
    const int before = motion;
    if (b.g[g_motion] >= 0) motion = b.g[g_motion];
    bool axis = false;
    for (char c : {'X', 'Y', 'Z', 'A', 'B', 'C'}) axis = axis || b.has(c);
    bool uses_axes = g0 == 100 || g0 == 920 || moved_by_nonmodal || b.g[g_tool_length] == 431;
    // A motion word moves even without axis words (LinuxCNC: to where it is).
    if (!uses_axes && (axis || b.g[g_motion] >= 0)) {
      if (is_cycle(motion)) {
        cycle(before);
      } else {
        il_set = false;  // a series of cycles ends with another motion (G80 too)
        move(g0 == 530);
      }
    }
    // 21. stop
    if (b.m[m_stop] >= 0) {
      int m = b.m[m_stop];
      if (m == 0 || m == 1)
        simple(event::pause_ev, 0, 0, 0, m);
      else
        end_program(m == 30);
    }
  }

  void tool_length() {
    int c = b.g[g_tool_length];
    pose t{};
    if (c == 430) {
      int h = tool_loaded;
      if (b.has('H')) {
        double hv = b.v('H');
        if (hv < 0 || hv != std::floor(hv) || hv > tool_max)
          fail(b.at('H'), "H must be a tool number (a whole number 0.." + std::to_string(tool_max) + ")");
        h = int(hv);
      }
      int hcol = b.has('H') ? b.at('H') : b.g_col[g_tool_length];
      if (h != 0 && !have_tool_table) {
        warn(hcol,
             "G43 H" + std::to_string(h) +
                 ": no tool table, so tool length 0 (add [EMCIO] TOOL_TABLE to the machine file for the "
                 "tools' lengths)");
      } else if (h != 0) {
        auto it = tools.find(h);
        if (it == tools.end())
          fail(hcol, "tool " + std::to_string(h) + " is not in the tool table: add a line \"T" +
                         std::to_string(h) + " P" + std::to_string(h) + " Z<length>\" to it");
        t = it->second.offset;
      }
    } else if (c == 431) {
      for (int a = 0; a < n_axes; ++a)
        if (b.has("XYZABC"[a])) t[size_t(a)] = b.v("XYZABC"[a]) * scale(a);
    }
    // The program position stays: the machine position's meaning changes.
    tlo = t;
    pose o = to_out(tlo);
    event e{};
    e.k = event::tlo_ev;
    e.s.end = o;
    events.push_back(e);
  }

  void warn(int col, const std::string &what) {
    warnings.emplace_back(file, line_no, col < 1 ? 1 : col, "warning: " + what);
    simple(event::warning_ev, 0, 0, 0, int(warnings.size() - 1));
  }

  // ---- canned cycles (LinuxCNC's interp_cycles.cc, XY plane) ------------
  // Z levels are worked in program coordinates and units, as LinuxCNC
  // does (a peck's depth is compared as it compares it); a point becomes
  // machine coordinates only when it is emitted.

  void cycle(int before) {
    const int code = motion;
    const int mcol = b.g[g_motion] >= 0 ? b.g_col[g_motion] : b.first_col;
    const std::string name = g_name(code);
    const bool same = before == code;  // a repeat of the cycle in force: R Z P Q may be left out
    if (pl != plane::xy)
      fail(mcol, name + " in the " + (pl == plane::zx ? "XZ (G18)" : "YZ (G19)") +
                     " plane: canned cycles run in the XY plane (G17) only here");
    if (fmode == feed_mode::inverse_time)
      fail(mcol, name + " in inverse time mode (G93): canned cycles need G94");
    if (feed <= 0) fail(mcol, name + " with a feed rate of zero (no F given)");
    if (!b.has('R') && !same) fail(mcol, name + " needs R (the retract plane)");
    if (!b.has('Z') && !same) fail(mcol, name + " needs Z (the bottom of the hole)");
    int repeats = 1;
    if (b.has('L')) {
      double l = b.v('L');
      if (l != std::floor(l) || l < 1 || l > turns_max)
        fail(b.at('L'), name + " L (repeats) must be a whole number 1.." + std::to_string(turns_max));
      repeats = int(l);
    }
    const double rv = b.has('R') ? b.v('R') : cycle_r;
    const double zv = b.has('Z') ? b.v('Z') : cycle_z;
    double p = 0, q = 0;
    if (code == 820 || code == 890) {
      if (!b.has('P') && !same) fail(mcol, name + " needs P (the dwell at the bottom, seconds)");
      p = b.has('P') ? b.v('P') : cycle_p;
      if (p < 0) fail(b.at('P'), "negative dwell time");
    }
    if (code == 730 || code == 830) {
      if (!b.has('Q') && !same) fail(mcol, name + " needs Q (the depth of each peck)");
      q = b.has('Q') ? b.v('Q') : cycle_q;
      if (!(q > 0)) fail(b.has('Q') ? b.at('Q') : mcol, name + " Q (the depth of each peck) must be above 0");
    }

    const double off_z = offset(Z);
    const double cur_z = (pos[Z] - off_z) / k;  // program coordinates and units
    double old_cc = il_set ? il : cur_z;
    if (!il_set) il = cur_z, il_set = true;
    double aa = pos[X], bb = pos[Y], da = 0, db = 0;  // machine coordinates, mm
    double r, cc;
    if (!incremental) {
      pose t = target(false);
      aa = t[X], bb = t[Y];
      r = rv;
      cc = zv;
    } else {
      da = b.has('X') ? b.v('X') * k : 0;
      db = b.has('Y') ? b.v('Y') * k : 0;
      r = rv + old_cc;
      cc = r + zv;
    }
    if (r < cc)
      fail(b.has('R') ? b.at('R') : mcol, name + ": the retract plane R is below the bottom Z (R " +
                                              std::to_string(r) + ", Z " + std::to_string(cc) + ")");
    if ((code == 730 || code == 830) && (r - cc) / q > 1e6)
      fail(b.at('Q'), name + " Q is too small: over a million pecks");

    auto at = [&](double x, double y, double z) {
      pose e = pos;
      e[X] = x, e[Y] = y, e[Z] = z * k + off_z;
      return e;
    };
    double current_cc = cur_z;
    if (old_cc < r) {  // below the R plane: straight up to it first
      emit_straight(event::traverse, at(pos[X], pos[Y], r));
      old_cc = current_cc = r;
    }
    const double clear = retract_r ? r : old_cc;
    const double rapid_delta = prog_units == units::mm ? 0.010 * 25.4 : 0.010;
    auto traverse = [&](double z) { emit_straight(event::traverse, at(aa, bb, z)); };
    auto feed_to = [&](double z) { emit_straight(event::feed, at(aa, bb, z)); };
    for (int rep = repeats; rep > 0; --rep) {
      aa += da, bb += db;
      if (rep == repeats && current_cc > r) {
        traverse(current_cc);
        traverse(r);
      } else {
        traverse(clear);
        if (clear > r) traverse(r);
      }
      switch (code) {
        case 810:  // drill
          feed_to(cc);
          traverse(clear);
          break;
        case 820:  // drill, dwell at the bottom
          feed_to(cc);
          simple(event::dwell, p);
          traverse(clear);
          break;
        case 730:  // chip break: back off a little after each peck
        case 830:  // peck: out to R after each peck, back down to just above the last one
          for (double d = r - q; d > cc; d -= q) {
            feed_to(d);
            if (code == 830) traverse(r);
            traverse(d + rapid_delta);
          }
          feed_to(cc);
          traverse(clear);
          break;
        case 850:  // bore: feed in, feed out to R
          feed_to(cc);
          feed_to(r);
          traverse(clear);
          break;
        default:  // 890: bore, dwell, feed out
          feed_to(cc);
          simple(event::dwell, p);
          feed_to(clear);
          break;
      }
    }
    cycle_r = rv;
    cycle_z = zv;
    if (code == 820 || code == 890) cycle_p = p;
    if (code == 730 || code == 830) cycle_q = q;
  }

  void g10() {
    int p = int(b.v('P'));
    int sys = p == 0 ? cs : p - 1;
    bool l20 = b.v('L') == 20;
    for (int a = 0; a < n_axes; ++a) {
      char c = "XYZABC"[a];
      if (!b.has(c)) continue;
      double v = b.v(c) * scale(a);
      if (l20)  // the current position is v in that system
        g5x[size_t(sys)][size_t(a)] = pos[size_t(a)] - tlo[size_t(a)] - g92[size_t(a)] - v;
      else
        g5x[size_t(sys)][size_t(a)] = v;
    }
  }

  // G28/G30: a traverse to the point the axis words give, then one to the
  // stored position for those axes (all axes without axis words).
  void home(const pose &stored) {
    bool any = false;
    for (char c : {'X', 'Y', 'Z', 'A', 'B', 'C'}) any = any || b.has(c);
    pose mid = target(false);
    pose end = mid;
    for (int a = 0; a < n_axes; ++a)
      if (!any || b.has("XYZABC"[a])) end[size_t(a)] = stored[size_t(a)];
    emit_straight(event::traverse, mid);
    emit_straight(event::traverse, end);
  }

  void move(bool g53) {
    pose end = target(g53);
    switch (motion) {
      case 0:
        emit_straight(event::traverse, end);
        break;
      case 10:
        need_feed(b.g[g_motion] == 10 ? b.g_col[g_motion] : b.first_col, "G1");
        emit_straight(event::feed, end);
        break;
      case 20:
      case 30:
        need_feed(b.g[g_motion] >= 0 ? b.g_col[g_motion] : b.first_col, motion == 20 ? "G2" : "G3");
        arc_move(end);
        break;
      case 382:
      case 383:
      case 384:
      case 385:
        probe(end);
        break;
      default:
        break;
    }
  }

  // G38.2..G38.5: LinuxCNC's convert_probe (interp_convert.cc). Cutter
  // radius compensation, which it also refuses, is never on here.
  void probe(const pose &end) {
    const int col = b.g[g_motion] >= 0 ? b.g_col[g_motion] : b.first_col;
    const std::string name = g_name(motion);
    if (fmode == feed_mode::inverse_time)
      fail(col, name + " in inverse time mode (G93): probing needs G94 and a feed rate (F)");
    if (feed <= 0) fail(col, name + " with a feed rate of zero (no F given)");
    const auto kind = probe_kind(motion - 382);
    if ((kind == probe_kind::toward_or_error || kind == probe_kind::away_or_error) && end == pos)
      fail(col, name +
                    " ends where it starts: the probe move needs a length (LinuxCNC: \"start point too "
                    "close to probe point\")");
    event e{};
    e.k = event::probe_ev;
    e.s.end = to_out(end);
    e.s.feed = out_feed();
    e.s.mode = fmode;
    e.i = int(kind);
    e.from = to_out(pos);
    e.col = col;
    events.push_back(e);
    pos = end;
  }

  // The sink ran a probe move: go on from where it stopped; G38.2 and
  // G38.4 fail as LinuxCNC's motion controller fails them (control.c,
  // command.c) when the input never changed or had already changed.
  void probed(const event &e) {
    const probe_outcome r = out->straight_probe(e.s, probe_kind(e.i));
    pos = to_mm(r.stop);
    const auto kind = probe_kind(e.i);
    const bool away = kind == probe_kind::away_or_error;
    if (kind != probe_kind::toward_or_error && !away) return;
    if (!r.tripped)
      fail(e.col, away ? "G38.4 move finished without breaking contact"
                       : "G38.2 move finished without making contact");
    if (r.trip == e.from)
      fail(e.col, away ? "probe is already clear when starting the G38.4 move"
                       : "probe is already tripped when starting the G38.2 move");
  }

  void need_feed(int col, const char *what) {
    if (fmode == feed_mode::inverse_time && !b.has('F'))
      fail(col, std::string(what) + " in inverse time mode (G93) needs an F word on its line");
    if (feed <= 0) fail(col, std::string(what) + " with a feed rate of zero (no F given)");
  }

  void arc_move(const pose &end) {
    int mcol = b.g[g_motion] >= 0 ? b.g_col[g_motion] : b.first_col;
    const char *gname = motion == 20 ? "G2" : "G3";
    int a1, a2;  // the plane's first and second axes
    char i1, i2, iforbidden;
    const char *pname;
    switch (pl) {
      case plane::xy:
        a1 = X, a2 = Y, i1 = 'I', i2 = 'J', iforbidden = 'K', pname = "XY (G17)";
        break;
      case plane::zx:
        a1 = Z, a2 = X, i1 = 'K', i2 = 'I', iforbidden = 'J', pname = "XZ (G18)";
        break;
      default:
        a1 = Y, a2 = Z, i1 = 'J', i2 = 'K', iforbidden = 'I', pname = "YZ (G19)";
        break;
    }
    const char L1 = "XYZ"[a1], L2 = "XYZ"[a2];
    int turns = 1;
    if (b.has('P')) {
      double p = b.v('P');
      if (p != std::floor(p) || p < 1 || p > turns_max)
        fail(b.at('P'),
             std::string(gname) + " P (turns) must be a whole number 1.." + std::to_string(turns_max));
      turns = int(p);
    }
    double s1 = pos[size_t(a1)], s2 = pos[size_t(a2)];
    double e1 = end[size_t(a1)], e2 = end[size_t(a2)];
    double c1, c2;
    if (b.has('R')) {
      if (b.has('I') || b.has('J') || b.has('K'))
        fail(b.at('R'), "mixed R and I J K forms for an arc: use one");
      if (!b.has(L1) && !b.has(L2))
        fail(mcol,
             std::string(1, L1) + " and " + L2 + " words missing for an R arc in the " + pname + " plane");
      double r = b.v('R') * k;
      if (e1 == s1 && e2 == s2)
        fail(b.at('R'), "R arc whose end point is its start point (the centre is undefined: use I J K)");
      double ar = std::fabs(r);
      if (ar / k < tol().radius) fail(b.at('R'), "zero-radius arc (R " + std::to_string(r / k) + ")");
      double m1 = (s1 + e1) / 2, m2 = (s2 + e2) / 2;
      double half = std::hypot(e1 - m1, e2 - m2);
      if ((half - ar) / k > tol().radius)
        fail(b.at('R'), "arc radius too small to reach the end point (half the chord is " +
                            std::to_string(half / k) + ", R " + std::to_string(ar / k) + ")");
      if (half / ar > 1 - 1e-12) half = ar;
      // The centre is on the chord's perpendicular bisector, to the right of
      // the chord for a short clockwise arc, to the left for a long one.
      bool right = (motion == 20) == (r > 0);
      double ch = std::atan2(e2 - s2, e1 - s1) + (right ? -M_PI_2 : M_PI_2);
      double off = ar * std::cos(std::asin(half / ar));
      c1 = m1 + off * std::cos(ch);
      c2 = m2 + off * std::sin(ch);
      if (turns != 1) fail(b.at('P'), "P (turns) with an R arc: use I J K");
    } else {
      if (!b.has('I') && !b.has('J') && !b.has('K'))
        fail(mcol, std::string(gname) + " needs R or the centre (I J K)");
      if (b.has(iforbidden))
        fail(b.at(iforbidden), std::string(1, iforbidden) + " word for an arc in the " + pname + " plane");
      double o1 = b.has(i1) ? b.v(i1) * k : 0, o2 = b.has(i2) ? b.v(i2) * k : 0;
      if (arc_absolute) {
        if (!b.has(i1))
          fail(mcol, std::string(1, i1) + " word missing for an arc with absolute centre (G90.1)");
        if (!b.has(i2))
          fail(mcol, std::string(1, i2) + " word missing for an arc with absolute centre (G90.1)");
        c1 = o1 + offset(a1);
        c2 = o2 + offset(a2);
      } else {
        c1 = s1 + o1;
        c2 = s2 + o2;
      }
      // LinuxCNC's checks, in program units.
      double r1 = std::hypot(c1 - s1, c2 - s2) / k, r2 = std::hypot(c1 - e1, c2 - e2) / k;
      int icol = b.has(i1) ? b.at(i1) : b.at(i2);
      if (r1 < tol().radius || r2 < tol().radius) fail(icol, "zero-radius arc");
      double abs_err = std::fabs(r1 - r2), rel_err = abs_err / std::max(r1, r2);
      if (abs_err > tol().spiral_abs * 100.0 || (rel_err > spiral_rel && abs_err > tol().spiral_abs)) {
        char msg[160];
        std::snprintf(msg, sizeof msg,
                      "radius to the end of the arc (%.6g) differs from the radius to its start (%.6g)", r2,
                      r1);
        fail(icol, msg);
      }
    }
    arc a{};
    a.end = to_out(end);
    a.centre_first = c1 / out_scale;
    a.centre_second = c2 / out_scale;
    a.in = pl;
    a.turns = motion == 20 ? -turns : turns;
    a.feed = out_feed();
    a.mode = fmode;
    event e{};
    e.k = event::arc_feed;
    e.a = a;
    events.push_back(e);
    pos = end;
  }

  // M2/M30 (or the closing %): the last command of its line; the program
  // ends once the line's commands before it are given on (ended_program()), so a
  // probe on its line that fails leaves the program running (MDI).
  void end_program(bool m30) { simple(event::end_ev, 0, 0, 0, m30); }

  void ended_program() {
    // LinuxCNC's reset at M2/M30 (what a following program starts with).
    cs = 0;
    pl = plane::xy;
    incremental = false;
    fmode = feed_mode::units_per_minute;
    motion = 10;
    il_set = false;
    sdir = spindle_dir::off;
    mist = flood = false;
    ended = true;
  }

  void flush() {
    if (!out) {
      for (const event &e : events)
        if (e.k == event::end_ev) ended_program();
      events.clear();
      return;
    }
    if (!events.empty()) out->source_line(file, line_no);
    for (const event &e : events) {
      switch (e.k) {
        case event::traverse:
          out->straight_traverse(e.s);
          break;
        case event::feed:
          out->straight_feed(e.s);
          break;
        case event::probe_ev:
          probed(e);
          break;
        case event::arc_feed:
          out->arc_feed(e.a);
          break;
        case event::dwell:
          out->dwell(e.d[0]);
          break;
        case event::units_ev:
          out->program_units(units(e.i));
          break;
        case event::plane_ev:
          out->select_plane(plane(e.i));
          break;
        case event::path_ev:
          out->set_path_mode(path_mode(e.i), e.d[0], e.d[1]);
          break;
        case event::spindle_ev:
          out->spindle(spindle_dir(e.i), e.d[0]);
          break;
        case event::coolant_ev:
          out->coolant(e.d[0] != 0, e.d[1] != 0);
          break;
        case event::select_tool_ev:
          out->select_tool(e.i);
          break;
        case event::change_tool_ev:
          out->change_tool(e.i);
          break;
        case event::tlo_ev:
          out->tool_length_offset(e.s.end);
          break;
        case event::pause_ev:
          out->pause(e.i == 1);
          break;
        case event::message_ev:
          if (b.msg_debug)
            out->debug(b.msg);
          else
            out->message(b.msg);
          break;
        case event::warning_ev:
          out->warning(warnings[size_t(e.i)]);
          break;
        case event::end_ev:
          ended_program();
          out->program_end(e.i != 0);
          break;
      }
    }
    events.clear();
    warnings.clear();
  }

  // One line; false once the program ended.
  bool line(std::string_view s) {
    if (ended) return false;
    if (!parse(s)) return true;
    events.clear();
    warnings.clear();
    const modal_state before = *this;
    try {
      execute();
    } catch (const error &) {
      static_cast<modal_state &>(*this) = before;
      throw;
    }
    flush();
    return !ended;
  }

  void run(std::istream &in) {
    std::string text;
    bool percent = false, first = true;
    line_no = 0;
    while (std::getline(in, text)) {
      ++line_no;
      std::string_view s(text);
      // A UTF-8 byte-order mark (some Windows editors write one) is no character of the program.
      if (line_no == 1 && s.substr(0, 3) == "\xEF\xBB\xBF") s.remove_prefix(3);
      size_t a = 0, e = s.size();
      while (a < e && is_space(s[a])) ++a;
      while (e > a && is_space(s[e - 1])) --e;
      if (e - a == 1 && s[a] == '%') {
        if (first) {
          percent = true;
          first = false;
          continue;
        }
        if (!percent) fail(int(a) + 1, "closing '%' without an opening one on the first line");
        if (!ended) {
          events.clear();
          end_program(false);
          flush();
        }
        return;
      }
      if (a < e) first = false;
      if (!line(s)) return;
    }
    if (in.bad()) fail(1, "read error");
    ++line_no;
    fail(1, percent ? "file ended without its closing '%'" : "file ended without M2, M30 or '%'");
  }
};

interpreter::interpreter(sink &out, options o) : p_(std::make_unique<impl>(&out, o)) {}
interpreter::~interpreter() = default;

void interpreter::set_tool_table(std::map<int, tool> table) {
  for (auto &t : table)
    for (int a = 0; a < 3; ++a) t.second.offset[size_t(a)] *= p_->out_scale;
  p_->tools = std::move(table);
  p_->have_tool_table = true;
}

void interpreter::run(std::istream &in, const std::string &name) {
  p_->file = name;
  p_->ended = false;
  p_->run(in);
}

void interpreter::run_file(const std::string &path) {
  std::ifstream f(path);
  if (!f) throw error(path, 0, 0, "cannot open the file");
  run(f, path);
}

void interpreter::check(std::istream &in, const std::string &name) const {
  impl copy(*p_);
  copy.out = nullptr;
  copy.file = name;
  copy.ended = false;
  copy.run(in);
}

bool interpreter::execute_line(std::string_view line, const std::string &name, int line_no) {
  p_->file = name;
  p_->line_no = line_no;
  return p_->line(line);
}

pose interpreter::position() const { return p_->to_out(p_->pos); }

void interpreter::set_position(const pose &machine) { p_->pos = p_->to_mm(machine); }

pose interpreter::work_offset() const {
  pose o{};
  for (size_t a = 0; a < o.size(); ++a) o[a] = p_->g5x[size_t(p_->cs)][a] + p_->g92[a];
  return p_->to_out(o);
}

coordinate_state interpreter::coordinates() const {
  coordinate_state c;
  for (size_t i = 0; i < c.g5x.size(); ++i) c.g5x[i] = p_->to_out(p_->g5x[i]);
  c.system = p_->cs;
  c.g28 = p_->to_out(p_->g28);
  c.g30 = p_->to_out(p_->g30);
  c.g92 = p_->to_out(p_->g92);
  return c;
}
units interpreter::program_units() const noexcept { return p_->prog_units; }

void interpreter::set_coordinates(const coordinate_state &c) {
  for (size_t i = 0; i < c.g5x.size(); ++i) p_->g5x[i] = p_->to_mm(c.g5x[i]);
  p_->cs = c.system >= 0 && c.system < int(c.g5x.size()) ? c.system : 0;
  p_->g28 = p_->to_mm(c.g28);
  p_->g30 = p_->to_mm(c.g30);
  p_->g92 = p_->to_mm(c.g92);
}

interpreter::modes interpreter::modal() const {
  const impl &s = *p_;
  return modes{s.motion, s.cs,   s.pl,    s.prog_units,  s.incremental, s.fmode,
               s.sdir,   s.mist, s.flood, s.tool_loaded, s.feed,        s.speed};
}

std::map<int, tool> read_tool_table(const std::string &path, units in, units machine) {
  std::ifstream f(path);
  if (!f) throw error(path, 0, 0, "cannot open the tool table");
  double s = (in == units::inch ? mm_per_inch : 1.0) / (machine == units::inch ? mm_per_inch : 1.0);
  std::map<int, tool> table;
  std::string text;
  int n = 0;
  while (std::getline(f, text)) {
    ++n;
    auto semi = text.find(';');
    if (semi != std::string::npos) text.resize(semi);
    std::istringstream ws(text);
    std::string w;
    tool t;
    int number = -1;
    while (ws >> w) {
      char L = upper(w[0]);
      char *endp = nullptr;
      double v = std::strtod(w.c_str() + 1, &endp);
      if (w.size() < 2 || *endp) throw error(path, n, 1, "bad word '" + w + "' in the tool table");
      static const char axes[] = "XYZABC";
      const char *ax = std::strchr(axes, L);
      if (L == 'T' && (v < 0 || v != std::floor(v) || v > tool_max))
        throw error(path, n, 1,
                    "bad tool number '" + w + "' in the tool table: 0.." + std::to_string(tool_max));
      if (L == 'T')
        number = int(v);
      else if (L == 'D')
        t.diameter = v * s;
      else if (ax && *ax)
        t.offset[size_t(ax - axes)] = (ax - axes) < 3 ? v * s : v;
    }
    if (number >= 0) table[number] = t;
  }
  return table;
}

}  // namespace x4step::gcode
