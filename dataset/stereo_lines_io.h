// The `stereo-lines/1` observation format (JSON; docs/formats.md):
//   {"format": "stereo-lines/1",
//    "rig": {"width": 640, "height": 480,
//            "left":  {"fx": .., "fy": .., "cx": .., "cy": ..},
//            "right": {"fx": .., "fy": .., "cx": .., "cy": ..},
//            "right_from_left": {"R": [[..],[..],[..]], "t": [..]}},
//    "frames": [{"time": 0.0, "left": [[id, u1, v1, u2, v2], ...], "right": [...]}, ...]}
//
// Units: pixels for intrinsics and segment endpoints (u right, v down, origin at the centre of
// the top-left pixel), metres for t, seconds for times. X_right = R X_left + t.
// Every key is required and unknown keys are rejected (a misspelt key must not silently turn
// into a default). Ids are any integers; a line may be seen in one image only.
#pragma once

#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "common/file_io.h"
#include "dataset/stereo_sequence.h"

namespace slt {

// Throw ConfigError ("<file>: key 'frames[3].left[7]': ...") on any malformed content.
StereoSequence ReadStereoLines(const std::string& path);
StereoSequence StereoLinesFromJson(const nlohmann::json& document, const std::string& where);
nlohmann::json StereoLinesToJson(const StereoSequence& sequence);
// Writes a stereo-lines/1 file one frame at a time, so that a front end can stream any number
// of frames with flat memory. The text is that of WriteStereoLines. The file is written through
// an AtomicFileWriter (common/file_io.h) and put in place by Close(); a writer destroyed before
// Close() removes it (a program writes all its outputs or none). Each frame is checked as
// CheckStereoSequence does; errors name PATH and the frame's key path.
class StereoLinesWriter {
 public:
  StereoLinesWriter(const std::string& path, const StereoRig& rig);
  ~StereoLinesWriter();
  StereoLinesWriter(const StereoLinesWriter&) = delete;
  StereoLinesWriter& operator=(const StereoLinesWriter&) = delete;
  void Append(const StereoFrame& frame);
  void Close();
  size_t frames() const { return frames_; }

 private:
  std::unique_ptr<AtomicFileWriter> file_;
  std::string buffer_;
  size_t frames_ = 0;
  double previous_time_ = 0.0;
  bool closed_ = false;
};

// Checks the sequence first (CheckStereoSequence), so it never writes a file that
// ReadStereoLines would reject; writes atomically, one observation per line.
void WriteStereoLines(const std::string& path, const StereoSequence& sequence);

// Reads a stereo-lines/1 file frame by frame: it holds one frame's text and observations at a
// time, so memory does not grow with the length of the sequence (`track` uses it). Same checks
// and same error messages as ReadStereoLines, frame by frame (a bad frame k throws when it is
// read, after frames 0..k-1 were returned). Streaming needs "format" and "rig" before "frames",
// as every writer of the project puts them; a file with another key order (or that is not a
// JSON object) is read whole with ReadStereoLines instead. A top-level key given twice is an
// error (ReadStereoLines keeps the last).
class StereoLinesReader {
 public:
  explicit StereoLinesReader(const std::string& path);
  ~StereoLinesReader();
  StereoLinesReader(const StereoLinesReader&) = delete;
  StereoLinesReader& operator=(const StereoLinesReader&) = delete;

  const StereoRig& rig() const { return rig_; }
  // Reads the next frame into *frame; false after the last one (the rest of the file is then
  // checked). Throws ConfigError naming the file and key ("frames[3].left[7]").
  bool Next(StereoFrame* frame);

 private:
  class Scanner;
  void FinishObject();  // after the frames: the closing brace and nothing else
  std::string path_;
  StereoRig rig_;
  std::unique_ptr<Scanner> scanner_;    // streaming
  std::optional<StereoSequence> whole_;  // the fallback: the file read whole
  size_t next_frame_ = 0;
  double previous_time_ = 0.0;
  bool in_frames_ = false;
};

// The rules a sequence must satisfy beyond the JSON structure: a usable rig
// (StereoRig::Check), finite times and coordinates, non-decreasing times, segments of non-zero
// length, no id twice in one image of one frame. Throws ConfigError naming `where` and the key
// path the offending value has in the file ("frames[3].left[7]").
void CheckStereoSequence(const StereoSequence& sequence, const std::string& where);

// The rig block alone (also used inside simulation configs). Every field is required; `path`
// is the block's key path in the errors ("rig").
StereoRig StereoRigFromJson(const nlohmann::json& rig, const std::string& where, const std::string& path);
nlohmann::json StereoRigToJson(const StereoRig& rig);

}  // namespace slt
