// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/io/read_file.h>

#include "text_cursor.h"

#include <filesystem>
#include <fstream>

namespace hdm {

void check_input_size(uint64_t size, uint64_t max_bytes, const std::string& name) {
  if (size > max_bytes)
    throw IoError(name + ": " + io::detail::with_commas(size) + " bytes, more than the input limit of " +
                  io::detail::with_commas(max_bytes) + " bytes" +
                  (max_bytes >= (1u << 20) ? " (" + std::to_string(max_bytes >> 20) + " MiB)" : std::string()) +
                  "; raise the limit to read it (hdm: --max-input-mb)");
}

std::string read_file(const std::string& path, uint64_t max_bytes) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw IoError(path + ": no such file");
  if (!std::filesystem::is_regular_file(status)) throw IoError(path + ": not a regular file");
  const uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw IoError(path + ": cannot determine the file size: " + ec.message());
  check_input_size(size, max_bytes, path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open for reading");
  std::string bytes(static_cast<size_t>(size), '\0');
  if (size > 0 && !in.read(bytes.data(), static_cast<std::streamsize>(size))) throw IoError(path + ": read error");
  return bytes;
}

}  // namespace hdm
