// SPDX-License-Identifier: LGPL-2.1-or-later
/**
 * @file files.hpp
 * @brief Files that several programs share (the parameter file, the
 *        machine file that x4grbl's $ settings change): read whole,
 *        replaced whole, under a lock.
 */
#ifndef X4STEP_FILES_HPP
#define X4STEP_FILES_HPP

#include <stdexcept>
#include <string>

namespace x4step::machine {

/// A file that cannot be read, locked or written: what() names it and why.
class file_error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An exclusive flock() on "PATH.lock" for as long as it lives: opened
/// read-only, so that another user's lock file serves too; on a kernel
/// without file locks (ENOSYS) nothing is waited for.
class file_lock {
 public:
  explicit file_lock(const std::string &path);
  ~file_lock();
  file_lock(const file_lock &) = delete;
  file_lock &operator=(const file_lock &) = delete;

 private:
  int fd_;
};

/// The whole text of a file; `missing_ok`: "" if it does not exist. An
/// error is "PATH: WHAT: reason".
std::string read_text(const std::string &path, bool missing_ok, const std::string &what = "cannot read");

/// Replaces the file's text atomically: "PATH.XXXXXX" in the same
/// directory with the old file's mode (0644 for a new one), fsynced,
/// renamed over PATH, the directory fsynced. A reader sees the old file
/// or the new one, never half of one; a power cut after it returns keeps it.
void replace_file(const std::string &path, const std::string &text);

}  // namespace x4step::machine

#endif
