#include "core/fileio.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <random>
#include <regex>

#include "core/error.h"

namespace roger {

namespace fs = std::filesystem;

void sync_folder_of(const std::string& path) {
  const fs::path target(path);
  const std::string dir = target.has_parent_path() ? target.parent_path().string() : std::string(".");
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // best effort: the file itself is already on disk
  ::fsync(fd);
  ::close(fd);
}

AtomicFile::AtomicFile(const std::string& path, std::string context)
    : path_(path), context_(std::move(context)) {
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // Process id, a counter and a random number: concurrent writers (threads, processes, a resumed
  // run beside a stale one) never share a temporary.
  static std::atomic<unsigned> counter{0};
  std::random_device rd;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string name = "." + target.filename().string() + ".tmp" + std::to_string(getpid()) +
                             "-" + std::to_string(counter++) + "-" + std::to_string(rd() % 100000);
    temp_ = (dir / name).string();
    // 0666 and O_EXCL: the umask decides the final permissions, and no other file is clobbered.
    const int fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      file_ = fdopen(fd, "wb");
      if (!file_) {
        const int err = errno;
        ::close(fd);
        ::unlink(temp_.c_str());
        temp_.clear();
        fail(err);
      }
      return;
    }
    if (errno != EEXIST) {
      const int err = errno;
      temp_.clear();
      fail(err);
    }
  }
  temp_.clear();
  fail(EEXIST);
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_ && !temp_.empty()) ::unlink(temp_.c_str());
}

void AtomicFile::append(const void* data, size_t length) {
  if (error_ != 0 || length == 0) return;
  if (std::fwrite(data, 1, length, file_) != length) error_ = errno ? errno : EIO;
}

void AtomicFile::check() {
  if (error_ != 0) fail(error_);
}

void AtomicFile::fail(const std::string& reason) const {
  throw Error(context_ + " '" + path_ + "': " + reason);
}

void AtomicFile::commit() {
  if (error_ != 0) fail(error_);
  if (std::fflush(file_) != 0 || ::fsync(fileno(file_)) != 0) fail(errno);
  FILE* f = file_;
  file_ = nullptr;
  if (std::fclose(f) != 0) fail(errno);
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) fail(errno);
  committed_ = true;
  // The rename itself lives in the folder: without this a crash of the machine could lose it,
  // or keep a later file's rename and not this one's (a result.json without its policy.json).
  sync_folder_of(path_);
}

void AtomicFile::fail(int err) {
  throw FileError(context_ + " '" + path_ + "': " + std::strerror(err), path_, err);
}

void make_parent_folder(const std::string& path, const std::string& context) {
  const fs::path target(path);
  if (!target.has_parent_path()) return;
  std::error_code ec;
  fs::create_directories(target.parent_path(), ec);
  if (ec) throw FileError(context + " '" + path + "': " + ec.message(), path, ec.value());
}

void write_file_atomic(const std::string& path, const std::string& content,
                       const std::string& context) {
  make_parent_folder(path, context);
  AtomicFile file(path, context);
  file.append(content);
  file.commit();
}

bool is_writer_leftover(const std::string& name) {
  static const std::regex leftover(R"(\..+\.tmp[0-9]+-[0-9]+-[0-9]+|\.staged[0-9]+-[0-9]+-[0-9]+\.tmp)");
  return std::regex_match(name, leftover);
}

namespace {

// Takes the lock of a claim on `path` (made if missing: `made` says so) without waiting, and
// returns its descriptor; throws naming the holder when another process has it. The lock holds only
// if the file locked is still the one at the path: a claim that ended removes the file it made, and
// one locked between its open and that removal holds nothing, so it tries again.
int take_claim_lock(const std::string& path, const std::string& dir, const std::string& command, bool& made) {
  for (;;) {
    int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    made = fd >= 0;
    if (fd < 0 && errno == EEXIST) fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0) {
      if (errno == ENOENT) continue;  // removed by a claim ending between the two opens
      const int err = errno;
      throw FileError(command + ": cannot write into '" + dir + "': " + std::strerror(err), path, err);
    }
    int got;
    while ((got = ::flock(fd, LOCK_EX | LOCK_NB)) != 0 && errno == EINTR) {
    }
    if (got != 0) {
      std::string holder(200, '\0');
      const ssize_t n = ::pread(fd, holder.data(), holder.size() - 1, 0);
      holder.resize(n > 0 ? size_t(n) : 0);
      while (!holder.empty() && (holder.back() == '\n' || holder.back() == '\0')) holder.pop_back();
      ::close(fd);
      throw Error(command + ": the folder '" + dir + "' is in use by another command writing into it" +
                  (holder.empty() ? std::string() : " (" + holder + ")") + ": wait for it to end, or give another folder");
    }
    struct stat held, named;
    if (::fstat(fd, &held) == 0 && ::stat(path.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
        held.st_dev == named.st_dev)
      return fd;
    ::close(fd);
  }
}

}  // namespace

OutputClaim::OutputClaim(const std::string& dir, const std::string& command) : dir_(dir) {
  std::error_code ec;
  made_ = !fs::exists(dir, ec);
  if (!made_ && !fs::is_directory(dir, ec))
    throw FileError(command + ": cannot write into '" + dir + "': " + std::strerror(ENOTDIR), dir, ENOTDIR);
  fs::create_directories(dir, ec);
  if (ec) throw FileError(command + ": cannot make the folder '" + dir + "': " + ec.message(), dir, ec.value());
  try {
    fd_ = take_claim_lock((fs::path(dir) / ".lock").string(), dir, command, own_file_);
  } catch (const FileError&) {
    if (made_) fs::remove(dir, ec);
    throw;
  }
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  const std::string text = "pid " + std::to_string(::getpid()) + " on " + host + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, text.data(), text.size(), 0) != ssize_t(text.size())) {
    // Only a refusal's message reads it: the lock holds without it.
  }
  std::vector<fs::path> left;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (is_writer_leftover(it->path().filename().string())) left.push_back(it->path());
  for (const fs::path& p : left) fs::remove_all(p, ec);
}

OutputClaim::~OutputClaim() {
  if (fd_ < 0) return;
  std::error_code ec;
  // The lock file this claim made goes (a folder keeps only what its command wrote), and a folder it
  // made and nothing was written into goes too: as it was, absent.
  if (own_file_) fs::remove(fs::path(dir_) / ".lock", ec);
  ::close(fd_);  // closing releases the lock
  if (made_ && fs::is_empty(dir_, ec) && !ec) fs::remove(dir_, ec);
}

StagedFiles::StagedFiles(const std::string& dir) : dir_(dir) {
  static std::atomic<unsigned> counter{0};
  std::random_device rd;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string name = ".staged" + std::to_string(getpid()) + "-" + std::to_string(counter++) + "-" +
                             std::to_string(rd() % 100000) + ".tmp";
    path_ = (fs::path(dir) / name).string();
    if (::mkdir(path_.c_str(), 0777) == 0) return;
    if (errno != EEXIST) {
      const int err = errno;
      path_.clear();
      throw FileError("cannot write into '" + dir + "': " + std::strerror(err), dir, err);
    }
  }
  path_.clear();
  throw Error("cannot write into '" + dir + "': no free name for a staging folder");
}

StagedFiles::~StagedFiles() {
  std::error_code ec;
  if (!path_.empty()) fs::remove_all(path_, ec);
}

std::string StagedFiles::stage(const std::string& name) const { return (fs::path(path_) / name).string(); }

std::vector<std::string> StagedFiles::commit(const std::vector<std::string>& names,
                                             const std::vector<std::string>& withdrawn) {
  // A folder where a file goes would stop the moves halfway: refused before the first.
  for (const auto& n : names) {
    const std::string to = (fs::path(dir_) / fs::path(n).filename()).string();
    std::error_code ec;
    if (fs::is_directory(fs::symlink_status(to, ec)))
      throw FileError("cannot write '" + to + "': " + std::strerror(EISDIR), to, EISDIR);
  }
  for (const auto& n : withdrawn) {
    const std::string gone = (fs::path(dir_) / n).string();
    std::error_code ec;
    if (fs::remove(gone, ec); ec) throw FileError("cannot remove '" + gone + "': " + ec.message(), gone, ec.value());
  }
  std::vector<std::string> moved;
  for (const auto& n : names) {
    const std::string file = fs::path(n).filename().string();
    const std::string to = (fs::path(dir_) / file).string();
    std::error_code ec;
    fs::rename(stage(file), to, ec);
    if (ec) throw FileError("cannot write '" + to + "': " + ec.message(), to, ec.value());
    moved.push_back(to);
  }
  if (!moved.empty()) sync_folder_of(moved.front());
  return moved;
}

std::string read_file_text(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    throw Error("cannot read '" + path + "': not a regular file" +
                (std::filesystem::is_directory(status) ? " (a folder)" : " (a device, a pipe or a socket)"));
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (in) text << in.rdbuf();
  return text.str();
}

}  // namespace roger
