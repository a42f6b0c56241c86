#include "common/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace slt {
namespace {

namespace fs = std::filesystem;

// `path` absolute and normalised, links resolved as far as they exist; as written (absolute,
// normalised) when it cannot be resolved (a component without permission). An empty path is
// the working directory: the parent of a bare file name (fs::absolute throws on "").
fs::path ResolvedPath(const fs::path& path) {
  const fs::path given = path.empty() ? fs::path(".") : path;
  std::error_code error;
  const fs::path resolved = fs::weakly_canonical(fs::absolute(given), error);
  return error ? fs::absolute(given).lexically_normal() : resolved;
}

// Temporary files in flight, for the signal handler: it may only read these pointers and call
// unlink(), both async-signal-safe. A writer claims a free slot (nullptr) for the lifetime of
// its temporary name.
constexpr int kTemporarySlots = 64;
std::atomic<const char*> g_temporary_files[kTemporarySlots];

// The slot claimed for `path` (whose characters must outlive the claim), or -1 when all are in
// use (the file is then not removed on a signal).
int ClaimTemporarySlot(const std::string& path) {
  for (int i = 0; i < kTemporarySlots; ++i) {
    const char* expected = nullptr;
    if (g_temporary_files[i].compare_exchange_strong(expected, path.c_str())) return i;
  }
  return -1;
}

void ReleaseTemporarySlot(int slot) {
  if (slot >= 0) g_temporary_files[slot].store(nullptr);
}

extern "C" void RemoveTemporaryFilesAndDie(int signal_number) {
  for (auto& slot : g_temporary_files) {
    const char* path = slot.load();
    if (path != nullptr) ::unlink(path);
  }
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

std::string ErrnoText() { return std::strerror(errno); }

}  // namespace

std::ifstream OpenInputFile(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) throw std::runtime_error(path + ": is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open file (" + ErrnoText() + ")");
  return in;
}

bool SamePath(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error)) {
    const bool same = fs::equivalent(a, b, error);
    if (!error) return same;
  }
  return ResolvedPath(a) == ResolvedPath(b);
}

void RefuseOutputThatIsInput(const std::string& what, const std::string& output,
                             const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs) {
    if (SamePath(output, input)) {
      throw std::runtime_error(what + " " + output + ": is also an input (" + input + "); refusing to overwrite it");
    }
  }
}

void CheckOutputsBeforeWork(const std::vector<std::pair<std::string, std::string>>& outputs,
                            std::vector<std::string> inputs) {
  for (const auto& [flag, path] : outputs) {
    if (path.empty()) continue;
    RefuseOutputThatIsInput(flag, path, inputs);
    CheckWritable(flag, path);
    inputs.push_back(path);
  }
}

void CheckWritable(const std::string& what, const std::string& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (fs::is_directory(status)) throw std::runtime_error(what + " " + path + ": is a directory, expected a file");
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    // A device or a FIFO: opening a FIFO and closing it again would end its reader's input.
    if (::access(path.c_str(), W_OK) != 0) {
      throw std::runtime_error(what + " " + path + ": cannot write (" + ErrnoText() + ")");
    }
    return;
  }
  const bool existed = fs::exists(status);
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT, 0666);
  if (fd < 0) throw std::runtime_error(what + " " + path + ": cannot write (" + ErrnoText() + ")");
  ::close(fd);
  if (!existed) ::unlink(path.c_str());
}

std::string JoinPath(const std::string& dir, const std::string& file) { return (fs::path(dir) / file).string(); }

void CreateDirectories(const std::string& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw std::runtime_error(dir + ": cannot create directory (" + error.message() + ")");
}

std::string StagingDir(const std::string& dir) {
  std::string staging = fs::path(dir).lexically_normal().string();
  while (staging.size() > 1 && staging.back() == '/') staging.pop_back();
  return staging + ".partial";
}

std::string FreshStagingDir(const std::string& dir) {
  const std::string staging = StagingDir(dir);
  std::error_code error;
  fs::remove_all(staging, error);
  if (error) throw std::runtime_error(staging + ": cannot remove an earlier run's files (" + error.message() + ")");
  CreateDirectories(staging);
  return staging;
}

namespace {

// True when `dir` holds nothing, or nothing but the relative path `kept`.
bool HoldsOnly(const fs::path& dir, const fs::path& kept) {
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    if (kept.empty() || entry.path().filename() != *kept.begin() || !entry.is_directory()) return false;
    const fs::path rest = kept.lexically_relative(*kept.begin());
    if (rest != "." && !HoldsOnly(entry.path(), rest)) return false;
  }
  return true;
}

}  // namespace

void CheckReplaceableDirectory(const std::string& what, const std::string& dir, const std::string& marker,
                               const std::string& program, const std::string& kept) {
  std::error_code error;
  if (!fs::exists(dir, error)) return;
  if (!fs::is_directory(dir, error)) throw std::runtime_error(what + " " + dir + ": exists and is not a directory");
  if (!fs::exists(fs::path(dir) / marker, error) && !HoldsOnly(dir, kept)) {
    throw std::runtime_error(what + " " + dir + ": holds files no " + program + " wrote (it has no " + marker +
                             ") and the run replaces the directory whole; give a new or empty directory, or move "
                             "those files out");
  }
}

void RefusePathsInReplacedDirectory(const std::string& what, const std::string& dir,
                                    const std::vector<std::pair<std::string, std::string>>& paths,
                                    const std::string& kept) {
  const fs::path root = ResolvedPath(dir);
  const auto within = [&](const fs::path& path) {
    const auto in = [](const fs::path& p, const fs::path& folder) {
      const fs::path relative = p.lexically_relative(folder);
      return !relative.empty() && *relative.begin() != "..";
    };
    return in(path, root) && (kept.empty() || !in(path, root / kept));
  };
  for (const auto& [flag, path] : paths) {
    if (path.empty()) continue;
    // Where the file is (an input read through a link) and where a new file of that name lands
    // (an output renamed over a link replaces the link): either inside is refused.
    const fs::path full = ResolvedPath(path), named = ResolvedPath(fs::path(path).parent_path()) / fs::path(path).filename();
    if (within(full) || within(named)) {
      throw std::runtime_error(what + " " + dir + ": holds " + flag + " " + path +
                               ", which the run would delete (it replaces the directory whole" +
                               (kept.empty() ? "" : ", keeping only " + kept + "/") + ")");
    }
  }
}

void ReplaceDirectory(const std::string& staging, const std::string& dir, const std::string& kept) {
  std::error_code error;
  const fs::path kept_path = fs::path(dir) / kept;
  if (!kept.empty() && fs::exists(kept_path, error)) {
    const fs::path target = fs::path(staging) / kept;
    CreateDirectories(target.parent_path().string());
    fs::rename(kept_path, target, error);
    if (error) throw std::runtime_error(kept_path.string() + ": cannot move into " + staging + " (" + error.message() + ")");
  }
  const bool replaces = fs::exists(dir, error);
  const std::string old = dir + ".old." + std::to_string(::getpid());
  if (replaces) {
    fs::rename(dir, old, error);
    if (error) throw std::runtime_error(dir + ": cannot move aside (" + error.message() + "); the new one is in " + staging);
  }
  fs::rename(staging, dir, error);
  if (error) throw std::runtime_error(staging + ": cannot move to " + dir + " (" + error.message() + ")");
  if (replaces) fs::remove_all(old, error);
}

AtomicFileWriter::AtomicFileWriter(const std::string& path) : path_(path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (fs::is_directory(status)) throw std::runtime_error(path + ": is a directory, expected a file");
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    // A device or a FIFO: renaming over it would replace it with a regular file.
    out_.open(path, std::ios::binary);
    if (!out_) throw std::runtime_error(path + ": cannot write file (" + ErrnoText() + ")");
    return;
  }
  tmp_ = path + ".tmp." + std::to_string(::getpid());
  slot_ = ClaimTemporarySlot(tmp_);
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    const std::string why = ErrnoText();
    ReleaseTemporarySlot(slot_);
    throw std::runtime_error(path + ": cannot write file (" + why + ")");
  }
}

AtomicFileWriter::~AtomicFileWriter() {
  if (committed_ || tmp_.empty()) return;
  out_.close();
  std::remove(tmp_.c_str());
  ReleaseTemporarySlot(slot_);
}

void AtomicFileWriter::Commit() {
  if (committed_) return;
  out_.flush();
  if (!out_) throw std::runtime_error(path_ + ": write failed");
  out_.close();
  committed_ = true;
  if (tmp_.empty()) return;
  const bool moved = std::rename(tmp_.c_str(), path_.c_str()) == 0;
  if (!moved) std::remove(tmp_.c_str());
  ReleaseTemporarySlot(slot_);
  if (!moved) throw std::runtime_error(path_ + ": cannot move the written file into place");
}

void WriteTextFileAtomically(const std::string& path, const std::string& contents) {
  AtomicFileWriter file(path);
  file.stream() << contents;
  file.Commit();
}

void InstallTemporaryFileCleanup() {
  struct sigaction action {};
  action.sa_handler = RemoveTemporaryFilesAndDie;
  sigemptyset(&action.sa_mask);
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);
}

}  // namespace slt
