// fileio.h: files written atomically. Results, policies and pictures are read by other programs
// (and by a resumed run): a reader must see the old file or the whole new one, never half of one.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

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

// Files written together into one folder: the writer puts each into a staging folder inside it
// (by the name it will have), and commit() moves them all in once every one is whole. A writer
// that fails halfway (a value it refuses, a full disk) leaves the folder's earlier files as they
// were, not some new and some old. Each move is one rename: a crash of the machine among them can
// still leave some moved, each file whole.
class StagedFiles {
 public:
  // `dir` must exist. The staging folder is a hidden one inside it, unique to this writer.
  explicit StagedFiles(const std::string& dir);
  // Removes the staging folder and whatever is still in it.
  ~StagedFiles();
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;

  // The staging folder.
  const std::string& path() const { return path_; }
  // Where to write the file that will be `dir`/`name`.
  std::string stage(const std::string& name) const;
  // Moves each staged file (a name in the staging folder, or its path there) into dir, in order,
  // and returns their paths in dir. Throws roger::FileError naming the file that could not move.
  // `withdrawn` (names in dir) are removed once the moves are checked and before the first: a file
  // that says the folder is whole (a training's summary.json, moved in last) must not stand beside
  // some new files when a kill comes among the moves.
  std::vector<std::string> commit(const std::vector<std::string>& names, const std::vector<std::string>& withdrawn = {});

 private:
  std::string dir_, path_;
};

// Whether `name` (a file name, no folder) is what a writer killed part-way leaves behind:
// write_file_atomic's temporary ".NAME.tmpPID-N-R" or StagedFiles' folder ".stagedPID-N-R.tmp".
bool is_writer_leftover(const std::string& name);

// One writer's claim on an output folder while it lives (flock on the folder's hidden `.lock`, with
// this process's id and host in it): a second command writing into the same folder is refused
// naming the first, instead of both committing and leaving one's policy beside the other's
// summary. It makes the folder when missing, and its lock file when missing; both go again when the
// claim ends (the folder only when nothing was written into it), so that a folder holds only what
// its command wrote and "nothing written" leaves the disk as it was. On claiming, it removes what a writer killed
// part-way left there (StagedFiles' folders, write_file_atomic's temporaries): no other writer can
// be using them.
class OutputClaim {
 public:
  // `command` names the writer in the refusal ("roger train"). Throws roger::Error when another
  // process holds the folder, roger::FileError when the folder cannot be made or the lock opened.
  OutputClaim(const std::string& dir, const std::string& command);
  ~OutputClaim();
  OutputClaim(const OutputClaim&) = delete;
  OutputClaim& operator=(const OutputClaim&) = delete;

 private:
  std::string dir_;
  int fd_ = -1;
  bool made_ = false;      // the folder did not exist before the claim
  bool own_file_ = false;  // the claim made the lock file (and removes it when it ends)
};

// Flushes to disk the folder holding `path`, so that a rename or removal in it survives a crash of
// the machine (best effort: a folder that cannot be opened is left as it is).
void sync_folder_of(const std::string& path);

// Makes the folder (and its parents) an output file `path` goes into; a FileError starting with
// `context` when it cannot be made (a file on the way, no permission).
void make_parent_folder(const std::string& path, const std::string& context);

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
