#include "core/fileio.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <random>

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

std::vector<std::string> StagedFiles::commit(const std::vector<std::string>& names) {
  // A folder where a file goes would stop the moves halfway: refused before the first.
  for (const auto& n : names) {
    const std::string to = (fs::path(dir_) / fs::path(n).filename()).string();
    std::error_code ec;
    if (fs::is_directory(fs::symlink_status(to, ec)))
      throw FileError("cannot write '" + to + "': " + std::strerror(EISDIR), to, EISDIR);
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
