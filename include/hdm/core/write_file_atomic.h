// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Writing files so that a failure never loses the previous ones and nothing else can be
/// redirected into: the one way every hdm writer (model files, exports and their side files,
/// pictures, CSV recordings, JSON reports) puts bytes on disk (docs/reliability.md).

#include <cstddef>
#include <functional>
#include <span>
#include <string>

namespace hdm {

/// One file of a set written by write_files_atomic().
struct FileBytes {
  std::string path;            ///< destination; its directory must exist and be writable
  const void* data = nullptr;  ///< @ref size bytes (may be null when @ref size is 0)
  size_t size = 0;             ///< number of bytes
};

/// @brief Writes @p size bytes to @p path so that a failure or a kill never loses the previous
/// file and a planted link cannot redirect the write: write_files_atomic() of one file.
/// @param path  destination file; its directory must exist and be writable.
/// @param data  @p size bytes (may be null when @p size is 0).
/// @param size  number of bytes to write.
/// @throws IoError "<path>: <reason>" on any failure; no temporary file is left behind.
/// @note O(size) plus two fsyncs; allocates the temporary's name only.
void write_file_atomic(const std::string& path, const void* data, size_t size);

/// Where the streaming form of write_file_atomic() puts a file's bytes, in order.
class FileSink {
 public:
  /// @brief Appends @p size bytes (@p data may be null when @p size is 0) to the file.
  /// @throws IoError "<path>: cannot write: <reason>" naming the destination.
  virtual void write(const void* data, size_t size) = 0;

 protected:
  ~FileSink() = default;
};

/// @brief write_file_atomic() of bytes made in pieces: @p produce writes the file's bytes to the
/// sink in order as it makes them, so the whole file is never held in memory (a model file is
/// as large as the model's stored arrays: 370 MiB at 100,000 slabs). Same guarantees as the
/// one-buffer form.
/// @param path     destination file; its directory must exist and be writable.
/// @param produce  called once with the sink; may throw.
/// @throws IoError as the one-buffer form; whatever @p produce throws, after the temporary is
///         removed (the destination keeps its old content either way).
/// @note O(size) plus two fsyncs; allocates the temporary's name only (plus what @p produce does).
void write_file_atomic(const std::string& path, const std::function<void(FileSink&)>& produce);

/// @brief Writes a set of files (an export and its side files) so that either every file is
/// replaced or, on a failure, none is and nothing new is left.
///
/// Each file's bytes go into an unnamed temporary created in the destination's directory
/// (`O_TMPFILE`, or where the file system lacks it a name created with `O_CREAT|O_EXCL|O_NOFOLLOW`),
/// are flushed to disk (fsync), and get a name only when every file of the set is written: the
/// temporary name `.<file name>.<pid>-<k>.tmp` (a name that exists, a planted file or link
/// included, is never opened or followed: the next k is tried, at most 100), then each is renamed
/// over its destination (the side files first, @p files[0] last) and the directory is flushed. A
/// kill at any point leaves each destination as the old file or the complete new one; a kill
/// while the temporary is unnamed leaves nothing, one between naming and renaming (a few
/// microseconds) a temporary whose process is dead, which the next write of that destination
/// removes (only regular files of this user whose name carries a process id that no longer
/// exists).
/// @param files  destinations and their bytes; destinations must differ.
/// @throws IoError "<path>: <reason>" naming the file and the system's reason (no space, read-only
///         directory, permission) on any failure; every temporary is removed, every destination
///         keeps its old content (a rename failing after others succeeded, which needs no space,
///         leaves the renamed files new).
/// @note O(total size) plus one fsync per file and per directory; allocates names only.
void write_files_atomic(std::span<const FileBytes> files);

/// @brief The temporary name write_files_atomic() gives the @p k-th temporary of process @p pid
/// for destination @p path: `<directory>/.<file name>.<pid>-<k>.tmp`. O(path length).
std::string temporary_name(const std::string& path, long pid, unsigned k);

}  // namespace hdm
