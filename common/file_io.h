// Opening input files and writing output files, the same way in every program.
//
// Every input error names the file ("<path>: is a directory"); every output is written whole or
// not at all (temporary file + rename) unless it is a device or a FIFO, which is written directly
// (renaming over /dev/null would replace the device with a regular file); and no program
// overwrites one of its inputs. Temporary files in flight are removed when the program is
// stopped by SIGINT or SIGTERM (InstallTemporaryFileCleanup).
#pragma once

#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace slt {

// Opens `path` for reading (binary). Throws std::runtime_error "<path>: cannot open file (<why>)"
// or "<path>: is a directory, expected a file".
std::ifstream OpenInputFile(const std::string& path);

// True when `a` and `b` name the same file or directory: the same inode when both exist (hard and
// symbolic links included), the same normalised absolute path otherwise.
bool SamePath(const std::string& a, const std::string& b);

// Throws std::runtime_error "<what> <output>: is also an input (<input>); refusing to overwrite
// it" when `output` is one of `inputs` (empty paths are ignored).
void RefuseOutputThatIsInput(const std::string& what, const std::string& output,
                             const std::vector<std::string>& inputs);

// Checks that `path` can be written before any work is done: creates it when absent (removed
// again at once), opens a regular file for appending (nothing written), checks the permission
// of a device or FIFO. Throws std::runtime_error "<what> <path>: cannot write (<why>)".
void CheckWritable(const std::string& what, const std::string& path);

// A program's outputs checked before its (possibly long) work: none may be one of `inputs` or
// another output (RefuseOutputThatIsInput), and each must be writable (CheckWritable). `outputs`
// are (flag, path) pairs; empty paths are skipped.
void CheckOutputsBeforeWork(const std::vector<std::pair<std::string, std::string>>& outputs,
                            std::vector<std::string> inputs);

// dir/file, as a string.
std::string JoinPath(const std::string& dir, const std::string& file);
// Creates `dir` and its parents when absent. Throws std::runtime_error "<dir>: cannot create
// directory (<why>)".
void CreateDirectories(const std::string& dir);
// An output directory is written whole or not at all, like a file: everything goes into
// StagingDir(dir) ("<dir>.partial", trailing slashes dropped), which ReplaceDirectory then
// renames to `dir`; the old `dir`, if any, is moved aside first and removed last, except its
// subfolder `kept` (a relative path, "" = none), which moves into the new one (run_experiment
// keeps other runs' shards, raw/shards). Throws std::runtime_error naming both directories when
// a rename fails.
std::string StagingDir(const std::string& dir);
void ReplaceDirectory(const std::string& staging, const std::string& dir, const std::string& kept = "");
// StagingDir(dir), emptied of what an interrupted run left there and created: where the program
// then writes what ReplaceDirectory swaps in. Throws std::runtime_error naming it.
std::string FreshStagingDir(const std::string& dir);
// Before the work: a directory that `program` will replace whole must not hold files a user put
// there, which would go with it. It may be absent, or a directory that holds `marker` (a file
// the program writes into every such directory: an earlier output of its own), nothing, or
// nothing but `kept`. Otherwise throws std::runtime_error "<what> <dir>: ..." saying why.
void CheckReplaceableDirectory(const std::string& what, const std::string& dir, const std::string& marker,
                               const std::string& program, const std::string& kept = "");
// Before the work, too: none of `paths` ((flag, path) pairs, empty paths skipped: the program's
// inputs and its other outputs) may be `dir` or lie in it outside its subfolder `kept` ("" =
// none), through links or not, since replacing `dir` would take them with it. Throws
// std::runtime_error "<what> <dir>: holds <flag> <path>, which the run would delete (it replaces
// the directory whole[, keeping only <kept>/])".
void RefusePathsInReplacedDirectory(const std::string& what, const std::string& dir,
                                    const std::vector<std::pair<std::string, std::string>>& paths,
                                    const std::string& kept = "");
// An output file written as a stream and put in place whole: a regular (or absent) file is
// written to "<path>.tmp.<pid>" and renamed to `path` by Commit(), so readers never see a
// half-written file and a run that fails leaves none (the destructor removes an uncommitted
// temporary file, and so does InstallTemporaryFileCleanup's handler on SIGINT and SIGTERM); an
// existing device or FIFO is written directly. For outputs that grow with the run (logs,
// observations), which are then never held in memory. Throws std::runtime_error naming `path`.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(const std::string& path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  std::ostream& stream() { return out_; }
  const std::string& path() const { return path_; }
  // Flushes and renames into place; throws if a write failed (the temporary file is removed).
  void Commit();

 private:
  std::string path_, tmp_;  // tmp_ empty: a device or FIFO, written directly
  std::ofstream out_;
  int slot_ = -1;  // its slot for the signal handler
  bool committed_ = false;
};

// Writes `contents` to `path` at once (AtomicFileWriter).
void WriteTextFileAtomically(const std::string& path, const std::string& contents);

// On SIGINT and SIGTERM, removes the temporary files AtomicFileWriter has in flight, then
// dies of the signal as it would have without the handler. Idempotent.
void InstallTemporaryFileCleanup();

}  // namespace slt
