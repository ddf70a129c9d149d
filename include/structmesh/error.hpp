// Error types shared by every module. The CLI maps them to exit codes:
// InputError -> 2 (bad usage or bad input), Error -> 1 (runtime failure).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace structmesh {

/// A runtime failure that is not the user's input's fault (exit code 1).
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad input: unreadable, malformed or invalid file or option (exit code 2).
/// The message names the file and, where known, the line: "bunny.obj:1203: ...".
class InputError : public Error {
 public:
  using Error::Error;
};

/// Builds "file:line: message" (line 0 means "no line": "file: message").
std::string located_message(const std::string& file, std::uint64_t line, const std::string& message);

}  // namespace structmesh
