// libFuzzer target: the stereo-lines/1 readers. Any input must either read or throw a
// ConfigError naming the file; and what the streaming reader (StereoLinesReader) accepts, the
// whole-file reader (ReadStereoLines) must accept identically.
#include <cstdint>
#include <cstdlib>

#include "common/json_reader.h"
#include "dataset/stereo_lines_io.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slt;
  const std::string path = WriteFuzzInput(data, size);
  StereoSequence streamed;
  bool streamed_ok = true;
  try {
    StereoLinesReader reader(path);
    streamed.rig = reader.rig();
    StereoFrame frame;
    while (reader.Next(&frame)) streamed.frames.push_back(frame);
  } catch (const ConfigError& e) {
    ExpectNamed(e, path);
    streamed_ok = false;
  }
  try {
    const StereoSequence whole = ReadStereoLines(path);
    if (streamed_ok && whole.frames.size() != streamed.frames.size()) std::abort();
    for (size_t k = 0; streamed_ok && k < whole.frames.size(); ++k) {
      if (whole.frames[k].time != streamed.frames[k].time ||
          whole.frames[k].left.size() != streamed.frames[k].left.size() ||
          whole.frames[k].right.size() != streamed.frames[k].right.size()) {
        std::abort();
      }
    }
  } catch (const ConfigError& e) {
    ExpectNamed(e, path);
    if (streamed_ok) std::abort();  // the streaming reader accepted what the whole reader refuses
  }
  return 0;
}
