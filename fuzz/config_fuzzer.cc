// libFuzzer target: the JSON configs, a simulation config and every registered tracker's
// options. Any input must either read or throw a ConfigError naming its source.
#include <cstdint>
#include <string>

#include "common/json_reader.h"
#include "fuzz/fuzz_input.h"
#include "methods/pose_tracker.h"
#include "simulator/simulation_config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slt;
  const std::string path = WriteFuzzInput(data, size);
  nlohmann::json document;
  try {
    document = ReadJsonFile(path);
  } catch (const ConfigError& e) {
    ExpectNamed(e, path);
    return 0;
  }
  try {
    SimulationConfigFromJson(document, path);
  } catch (const ConfigError& e) {
    ExpectNamed(e, path);
  }
  for (const std::string& name : RegisteredTrackerNames()) {
    try {
      CreateTracker(name, document, path);
    } catch (const ConfigError& e) {
      ExpectNamed(e, path);
    }
  }
  return 0;
}
