// SPDX-License-Identifier: LGPL-2.1-or-later
// Shared files (files.hpp): a lock file, whole reads, atomic replacement.
#include "files.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace x4step::machine {

namespace {

std::string sys_error(const std::string &what, const std::string &path) {
  return path + ": " + what + ": " + std::strerror(errno);
}

// An open descriptor, closed however the scope ends.
class fd_guard {
 public:
  explicit fd_guard(int fd) : fd_(fd) {}
  ~fd_guard() {
    if (fd_ >= 0) ::close(fd_);
  }
  fd_guard(const fd_guard &) = delete;
  fd_guard &operator=(const fd_guard &) = delete;
  int get() const noexcept { return fd_; }
  int release() noexcept {
    const int f = fd_;
    fd_ = -1;
    return f;
  }

 private:
  int fd_;
};

void write_all(int fd, const std::string &text, const std::string &path) {
  for (size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw file_error(sys_error("cannot write", path));
    done += size_t(n);
  }
}

std::string directory_of(const std::string &path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash + 1);
}

}  // namespace

file_lock::file_lock(const std::string &path) {
  const std::string lock_path = path + ".lock";
  fd_ = ::open(lock_path.c_str(), O_RDONLY | O_CREAT | O_CLOEXEC, 0666);
  if (fd_ < 0) throw file_error(sys_error("cannot create the lock file", lock_path));
  // A kernel built without file locks (CONFIG_FILE_LOCKING off: ENOSYS)
  // has nothing to wait for: replace_file() still replaces the file whole.
  while (::flock(fd_, LOCK_EX) < 0 && errno != ENOSYS)
    if (errno != EINTR) {
      const std::string why = sys_error("cannot lock", lock_path);
      ::close(fd_);
      throw file_error(why);
    }
}

file_lock::~file_lock() { ::close(fd_); }

std::string read_text(const std::string &path, bool missing_ok, const std::string &what) {
  const fd_guard f(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (f.get() < 0) {
    if (errno == ENOENT && missing_ok) return {};
    throw file_error(sys_error(what, path));
  }
  std::string text;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(f.get(), buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw file_error(sys_error(what, path));  // EISDIR too
    if (n == 0) break;
    text.append(buf, size_t(n));
  }
  return text;
}

void replace_file(const std::string &path, const std::string &text) {
  // A new file beside the old one, then renamed over it: atomic.
  std::string tmp = path + ".XXXXXX";
  fd_guard out(::mkostemp(&tmp[0], O_CLOEXEC));
  if (out.get() < 0) throw file_error(sys_error("cannot write in " + directory_of(path), path));
  try {
    write_all(out.get(), text, tmp);
    struct stat old {};
    const mode_t mode = ::stat(path.c_str(), &old) == 0 ? old.st_mode & 07777 : 0644;  // the old file's
    if (::fchmod(out.get(), mode) < 0 || ::fsync(out.get()) < 0)
      throw file_error(sys_error("cannot write", tmp));
    if (::close(out.release()) < 0) throw file_error(sys_error("cannot write", tmp));
    if (::rename(tmp.c_str(), path.c_str()) < 0) throw file_error(sys_error("cannot replace", path));
    // The rename itself outlives a power cut once the directory is synced.
    const fd_guard dir(::open(directory_of(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (dir.get() >= 0) ::fsync(dir.get());
  } catch (...) {
    ::unlink(tmp.c_str());
    throw;
  }
}

}  // namespace x4step::machine
