// Outputs. A regular file is replaced atomically: written under a temporary
// name (an unnamed file where the file system allows) in its directory and
// renamed into place only when complete, so that a failed or interrupted run
// never leaves a half-written file and never clobbers an earlier good one.
// A symbolic link is followed (its target is replaced, the link kept); a
// device, pipe or socket, and "-" (standard output), are written directly,
// once the content is complete, and their write errors (a full disk) are
// reported. Temporary files are removed when the writer fails, throws or is
// ended by SIGINT, SIGTERM, SIGHUP or SIGQUIT; an unnamed one also on kill
// -9. Inputs: whole documents with a size limit, or piece by piece.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace clothfit {

// What an output path names, after following symbolic links.
struct OutputTarget {
  // kDescriptor: one of this process's open files: "-" (standard output)
  // and /dev/stdout, /dev/fd/N, /proc/self/fd/N.
  enum Kind { kNewFile, kRegularFile, kSpecialFile, kDescriptor };
  std::string path;  // the link's target for a symbolic link
  Kind kind = kNewFile;
  int fd = -1;  // kDescriptor: the descriptor
  // Written directly (no temporary file renamed over it).
  bool direct() const { return kind == kSpecialFile || kind == kDescriptor; }
};

// Throws InputError "path: cannot write: reason" for an empty path, a
// directory, a symbolic link loop or a path that cannot be examined.
OutputTarget ResolveOutput(const std::string& path);

// One output being written: write it through Write() or, for a library that
// opens files itself, under write_path(); then Commit(). Destroyed without
// Commit (an error, an exception), it leaves the target as it was.
class OutputFile {
 public:
  // Throws InputError "path: cannot write: reason".
  explicit OutputFile(const std::string& path);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  // A name the content may be written under (opened anew, truncated).
  const std::string& write_path() const { return write_path_; }
  void Write(const std::string& content);
  // Renames the content over a regular target or copies it to a direct
  // one. Throws InputError naming the path.
  void Commit();

 private:
  void CopyToTarget();

  std::string path_;  // as the user gave it, for messages
  OutputTarget target_;
  std::string write_path_;
  int fd_ = -1;
  bool named_ = false;  // write_path_ is a name in a directory
  int slot_ = -1;       // its entry in the signal handler's table
};

// Writes `content` to `path` as above. Throws InputError naming the path
// and the system's reason when the file cannot be written.
void WriteFileAtomically(const std::string& path, const std::string& content);

// Writes `path` through `write`, for libraries that open the file themselves
// (OpenEXR, OpenImageIO): `write` is given a name to write the content under
// and returns "" or the problem ("cannot write image: ..."). Throws
// InputError "path: problem"; exceptions from `write` pass through, and the
// target is left as it was in both cases.
void WriteAtomicallyVia(
    const std::string& path,
    const std::function<std::string(const std::string&)>& write);

// Throws InputError ("path: cannot write: reason") unless `path` can be
// written (a new file can be created in its directory, or the device is
// writable): a command checks its output before a long computation, not
// after. Leaves nothing behind.
void CheckWritable(const std::string& path);

// A file a command reads or writes, with the option that names it.
struct NamedFile {
  std::string option;  // "--data"
  std::string path;
};

// Throws InputError "OUT: --out names the same file as --data (IN): ..."
// when an output is one of the inputs or another output (the same file
// after links; "-" and devices such as /dev/null may repeat).
void CheckOutputsDistinct(const std::vector<NamedFile>& outputs,
                          const std::vector<NamedFile>& inputs);

// "" when `path` names a regular file (after symbolic links), else why not,
// for a message: the system's reason ("No such file or directory", "Too many
// levels of symbolic links", "Is a directory") or "not a regular file (a
// device, pipe or socket)". For inputs that a library must seek in (images);
// nothing is opened, so a pipe is not blocked on.
std::string RegularFileProblem(const std::string& path);

// Largest document ReadFileToString reads by default: a parameter file, a
// mip map's index or an image-stack manifest (clothfit's own are well under
// 1 MiB; a lookup table of 64 x 64 views is about 0.5 MiB).
inline constexpr size_t kMaxDocumentBytes = size_t{64} << 20;

// Reads a whole file of at most `max_bytes` (a regular file, or a device or
// pipe read as a stream up to the limit). Throws InputError naming the path
// when it cannot be read or is longer ("larger than the 64 MiB limit").
std::string ReadFileToString(const std::string& path,
                             size_t max_bytes = kMaxDocumentBytes);

// Reads a file piece by piece (1 MiB at a time), handing each piece to
// `consume` (pieces split lines anywhere); a file of any size in constant
// memory. Throws InputError naming the path when it cannot be read;
// exceptions from `consume` pass through.
void ReadFileInChunks(const std::string& path,
                      const std::function<void(std::string_view)>& consume);

}  // namespace clothfit
