// SPDX-License-Identifier: LGPL-2.1-or-later
// Why opening /dev/x4stepN was refused (EACCES, EPERM), and the fix, in
// words: not in the node's group, in it but not yet in this login
// session, or a node without the udev rule's group. Internal.
#ifndef X4STEP_ACCESS_HPP
#define X4STEP_ACCESS_HPP

#include <sys/types.h>

#include <string>
#include <vector>

namespace x4step::detail {

/// What decides the message.
struct access_facts {
  std::string group;        ///< the node's group, by name ("" unknown)
  bool listed = false;      ///< the user is a member (/etc/group, or the primary group)
  bool in_session = false;  ///< this process has the group
};

/// The facts from the node's group gid, the text of /etc/group and of
/// /etc/passwd, the user's uid and this process' groups (no NSS: static
/// programs read the files as they are).
access_facts access_facts_of(gid_t gid, const std::string &group_file, const std::string &passwd_file,
                             uid_t uid, const std::vector<gid_t> &session);

/// "PATH: permission denied: ...; FIX".
std::string access_denied_text(const std::string &path, const access_facts &f);

/// The same for this process and the node at path.
std::string access_denied_text(const std::string &path);

}  // namespace x4step::detail

#endif  // X4STEP_ACCESS_HPP
