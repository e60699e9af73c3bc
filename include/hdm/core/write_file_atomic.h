// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Writing a file so that a failure never loses the previous one: the one way every hdm writer
/// (model files, exports, screenshots) puts bytes on disk.

#include <cstddef>
#include <string>

namespace hdm {

/// @brief Writes @p size bytes to @p path so that a failure never loses the previous file:
/// writes "<path>.tmp", flushes it to disk (fsync), then renames it over @p path (POSIX rename is
/// atomic within a file system, so a reader sees the old file or the new one, never a mix).
/// @param path  destination file; its directory must exist and be writable.
/// @param data  @p size bytes (may be null when @p size is 0).
/// @param size  number of bytes to write.
/// @throws IoError "<path>: <reason>" on any failure; the temporary file is removed.
/// @note O(size) plus one fsync; allocates nothing beyond the C library's FILE buffer.
void write_file_atomic(const std::string& path, const void* data, size_t size);

}  // namespace hdm
