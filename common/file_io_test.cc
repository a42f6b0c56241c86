#include "common/file_io.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/csv.h"
#include "common/json_changes.h"

namespace slt {
namespace {

namespace fs = std::filesystem;

std::string TempDir(const std::string& name) {
  const std::string dir = std::string(::testing::TempDir()) + "slt_file_io_" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void Touch(const std::string& path) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << "x";
}

TEST(CheckReplaceableDirectory, RefusesADirectoryOfOtherFiles) {
  const std::string dir = TempDir("replaceable");
  const auto check = [&](const std::string& out) {
    return ErrorOf([&] { CheckReplaceableDirectory("--out", out, "run.json", "prog", "raw/shards"); });
  };
  EXPECT_EQ(check(dir + "/absent"), "");
  EXPECT_EQ(check(dir), "");  // empty
  Touch(dir + "/raw/shards/0-of-2/run.json");
  EXPECT_EQ(check(dir), "");  // nothing but the kept subfolder
  Touch(dir + "/raw/notes.txt");
  EXPECT_EQ(check(dir), "--out " + dir +
                            ": holds files no prog wrote (it has no run.json) and the run replaces the directory "
                            "whole; give a new or empty directory, or move those files out");
  Touch(dir + "/run.json");
  EXPECT_EQ(check(dir), "");  // an earlier output of the program
  EXPECT_EQ(check(dir + "/run.json"), "--out " + dir + "/run.json: exists and is not a directory");
  // Without a kept subfolder only an empty directory or an earlier output qualifies.
  const std::string viz = TempDir("replaceable_viz");
  Touch(viz + "/raw/shards/x");
  EXPECT_NE(ErrorOf([&] { CheckReplaceableDirectory("--viz", viz, "marker.csv", "prog"); }), "");
}

// track_images --viz over its own --output, run_experiment --merge --out over a shard: whatever
// lies in the replaced directory outside its kept subfolder, or is the directory, is refused.
TEST(RefusePathsInReplacedDirectory, RefusesWhatTheReplacementWouldDelete) {
  const std::string dir = TempDir("refuse_within");
  const auto check = [&](const std::string& path) {
    return ErrorOf([&] { RefusePathsInReplacedDirectory("--viz", dir + "/out", {{"--output", path}}, "raw/shards"); });
  };
  EXPECT_EQ(check(dir + "/out/traj.tum"),
            "--viz " + dir + "/out: holds --output " + dir + "/out/traj.tum, which the run would delete (it replaces "
            "the directory whole, keeping only raw/shards/)");
  EXPECT_NE(check(dir + "/out"), "");
  EXPECT_NE(check(dir + "/out/./a/../b/c.tum"), "");  // a path given unnormalised
  EXPECT_NE(check(dir + "/out/raw/x.tum"), "");
  EXPECT_EQ(check(dir + "/out/raw/shards/0-of-2"), "");  // the kept subfolder moves into the new one
  EXPECT_EQ(check(dir + "/outside.tum"), "");
  EXPECT_EQ(check(dir + "/out2/traj.tum"), "");  // a sibling with the same prefix
  EXPECT_EQ(check(""), "");
  // Through a symbolic link to the directory.
  fs::create_directories(dir + "/out");
  fs::create_directory_symlink(dir + "/out", dir + "/link");
  EXPECT_NE(check(dir + "/link/traj.tum"), "");
  // A link inside pointing out: an output renamed over it would land inside; a link outside
  // pointing in: an input read through it lies inside.
  fs::create_symlink(dir + "/outside.tum", dir + "/out/away.tum");
  EXPECT_NE(check(dir + "/out/away.tum"), "");
  Touch(dir + "/out/data.tum");
  fs::create_symlink(dir + "/out/data.tum", dir + "/in.tum");
  EXPECT_NE(check(dir + "/in.tum"), "");
  // Without a kept subfolder the message names none.
  EXPECT_EQ(ErrorOf([&] { RefusePathsInReplacedDirectory("--viz", dir + "/out", {{"--log", dir + "/out/l.csv"}}); }),
            "--viz " + dir + "/out: holds --log " + dir + "/out/l.csv, which the run would delete (it replaces the "
            "directory whole)");
}

// `track_images -o traj.tum --viz viz` run in the folder of both: paths without a folder are
// in the working directory (the parent of a bare name is empty; this threw before).
TEST(RefusePathsInReplacedDirectory, TakesBareNamesInTheWorkingDirectory) {
  const std::string dir = TempDir("refuse_bare");
  const fs::path previous = fs::current_path();
  fs::current_path(dir);
  const auto check = [&](const std::string& viz, const std::string& path) {
    return ErrorOf([&] { RefusePathsInReplacedDirectory("--viz", viz, {{"--output", path}}); });
  };
  const std::string traj_in_viz = check("viz", "viz/traj.tum"), traj_beside = check("viz", "traj.tum"),
                    viz_is_output = check("viz", "viz"), cwd_as_viz = check(".", "traj.tum");
  fs::current_path(previous);
  EXPECT_EQ(traj_beside, "");
  EXPECT_EQ(traj_in_viz, "--viz viz: holds --output viz/traj.tum, which the run would delete (it replaces the "
                         "directory whole)");
  EXPECT_NE(viz_is_output, "");
  EXPECT_NE(cwd_as_viz, "");
}

TEST(FreshStagingDir, EmptiesWhatAnInterruptedRunLeft) {
  const std::string dir = TempDir("fresh_staging") + "/out";
  Touch(StagingDir(dir) + "/stale/file.txt");
  EXPECT_EQ(FreshStagingDir(dir), StagingDir(dir));
  EXPECT_TRUE(fs::is_directory(StagingDir(dir)));
  EXPECT_TRUE(fs::is_empty(StagingDir(dir)));
}

TEST(ReplaceDirectory, CarriesTheKeptSubfolderOver) {
  const std::string dir = TempDir("replace_kept"), staging = StagingDir(dir);
  Touch(dir + "/old.txt");
  Touch(dir + "/raw/shards/0-of-2/run.json");
  fs::remove_all(staging);
  Touch(staging + "/new.txt");
  ReplaceDirectory(staging, dir, "raw/shards");
  EXPECT_TRUE(fs::exists(dir + "/new.txt"));
  EXPECT_TRUE(fs::exists(dir + "/raw/shards/0-of-2/run.json"));
  EXPECT_FALSE(fs::exists(dir + "/old.txt"));
  EXPECT_FALSE(fs::exists(staging));
}

TEST(OpenInputFile, ErrorsNameTheFile) {
  const std::string dir = TempDir("open");
  EXPECT_EQ(ErrorOf([&] { OpenInputFile(dir); }), dir + ": is a directory, expected a file");
  EXPECT_EQ(ErrorOf([&] { OpenInputFile(dir + "/absent"); }),
            dir + "/absent: cannot open file (No such file or directory)");
}

TEST(SamePath, LinksAndSpellings) {
  const std::string dir = TempDir("same");
  const std::string a = dir + "/a.txt";
  std::ofstream(a) << "x";
  fs::create_symlink(a, dir + "/link.txt");
  EXPECT_TRUE(SamePath(a, dir + "/./a.txt"));
  EXPECT_TRUE(SamePath(a, dir + "/link.txt"));
  EXPECT_TRUE(SamePath(dir + "/new.txt", dir + "/../" + fs::path(dir).filename().string() + "/new.txt"));
  EXPECT_FALSE(SamePath(a, dir + "/new.txt"));
  EXPECT_FALSE(SamePath(a, ""));
  EXPECT_EQ(ErrorOf([&] { RefuseOutputThatIsInput("--output", dir + "/link.txt", {"", a}); }),
            "--output " + dir + "/link.txt: is also an input (" + a + "); refusing to overwrite it");
  EXPECT_EQ(ErrorOf([&] { RefuseOutputThatIsInput("--output", dir + "/b.txt", {a}); }), "");
}

TEST(CheckWritable, RefusesUnwritablePathsAndLeavesNoFile) {
  const std::string dir = TempDir("writable");
  EXPECT_EQ(ErrorOf([&] { CheckWritable("--log", dir + "/new.csv"); }), "");
  EXPECT_FALSE(fs::exists(dir + "/new.csv"));
  EXPECT_EQ(ErrorOf([&] { CheckWritable("--log", dir + "/no/such/dir.csv"); }),
            "--log " + dir + "/no/such/dir.csv: cannot write (No such file or directory)");
  EXPECT_EQ(ErrorOf([&] { CheckWritable("--log", dir); }), "--log " + dir + ": is a directory, expected a file");
  // A FIFO is not opened (with no reader that would block; with one it would end its input).
  ASSERT_EQ(::mkfifo((dir + "/pipe").c_str(), 0600), 0);
  EXPECT_EQ(ErrorOf([&] { CheckWritable("--log", dir + "/pipe"); }), "");
}

// A streamed output appears whole at Commit(), replacing the old file only then; a writer
// destroyed without Commit() leaves the old file and no temporary one.
TEST(AtomicFileWriter, PutsTheFileInPlaceWholeAtCommitOrNotAtAll) {
  const std::string dir = TempDir("atomic");
  const std::string out = dir + "/log.csv", tmp = out + ".tmp." + std::to_string(::getpid());
  WriteTextFileAtomically(out, "old\n");
  {
    AtomicFileWriter file(out);
    file.stream() << "a,b\n";
    file.stream().flush();
    EXPECT_TRUE(fs::exists(tmp));
    EXPECT_EQ(ReadTextFile(out), "old\n");
    file.stream() << "1,2\n";
    file.Commit();
    EXPECT_FALSE(fs::exists(tmp));
    EXPECT_EQ(ReadTextFile(out), "a,b\n1,2\n");
  }
  EXPECT_EQ(ReadTextFile(out), "a,b\n1,2\n");
  {
    AtomicFileWriter abandoned(out);
    abandoned.stream() << "half";
    abandoned.stream().flush();
    EXPECT_TRUE(fs::exists(tmp));
  }
  EXPECT_FALSE(fs::exists(tmp));
  EXPECT_EQ(ReadTextFile(out), "a,b\n1,2\n");
  EXPECT_EQ(ErrorOf([&] { AtomicFileWriter file(dir); }), dir + ": is a directory, expected a file");
  EXPECT_NE(ErrorOf([&] { AtomicFileWriter file(dir + "/no_such_dir/x.csv"); }).find(dir + "/no_such_dir/x.csv: cannot write file ("),
            std::string::npos);
}

// Renaming a temporary file over a FIFO (or /dev/null) would replace it with a regular file.
TEST(WriteTextFileAtomically, WritesFifosDirectly) {
  const std::string dir = TempDir("fifo");
  const std::string fifo = dir + "/pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    WriteTextFileAtomically(fifo, "through the pipe\n");
    ::_exit(0);
  }
  {
    std::ifstream in(fifo);
    std::ostringstream s;
    s << in.rdbuf();
    received = s.str();
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_EQ(received, "through the pipe\n");
  struct stat info {};
  ASSERT_EQ(::stat(fifo.c_str(), &info), 0);
  EXPECT_TRUE(S_ISFIFO(info.st_mode));
  EXPECT_EQ(ErrorOf([&] { WriteTextFileAtomically(dir, "x"); }), dir + ": is a directory, expected a file");
}

TEST(WriteTextFileAtomically, WritesDevicesDirectly) {
  if (::access("/dev/null", W_OK) != 0) GTEST_SKIP() << "/dev/null not writable";
  WriteTextFileAtomically("/dev/null", "discarded\n");
  struct stat info {};
  ASSERT_EQ(::stat("/dev/null", &info), 0);
  EXPECT_TRUE(S_ISCHR(info.st_mode));
}

// A writer stopped by SIGTERM while its temporary file exists leaves nothing behind.
TEST(InstallTemporaryFileCleanup, RemovesTemporaryFilesOnSigterm) {
  const std::string dir = TempDir("signal");
  const std::string out = dir + "/out.txt";
  // The child rewrites a large file until it is killed; the parent waits for its temporary file.
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    InstallTemporaryFileCleanup();
    const std::string big(16 << 20, 'x');
    for (;;) WriteTextFileAtomically(out, big);
  }
  const std::string tmp = out + ".tmp." + std::to_string(child);
  for (int i = 0; i < 2000 && !fs::exists(tmp); ++i) ::usleep(1000);
  ASSERT_TRUE(fs::exists(tmp));
  ::kill(child, SIGTERM);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  EXPECT_FALSE(fs::exists(tmp));
}

}  // namespace
}  // namespace slt
