// fileio.h: files written atomically. Results, policies and pictures are read by other programs
// (and by a resumed run): a reader must see the old file or the whole new one, never half of one.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>

namespace roger {

// A temporary file beside the destination, renamed over it on commit() and removed otherwise.
// Errors are roger::Error with "<context> '<path>': <reason>"; those of the system (a full disk, no
// permission) are roger::FileError with its errno.
class AtomicFile {
 public:
  // Creates the temporary (0666 before the umask, never clobbering another file).
  AtomicFile(const std::string& path, std::string context);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Appends bytes, remembering the first error (reported by commit).
  void append(const void* data, size_t length);
  // Appends text.
  void append(const std::string& text) { append(text.data(), text.size()); }

  // True while every append has succeeded.
  bool ok() const { return error_ == 0; }

  // Throws for the first failed append, with the operating system's reason.
  void check();

  // Throws "<context> '<path>': <reason>" (for a writer's own failure, e.g. an encoder's).
  [[noreturn]] void fail(const std::string& reason) const;

  // Flushes to disk, renames over the destination and flushes the folder; throws (and removes the
  // temporary) on error. After a crash at any instant the destination is the old file or the new
  // one, whole.
  void commit();

  // The destination path.
  const std::string& path() const { return path_; }

 private:
  [[noreturn]] void fail(int err);
  std::string path_, context_, temp_;
  FILE* file_ = nullptr;
  int error_ = 0;
  bool committed_ = false;
};

// Flushes to disk the folder holding `path`, so that a rename or removal in it survives a crash of
// the machine (best effort: a folder that cannot be opened is left as it is).
void sync_folder_of(const std::string& path);

// Writes a whole file atomically, creating its folder if needed. `context` starts any error
// message, e.g. "cannot write the policy file".
void write_file_atomic(const std::string& path, const std::string& content,
                       const std::string& context = "cannot write");

// The whole content of a file, bytes as they are; empty when it cannot be read (callers that must
// tell a missing file from an empty one check for it first). Throws roger::Error naming the path
// when it is there but not a regular file: a device such as /dev/zero never ends, and a named pipe
// waits for a writer.
std::string read_file_text(const std::string& path);

}  // namespace roger
