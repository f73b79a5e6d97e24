// SPDX-License-Identifier: GPL-2.0
// x4ctl: the help of a command, from its record (command.hpp): the usage,
// its prose, its options in two columns, what follows them. The program's
// help lists every command of the registry with its summary.
#include <algorithm>
#include <string>

#include "cli.hpp"
#include "subcommand.hpp"

namespace x4ctl {
namespace {

// Where the second column starts.
constexpr size_t column = 23;

// "  left   text", the text's further lines under its first; a left part too
// wide for the column puts the text on the next line.
std::string two_columns(const std::string &left, const std::string &text) {
  std::string out = left;
  if (left.size() <= column)
    out += std::string(std::max<size_t>(1, column - left.size()), ' ');
  else
    out += "\n" + std::string(column, ' ');
  for (char ch : text) {
    out += ch;
    if (ch == '\n') out += std::string(column, ' ');
  }
  return out + "\n";
}

std::string option_line(const option &o) {
  std::string left = o.short_name ? std::string("  -") + o.short_name + ", --" : std::string("      --");
  left += o.name;
  if (!o.value.empty()) left += (o.list ? " " : "=") + o.value;
  return two_columns(left, o.help);
}

// The options of c as its help lists them: its own, then the common ones it
// does not name; hidden ones (no help) left out.
std::string options_text(const subcommand &c) {
  std::string out;
  for (const option &o : c.options)
    if (!o.help.empty()) out += option_line(o);
  for (const option &o : common_options())
    if (std::none_of(c.options.begin(), c.options.end(), [&](const option &m) { return m.name == o.name; }))
      out += option_line(o);
  return out;
}

std::string usage_text(const subcommand &c) {
  const std::string x4ctl = c.name.empty() ? "x4ctl " : "x4ctl " + c.name + " ";
  std::string out;
  for (const std::string &u : c.usage) out += (out.empty() ? "Usage: " : "       ") + x4ctl + u + "\n";
  return out;
}

std::string commands_text() {
  std::string out;
  for (const command_group &g : command_groups()) {
    if (!out.empty()) out += "\n";
    if (g.heading) out += std::string(g.heading) + "\n";
    for (const subcommand *c : g.commands)
      out += two_columns("  " + c->name + (c->synopsis.empty() ? "" : " " + c->synopsis), c->summary);
  }
  return out;
}

}  // namespace

std::string help_text(const subcommand &c) {
  if (c.overview) return help_text(main_command());
  std::string out = usage_text(c) + "\n" + c.prose + "\nOptions:\n" + options_text(c);
  if (c.name.empty()) out += "\n" + commands_text();
  if (!c.epilogue.empty()) out += "\n" + c.epilogue;
  return out;
}

}  // namespace x4ctl
