// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The device bridge's shared secret (docs/bridge.md): what a driver's hello packet must carry for
/// hdm to serve it. It lives in a file only its owner may read, or in an environment variable.

#include <string>

namespace hdm::bridge {

/// Name of the environment variable load_bridge_secret() reads when no file is given.
inline constexpr const char* kSecretVariable = "HDM_BRIDGE_SECRET";

/// @brief The shared secret: the content of @p file (trailing white space removed) or, when
/// @p file is empty, of the environment variable HDM_BRIDGE_SECRET.
///
/// A @p file that does not exist is created (`O_CREAT|O_EXCL|O_NOFOLLOW`, mode 0600) holding 32
/// random hexadecimal digits (getrandom), so `hdm bridge --secret-file F` and the driver started
/// after it with the same F agree. An existing file must be a regular file (not a link) owned by
/// this user and readable by no one else (mode 0600 or 0400).
/// @param file  path of the secret file, or empty for the environment variable.
/// @return the secret, kMinSecretBytes to kMaxSecretBytes bytes.
/// @throws InvalidInput naming the file or the variable when it is missing, too short or too long,
///         a link, another user's, or open to others (with the chmod that fixes it); IoError when
///         the file cannot be created or read (with the system's reason).
/// @note O(secret size); a few system calls. Not real-time.
std::string load_bridge_secret(const std::string& file);

}  // namespace hdm::bridge
