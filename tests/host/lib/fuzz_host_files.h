// host_files_fuzz's parts shared between its files: what a refusal must say, a valid text changed
// as the input says, and the scene kinds (fuzz_scene_files.cc).
#pragma once

#include <string>

#include "fuzz_input.h"

namespace palpa::testing::files_fuzz {

using Bytes = FuzzInput;

/// Prints "host files fuzz: WHAT: DETAIL" and aborts: the fuzzer's finding.
[[noreturn]] void Fail(const char* what, const std::string& detail);
/// A refusal must say what and where in words: not empty, not the JSON library's own message.
void CheckReason(const char* kind, const std::string& error, const std::string& text);
/// A valid JSON text changed as `variant` says (fuzz_host_files.cc's top): raw bytes, a leaf
/// replaced or removed, a number at an edge, bytes overwritten or the end cut.
std::string ChangedJson(Bytes& in, int variant, const std::string& valid);
/// A few bytes overwritten at chosen places, and perhaps the end cut off.
std::string Damaged(Bytes& in, std::string text);

/// Scene files, tissues (JSON grid, CSV force matrix, PGM image), trajectories, tactile streams and
/// datagrams, and pen presses, picked by the input and changed as `variant` says.
void CheckSceneKind(Bytes& in, int variant);

}  // namespace palpa::testing::files_fuzz
