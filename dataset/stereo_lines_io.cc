#include "dataset/stereo_lines_io.h"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <fstream>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <unordered_map>

#include "common/file_io.h"
#include "common/json_reader.h"

namespace slt {
namespace {

constexpr char kFormatName[] = "stereo-lines/1";

// Errors read "<where>: key '<path>': <reason>", as JsonReader's do.
[[noreturn]] void Fail(const std::string& where, const std::string& path, const std::string& reason) {
  throw ConfigError(where + ": key '" + path + "': " + reason);
}

std::string Indexed(const std::string& path, size_t index) { return path + "[" + std::to_string(index) + "]"; }

std::string Field(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

// What a JSON value is, for error messages: the value itself when short, else its type.
std::string Describe(const nlohmann::json& value) {
  const std::string text = value.dump();
  return text.size() <= 24 ? text : std::string("a JSON ") + value.type_name();
}

// Checks that `object` is a JSON object holding exactly `keys`: in a data file every key is
// required and an unknown one is a typo. (JsonReader serves option structs, whose keys are
// optional; it also copies its object, which for the frames would copy the bulk of the file.)
void ExpectFields(const nlohmann::json& object, const std::string& where, const std::string& path,
                  std::initializer_list<const char*> keys) {
  if (!object.is_object()) {
    const std::string reason = std::string("expected a JSON object, got ") + object.type_name();
    if (path.empty()) throw ConfigError(where + ": top level: " + reason);
    Fail(where, path, reason);
  }
  for (const char* key : keys) {
    if (!object.contains(key)) Fail(where, Field(path, key), "missing");
  }
  for (const auto& item : object.items()) {
    if (std::find(keys.begin(), keys.end(), item.key()) == keys.end()) {
      Fail(where, Field(path, item.key()), "unknown key");
    }
  }
}

// `what` prefixes the reason when `path` names more than the value ("id: ").
double Number(const nlohmann::json& value, const std::string& where, const std::string& path,
              const std::string& what = "") {
  if (!value.is_number()) Fail(where, path, what + "expected a number, got " + Describe(value));
  return value.get<double>();
}

std::int64_t Integer(const nlohmann::json& value, const std::string& where, const std::string& path,
                     const std::string& what = "") {
  if (value.is_number_unsigned()) {
    const std::uint64_t u = value.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      Fail(where, path, what + "integer " + value.dump() + " is out of range");
    }
    return static_cast<std::int64_t>(u);
  }
  if (value.is_number_integer()) return value.get<std::int64_t>();
  if (value.is_number_float()) {
    // Programs that store a whole observation row as floats (numpy's tolist() of a float
    // array) write id 7 as 7.0: accept integral values that a double holds exactly.
    const double d = value.get<double>();
    constexpr double kExactIntegerLimit = 9007199254740992.0;  // 2^53
    if (std::isfinite(d) && d == std::floor(d) && std::abs(d) <= kExactIntegerLimit) {
      return static_cast<std::int64_t>(d);
    }
  }
  Fail(where, path, what + "expected an integer, got " + Describe(value));
}

int ImageSize(const nlohmann::json& value, const std::string& where, const std::string& path) {
  const std::int64_t v = Integer(value, where, path);
  if (v <= 0 || v > std::numeric_limits<int>::max()) Fail(where, path, "must be a positive integer");
  return static_cast<int>(v);
}

PinholeCamera CameraFromJson(const nlohmann::json& object, const std::string& where, const std::string& path) {
  ExpectFields(object, where, path, {"fx", "fy", "cx", "cy"});
  PinholeCamera camera;
  camera.fx = Number(object["fx"], where, Field(path, "fx"));
  camera.fy = Number(object["fy"], where, Field(path, "fy"));
  camera.cx = Number(object["cx"], where, Field(path, "cx"));
  camera.cy = Number(object["cy"], where, Field(path, "cy"));
  return camera;
}

// A JSON array of exactly 3 numbers.
Eigen::Vector3d Vector3FromJson(const nlohmann::json& value, const std::string& where, const std::string& path) {
  if (!value.is_array() || value.size() != 3) {
    Fail(where, path, "expected an array of 3 numbers, got " + Describe(value));
  }
  return {Number(value[0], where, Indexed(path, 0)), Number(value[1], where, Indexed(path, 1)),
          Number(value[2], where, Indexed(path, 2))};
}

Rigid3d RigidFromJson(const nlohmann::json& object, const std::string& where, const std::string& path) {
  ExpectFields(object, where, path, {"R", "t"});
  Rigid3d transform;
  const nlohmann::json& rows = object["R"];
  const std::string r_path = Field(path, "R");
  if (!rows.is_array() || rows.size() != 3) {
    Fail(where, r_path, "expected 3 rows of 3 numbers, got " + Describe(rows));
  }
  for (int i = 0; i < 3; ++i) transform.rotation.row(i) = Vector3FromJson(rows[i], where, Indexed(r_path, i));
  transform.translation = Vector3FromJson(object["t"], where, Field(path, "t"));
  return transform;
}

// StereoRig::Check names the offending field relative to the rig ("rig.right_from_left.R: not
// a rotation matrix"); re-root that name at `path` so that the error names the key as it is
// spelt in this file.
void CheckRig(const StereoRig& rig, const std::string& where, const std::string& path) {
  try {
    rig.Check();
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    const size_t colon = message.find(": ");
    if (colon != std::string::npos && message.compare(0, 3, "rig") == 0) {
      Fail(where, path + message.substr(3, colon - 3), message.substr(colon + 2));
    }
    Fail(where, path, message);
  }
}

LineObservation ObservationFromJson(const nlohmann::json& value, const std::string& where,
                                    const std::string& path) {
  if (!value.is_array() || value.size() != 5) {
    Fail(where, path, "expected [id, u1, v1, u2, v2], got " + Describe(value));
  }
  LineObservation observation;
  observation.id = Integer(value[0], where, path, "id: ");
  static const char* const kNames[4] = {"u1: ", "v1: ", "u2: ", "v2: "};
  for (int i = 0; i < 4; ++i) observation.segment[i] = Number(value[i + 1], where, path, kNames[i]);
  return observation;
}

std::vector<LineObservation> ImageFromJson(const nlohmann::json& value, const std::string& where,
                                           const std::string& path) {
  if (!value.is_array()) Fail(where, path, "expected an array of observations, got " + Describe(value));
  std::vector<LineObservation> observations;
  observations.reserve(value.size());
  for (size_t j = 0; j < value.size(); ++j) {
    observations.push_back(ObservationFromJson(value[j], where, Indexed(path, j)));
  }
  return observations;
}

void CheckImage(const std::vector<LineObservation>& observations, const std::string& where,
                const std::string& path) {
  std::unordered_map<std::int64_t, size_t> first_index;
  first_index.reserve(observations.size());
  for (size_t j = 0; j < observations.size(); ++j) {
    const LineObservation& o = observations[j];
    if (!o.segment.allFinite()) Fail(where, Indexed(path, j), "coordinates must be finite");
    // A segment with coincident endpoints defines no line.
    if (o.segment.head<2>() == o.segment.tail<2>()) Fail(where, Indexed(path, j), "segment has zero length");
    const auto [it, inserted] = first_index.emplace(o.id, j);
    if (!inserted) {
      Fail(where, Indexed(path, j),
           "duplicate id " + std::to_string(o.id) + " (also at " + Indexed(path, it->second) + ")");
    }
  }
}

// Frame k of a sequence: finite non-decreasing time (after *previous_time when given), valid
// images.
void CheckFrame(const StereoFrame& frame, size_t k, const double* previous_time, const std::string& where) {
  const std::string frame_path = Indexed("frames", k);
  if (!std::isfinite(frame.time)) Fail(where, frame_path + ".time", "must be finite");
  if (previous_time != nullptr && frame.time < *previous_time) {
    Fail(where, frame_path + ".time",
         nlohmann::json(frame.time).dump() + " is before the previous frame's time " +
             nlohmann::json(*previous_time).dump());
  }
  CheckImage(frame.left, where, frame_path + ".left");
  CheckImage(frame.right, where, frame_path + ".right");
}

StereoFrame FrameFromJson(const nlohmann::json& object, const std::string& where, size_t k) {
  const std::string path = Indexed("frames", k);
  ExpectFields(object, where, path, {"time", "left", "right"});
  StereoFrame frame;
  frame.time = Number(object["time"], where, path + ".time");
  frame.left = ImageFromJson(object["left"], where, path + ".left");
  frame.right = ImageFromJson(object["right"], where, path + ".right");
  return frame;
}

void CheckFormat(const nlohmann::json& format, const std::string& where) {
  if (format != kFormatName) {
    Fail(where, "format", std::string("expected \"") + kFormatName + "\", got " + Describe(format));
  }
}

// The shortest text that reads back to the same value (to_chars without a precision); valid
// JSON for finite numbers.
template <typename T>
void AppendNumber(T value, std::string* out) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, result.ptr);
}

void AppendImage(const std::vector<LineObservation>& observations, std::string* out) {
  if (observations.empty()) {
    *out += "[]";
    return;
  }
  *out += "[";
  for (size_t j = 0; j < observations.size(); ++j) {
    *out += j == 0 ? "\n      [" : ",\n      [";
    AppendNumber(observations[j].id, out);
    for (int i = 0; i < 4; ++i) {
      *out += ", ";
      AppendNumber(observations[j].segment[i], out);
    }
    *out += "]";
  }
  *out += "\n    ]";
}

}  // namespace

StereoRig StereoRigFromJson(const nlohmann::json& object, const std::string& where, const std::string& path) {
  ExpectFields(object, where, path, {"width", "height", "left", "right", "right_from_left"});
  StereoRig rig;
  rig.width = ImageSize(object["width"], where, Field(path, "width"));
  rig.height = ImageSize(object["height"], where, Field(path, "height"));
  rig.left = CameraFromJson(object["left"], where, Field(path, "left"));
  rig.right = CameraFromJson(object["right"], where, Field(path, "right"));
  rig.right_from_left = RigidFromJson(object["right_from_left"], where, Field(path, "right_from_left"));
  CheckRig(rig, where, path);
  return rig;
}

nlohmann::json StereoRigToJson(const StereoRig& rig) {
  const auto camera = [](const PinholeCamera& c) {
    return nlohmann::json{{"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}};
  };
  const Eigen::Matrix3d& r = rig.right_from_left.rotation;
  const Eigen::Vector3d& t = rig.right_from_left.translation;
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) rows.push_back({r(i, 0), r(i, 1), r(i, 2)});
  return {{"width", rig.width},
          {"height", rig.height},
          {"left", camera(rig.left)},
          {"right", camera(rig.right)},
          {"right_from_left", {{"R", rows}, {"t", {t.x(), t.y(), t.z()}}}}};
}

void CheckStereoSequence(const StereoSequence& sequence, const std::string& where) {
  CheckRig(sequence.rig, where, "rig");
  for (size_t k = 0; k < sequence.frames.size(); ++k) {
    CheckFrame(sequence.frames[k], k, k > 0 ? &sequence.frames[k - 1].time : nullptr, where);
  }
}

StereoSequence StereoLinesFromJson(const nlohmann::json& document, const std::string& where) {
  ExpectFields(document, where, "", {"format", "rig", "frames"});
  CheckFormat(document["format"], where);
  StereoSequence sequence;
  sequence.rig = StereoRigFromJson(document["rig"], where, "rig");
  const nlohmann::json& frames = document["frames"];
  if (!frames.is_array()) Fail(where, "frames", "expected an array of frames, got " + Describe(frames));

  sequence.frames.reserve(frames.size());
  for (size_t k = 0; k < frames.size(); ++k) sequence.frames.push_back(FrameFromJson(frames[k], where, k));
  CheckStereoSequence(sequence, where);
  return sequence;
}

StereoSequence ReadStereoLines(const std::string& path) { return StereoLinesFromJson(ReadJsonFile(path), path); }

// Splits the file into the values of its top-level keys and the elements of "frames", each
// parsed on its own (ParseJson: the same syntax errors and depth limit as the whole file).
class StereoLinesReader::Scanner {
 public:
  Scanner(std::ifstream in, std::string where) : in_(std::move(in)), buffer_(in_.rdbuf()), where_(std::move(where)) {}

  int Peek() { return buffer_->sgetc(); }
  int Get() {
    const int c = buffer_->sbumpc();
    if (c != kEnd) ++offset_;
    return c;
  }
  void SkipSpace() {
    for (int c = Peek(); c == ' ' || c == '\t' || c == '\n' || c == '\r'; c = Peek()) Get();
  }
  [[noreturn]] void Syntax(const std::string& what) const {
    throw ConfigError(where_ + ": invalid JSON (" + what + " at byte " + std::to_string(offset_) + ")");
  }
  // The next non-space character, consumed.
  int Next() {
    SkipSpace();
    return Get();
  }

  // Replaces *text with the text of the next value: a string, a scalar, or an object or array up
  // to its matching bracket (brackets inside strings skipped; mismatched kinds are left for the
  // parser to report).
  void ReadValue(std::string* text) {
    text->clear();
    SkipSpace();
    const int first = Peek();
    if (first == '"') {
      ReadString(text);
    } else if (first == '{' || first == '[') {
      std::size_t depth = 0;
      do {
        const int c = Get();
        if (c == kEnd) Syntax("unexpected end of input");
        if (c == '"') {
          text->push_back('"');
          ReadStringRest(text);
          continue;
        }
        text->push_back(static_cast<char>(c));
        if (c == '{' || c == '[') ++depth;
        if (c == '}' || c == ']') --depth;
      } while (depth > 0);
    } else {
      for (int c = Peek(); c != kEnd && std::strchr(",]} \t\r\n", c) == nullptr; c = Peek()) {
        text->push_back(static_cast<char>(Get()));
      }
      if (text->empty()) Syntax("expected a value");
    }
  }
  // A key and its ':'.
  std::string ReadKey() {
    SkipSpace();
    if (Peek() != '"') Syntax("expected a key");
    std::string text;
    ReadString(&text);
    if (Next() != ':') Syntax("expected ':'");
    return ParseJson(text, where_).get<std::string>();
  }

 private:
  static constexpr int kEnd = std::char_traits<char>::eof();

  void ReadString(std::string* text) {
    text->push_back(static_cast<char>(Get()));  // the opening quote
    ReadStringRest(text);
  }
  void ReadStringRest(std::string* text) {
    for (;;) {
      int c = Get();
      if (c == kEnd) Syntax("unterminated string");
      text->push_back(static_cast<char>(c));
      if (c == '"') return;
      if (c == '\\') {
        c = Get();
        if (c == kEnd) Syntax("unterminated string");
        text->push_back(static_cast<char>(c));
      }
    }
  }

  std::ifstream in_;
  std::streambuf* buffer_;
  std::string where_;
  std::size_t offset_ = 0;
};

StereoLinesReader::StereoLinesReader(const std::string& path) : path_(path) {
  std::ifstream in;
  try {
    in = OpenInputFile(path);
  } catch (const std::runtime_error& e) {
    throw ConfigError(e.what());
  }
  scanner_ = std::make_unique<Scanner>(std::move(in), path);
  Scanner& s = *scanner_;
  const auto read_whole = [&] {
    scanner_.reset();
    whole_ = ReadStereoLines(path);
    rig_ = whole_->rig;
  };
  s.SkipSpace();
  if (s.Peek() != '{') {  // not an object: ReadStereoLines says what it is
    read_whole();
    return;
  }
  s.Get();
  s.SkipSpace();
  if (s.Peek() == '}') {  // {}: every key missing
    read_whole();
    return;
  }
  bool have_format = false, have_rig = false;
  std::string text;
  for (;;) {
    const std::string key = s.ReadKey();
    if (key == "frames") {
      if (!have_format || !have_rig) {
        read_whole();
        return;
      }
      s.SkipSpace();
      if (s.Peek() != '[') {
        s.ReadValue(&text);
        Fail(path, "frames", "expected an array of frames, got " + Describe(ParseJson(text, path)));
      }
      s.Get();
      in_frames_ = true;
      return;
    }
    if (key != "format" && key != "rig") Fail(path, key, "unknown key");
    bool& have = key == "format" ? have_format : have_rig;
    if (have) Fail(path, key, "given twice");
    have = true;
    s.ReadValue(&text);
    const nlohmann::json value = ParseJson(text, path);
    if (key == "format") {
      CheckFormat(value, path);
    } else {
      rig_ = StereoRigFromJson(value, path, "rig");
    }
    const int c = s.Next();
    if (c == '}') Fail(path, !have_format ? "format" : !have_rig ? "rig" : "frames", "missing");
    if (c != ',') s.Syntax("expected ',' or '}'");
  }
}

StereoLinesReader::~StereoLinesReader() = default;

bool StereoLinesReader::Next(StereoFrame* frame) {
  if (whole_) {
    if (next_frame_ >= whole_->frames.size()) return false;
    *frame = whole_->frames[next_frame_++];
    return true;
  }
  if (!in_frames_) return false;
  Scanner& s = *scanner_;
  s.SkipSpace();
  if (next_frame_ == 0 && s.Peek() == ']') {
    s.Get();
    FinishObject();
    return false;
  }
  std::string text;
  s.ReadValue(&text);
  *frame = FrameFromJson(ParseJson(text, path_), path_, next_frame_);
  CheckFrame(*frame, next_frame_, next_frame_ > 0 ? &previous_time_ : nullptr, path_);
  previous_time_ = frame->time;
  ++next_frame_;
  const int c = s.Next();
  if (c == ',') return true;
  if (c != ']') s.Syntax("expected ',' or ']'");
  FinishObject();
  return true;
}

void StereoLinesReader::FinishObject() {
  // Every key was given before the frames: only the closing brace may follow.
  in_frames_ = false;
  Scanner& s = *scanner_;
  const int c = s.Next();
  if (c == ',') {
    const std::string key = s.ReadKey();
    Fail(path_, key, key == "format" || key == "rig" || key == "frames" ? "given twice" : "unknown key");
  }
  if (c != '}') s.Syntax("expected ',' or '}'");
  s.SkipSpace();
  if (s.Peek() != std::char_traits<char>::eof()) s.Syntax("unexpected text after the top-level object");
}

nlohmann::json StereoLinesToJson(const StereoSequence& sequence) {
  const auto image = [](const std::vector<LineObservation>& observations) {
    nlohmann::json list = nlohmann::json::array();
    for (const LineObservation& o : observations) {
      list.push_back({o.id, o.segment[0], o.segment[1], o.segment[2], o.segment[3]});
    }
    return list;
  };
  nlohmann::json frames = nlohmann::json::array();
  for (const StereoFrame& frame : sequence.frames) {
    frames.push_back({{"time", frame.time}, {"left", image(frame.left)}, {"right", image(frame.right)}});
  }
  return {{"format", kFormatName}, {"rig", StereoRigToJson(sequence.rig)}, {"frames", std::move(frames)}};
}

StereoLinesWriter::StereoLinesWriter(const std::string& path, const StereoRig& rig) {
  CheckRig(rig, path, "rig");
  file_ = std::make_unique<AtomicFileWriter>(path);
  // One rig field per line and one observation per line: readable in a pager, diffable, and a
  // fraction of the size of an indented dump (which puts every number on its own line).
  std::string text = std::string("{\n  \"format\": \"") + kFormatName + "\",\n  \"rig\": {";
  const nlohmann::json rig_json = StereoRigToJson(rig);
  for (auto it = rig_json.begin(); it != rig_json.end(); ++it) {
    text += it == rig_json.begin() ? "\n    \"" : ",\n    \"";
    text += it.key() + "\": " + it.value().dump();
  }
  text += "\n  },\n  \"frames\": [";
  file_->stream() << text;
}

StereoLinesWriter::~StereoLinesWriter() = default;

void StereoLinesWriter::Append(const StereoFrame& frame) {
  if (closed_) throw std::logic_error(file_->path() + ": frame appended after Close()");
  CheckFrame(frame, frames_, frames_ > 0 ? &previous_time_ : nullptr, file_->path());
  buffer_.clear();
  buffer_ += frames_ == 0 ? "\n    {\"time\": " : ",\n    {\"time\": ";
  AppendNumber(frame.time, &buffer_);
  buffer_ += ", \"left\": ";
  AppendImage(frame.left, &buffer_);
  buffer_ += ", \"right\": ";
  AppendImage(frame.right, &buffer_);
  buffer_ += "}";
  file_->stream() << buffer_;
  if (!file_->stream()) throw std::runtime_error(file_->path() + ": write failed");
  previous_time_ = frame.time;
  ++frames_;
}

void StereoLinesWriter::Close() {
  if (closed_) return;
  file_->stream() << (frames_ == 0 ? "]\n}\n" : "\n  ]\n}\n");
  file_->Commit();
  closed_ = true;
}

void WriteStereoLines(const std::string& path, const StereoSequence& sequence) {
  CheckStereoSequence(sequence, path);
  StereoLinesWriter writer(path, sequence.rig);
  for (const StereoFrame& frame : sequence.frames) writer.Append(frame);
  writer.Close();
}

}  // namespace slt
