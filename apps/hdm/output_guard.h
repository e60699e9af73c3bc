// SPDX-License-Identifier: MIT
#pragma once
// The output of a command is never one of its inputs: every command that reads files and writes
// one checks its outputs here before it reads anything (docs/reliability.md).
#include <string>
#include <vector>

namespace hdm::app {

/// Throws InvalidInput naming @p option when an output in @p outputs is the same file as an input
/// in @p inputs (same device and inode, so a link or another spelling of the path is caught), or
/// two outputs are the same file. Outputs that do not exist yet cannot be an input. Empty paths are
/// skipped.
void check_outputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs,
                   const char* option = "-o");

/// Throws InvalidInput naming @p option when @p path, where a slab model (.hdm) is written, has the
/// extension of a mesh format (.obj, .ply, .off, .stl, .glb, .gltf, ...): a model saved there
/// would replace a mesh with a file no mesh reader takes.
void check_model_output(const std::string& path, const char* option = "-o");

}  // namespace hdm::app
