// Helpers of the libFuzzer targets (fuzz/README.md): the input as a file, and the check that an
// error names its file.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>

namespace slt {

// The input written to a file of this process (the readers under test read paths).
inline std::string WriteFuzzInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/slt_fuzz_input_" + std::to_string(::getpid()) + ".txt";
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), size);
  return path;
}

// Every input error must name its source: a message that does not start with `where` is a
// finding (abort, so that libFuzzer saves the input).
inline void ExpectNamed(const std::exception& e, const std::string& where) {
  if (std::string(e.what()).rfind(where, 0) != 0) {
    std::fprintf(stderr, "error without its source '%s': %s\n", where.c_str(), e.what());
    std::abort();
  }
}

}  // namespace slt
