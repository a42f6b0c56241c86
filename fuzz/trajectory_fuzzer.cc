// libFuzzer target: the TUM and KITTI trajectory readers. Any input must either read or throw
// a std::runtime_error naming the file.
#include <cstdint>
#include <stdexcept>

#include "dataset/trajectory.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slt;
  const std::string path = WriteFuzzInput(data, size);
  try {
    ReadTumTrajectory(path);
  } catch (const std::runtime_error& e) {
    ExpectNamed(e, path);
  }
  try {
    ReadKittiTrajectory(path, 0.1);
  } catch (const std::runtime_error& e) {
    ExpectNamed(e, path);
  }
  return 0;
}
