// The `stereo-lines/1` observation format (JSON; docs/formats.md):
//   {"format": "stereo-lines/1",
//    "rig": {"width": 640, "height": 480,
//            "left":  {"fx": .., "fy": .., "cx": .., "cy": ..},
//            "right": {"fx": .., "fy": .., "cx": .., "cy": ..},
//            "right_from_left": {"R": [[..],[..],[..]], "t": [..]}},
//    "frames": [{"time": 0.0, "left": [[id, u1, v1, u2, v2], ...], "right": [...]}, ...]}
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "dataset/stereo_sequence.h"

namespace slt {

// Throw ConfigError ("<file>: key 'frames[3].left[7]': ...") on any malformed content.
StereoSequence ReadStereoLines(const std::string& path);
StereoSequence StereoLinesFromJson(const nlohmann::json& document, const std::string& where);
nlohmann::json StereoLinesToJson(const StereoSequence& sequence);
void WriteStereoLines(const std::string& path, const StereoSequence& sequence);

// The rig block alone (also used inside simulation configs).
StereoRig StereoRigFromJson(const nlohmann::json& rig, const std::string& where, const std::string& path);
nlohmann::json StereoRigToJson(const StereoRig& rig);

}  // namespace slt
