// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Reading a whole input file into memory under a size limit: the first step of every hdm reader
/// (meshes, `.hdm` models, sculpt scripts), so no file is read, and nothing is allocated for it,
/// beyond a limit the user can raise.

#include <cstdint>
#include <string>

namespace hdm {

/// Default input size limit of hdm's readers [bytes]: 1 GiB, about 20 million triangles as binary
/// STL or PLY and 10 million as OBJ or OFF text. Raised per call through the readers' options
/// (MeshReadOptions, ModelLoadOptions) or, in the `hdm` program, with `--max-input-mb`.
inline constexpr uint64_t default_max_input_bytes = uint64_t(1) << 30;

/// @brief Returns the bytes of @p path, after checking that the file is a regular file of at most
/// @p max_bytes bytes (checked before anything is read or allocated).
/// @throws IoError "<path>: no such file", "<path>: not a regular file", "<path>: cannot open for
///         reading", "<path>: read error", or "<path>: 3,221,225,472 bytes, more than the input
///         limit of 1,073,741,824 bytes (1024 MiB); raise the limit to read it (hdm:
///         --max-input-mb)".
/// @note O(file size); one allocation of the file's size.
std::string read_file(const std::string& path, uint64_t max_bytes = default_max_input_bytes);

/// @brief Throws the IoError above when @p size bytes of input named @p name exceed @p max_bytes.
void check_input_size(uint64_t size, uint64_t max_bytes, const std::string& name);

}  // namespace hdm
