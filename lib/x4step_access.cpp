// SPDX-License-Identifier: LGPL-2.1-or-later
// Why opening /dev/x4stepN was refused, and the fix (x4step_access.hpp).
#include "x4step_access.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <sstream>

namespace x4step::detail {
namespace {

// The colon-separated fields of a line of /etc/group or /etc/passwd.
std::vector<std::string> fields(const std::string &line) {
  std::vector<std::string> f;
  std::string one;
  std::istringstream in(line);
  while (std::getline(in, one, ':')) f.push_back(one);
  if (!line.empty() && line.back() == ':') f.emplace_back();
  return f;
}

std::string slurp(const char *path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

access_facts access_facts_of(gid_t gid, const std::string &group_file, const std::string &passwd_file,
                             uid_t uid, const std::vector<gid_t> &session) {
  access_facts f;
  std::string user;
  std::istringstream pw(passwd_file);
  for (std::string line; std::getline(pw, line);) {
    const auto p = fields(line);  // name:x:uid:gid:...
    if (p.size() >= 4 && p[2] == std::to_string(uid)) {
      user = p[0];
      f.listed = p[3] == std::to_string(gid);
      break;
    }
  }
  std::istringstream gr(group_file);
  for (std::string line; std::getline(gr, line);) {
    const auto g = fields(line);  // name:x:gid:member,member
    if (g.size() < 3 || g[2] != std::to_string(gid)) continue;
    f.group = g[0];
    std::istringstream members(g.size() > 3 ? g[3] : "");
    for (std::string m; std::getline(members, m, ',');) f.listed |= !user.empty() && m == user;
    break;
  }
  f.in_session = std::find(session.begin(), session.end(), gid) != session.end();
  return f;
}

std::string access_denied_text(const std::string &path, const access_facts &f) {
  const std::string denied = path + ": permission denied: ";
  if (f.group != "lp")
    return denied + "the node belongs to group " + (f.group.empty() ? "unknown" : f.group) +
           ", not lp: install the udev rule 60-x4step.rules (make install), then 'sudo udevadm trigger'";
  if (f.in_session)
    return denied +
           "this session has group lp, yet the node refuses it: check its mode (0660, from the udev "
           "rule 60-x4step.rules)";
  if (f.listed)
    return denied +
           "you are in group lp, but this login session started before you were added: log in again "
           "(or run 'newgrp lp')";
  return denied +
         "you are not in group lp, which may use the motors: sudo usermod -aG lp $USER, then log in again";
}

std::string access_denied_text(const std::string &path) {
  struct stat sb {};
  if (::stat(path.c_str(), &sb))
    return path +
           ": permission denied: the motors need group lp: sudo usermod -aG lp $USER, then log in again";
  std::vector<gid_t> session(static_cast<size_t>(std::max(0, ::getgroups(0, nullptr))));
  session.resize(
      static_cast<size_t>(std::max(0, ::getgroups(static_cast<int>(session.size()), session.data()))));
  session.push_back(::getegid());
  return access_denied_text(
      path, access_facts_of(sb.st_gid, slurp("/etc/group"), slurp("/etc/passwd"), ::getuid(), session));
}

}  // namespace x4step::detail
