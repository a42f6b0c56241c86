// The command-line programs end to end: simulate -> track -> evaluate, a sequence written by
// another program (hand-written file), and the one-line errors.
#include <gtest/gtest.h>

#include <algorithm>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <sys/stat.h>

#include "common/csv.h"
#include "common/json_reader.h"
#include "dataset/trajectory.h"

namespace slt {
namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string output;  // stdout and stderr
};

Result RunCommand(const std::string& command) {
  const std::string full = command + " 2>&1";
  FILE* pipe = popen(full.c_str(), "r");
  Result r{-1, ""};
  if (!pipe) return r;
  char buffer[4096];
  while (fgets(buffer, sizeof buffer, pipe)) r.output += buffer;
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string Bin(const std::string& name) { return std::string(SLT_BINARY_DIR) + "/" + name; }

class EndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("slt_e2e_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(EndToEnd, SimulateTrackEvaluate) {
  {
    std::ofstream(Path("sim.json")) << R"({"frames": 50, "noise": {"endpoint_px": 1.0}})";
  }
  Result r = RunCommand(Bin("simulate") + " " + Path("sim.json") + " --out " + Path("run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(Path("run/seq.json")));
  ASSERT_TRUE(fs::exists(Path("run/gt.tum")));

  for (const std::string method : {"trifocal_line_ekf", "constant_pose"}) {
    const std::string traj = Path("run/" + method + ".tum");
    r = RunCommand(Bin("track") + " --method " + method + " --input " + Path("run/seq.json") + " --output " + traj +
            " --kitti " + Path("run/" + method + ".kitti") + " --log " + Path("run/" + method + ".csv"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(ReadTumTrajectory(traj).size(), 50u);
    r = RunCommand(Bin("evaluate") + " --gt " + Path("run/gt.tum") + " --est " + traj + " --out " +
            Path("run/" + method + ".metrics.json"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json metrics = ReadJsonFile(Path("run/" + method + ".metrics.json"));
    const double final_rot = metrics.at("final_rot_err_deg").get<double>();
    if (method == "trifocal_line_ekf") {
      EXPECT_LT(final_rot, 0.3) << r.output;
      EXPECT_LT(metrics.at("ate_trans_m").at("rmse").get<double>(), 0.005);
    } else {
      EXPECT_GT(final_rot, 0.5) << "the trivial tracker should not be accurate on a moving camera";
    }
  }
}

TEST_F(EndToEnd, TracksAHandWrittenSequence) {
  const std::string input = std::string(SLT_SOURCE_DIR) + "/dataset/testdata/handwritten.stereo-lines.json";
  const Result r = RunCommand(Bin("track") + " --method trifocal_line_ekf --input " + input + " --output " + Path("t.tum"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Trajectory t = ReadTumTrajectory(Path("t.tum"));
  // One pose per frame, at the frame times of the file (0, 0.05, 0.05: a repeated time is kept),
  // the first the world (identity), all finite.
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].time, 0.0);
  EXPECT_EQ(t[1].time, 0.05);
  EXPECT_EQ(t[2].time, 0.05);
  EXPECT_LT((t[0].world_from_cam.ToMatrix4() - Eigen::Matrix4d::Identity()).norm(), 1e-9);
  for (const TimedPose& p : t) {
    EXPECT_TRUE(p.world_from_cam.translation.allFinite());
    EXPECT_TRUE(p.world_from_cam.rotation.allFinite());
  }
}

void ExpectOneErrorLine(const std::string& output) {
  EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
  EXPECT_EQ(output.rfind("track: error: ", 0), 0u) << output;
}

TEST_F(EndToEnd, ErrorsAreOneLineAndNameTheProblem) {
  Result r = RunCommand(Bin("track") + " --method no_such --input x.json --output y.tum");
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneErrorLine(r.output);
  EXPECT_NE(r.output.find("unknown method 'no_such'"), std::string::npos) << r.output;
  {
    std::ofstream(Path("bad.json")) << R"({"filter": {"max_iterations": 0}})";
  }
  r = RunCommand(Bin("track") + " --method trifocal_line_ekf --config " + Path("bad.json") + " --print-config");
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneErrorLine(r.output);
  EXPECT_NE(r.output.find(Path("bad.json") + ": key 'filter.max_iterations'"), std::string::npos) << r.output;
  r = RunCommand(Bin("track") + " --method trifocal_line_ekf --input " + Path("missing.json") + " --output " + Path("o.tum"));
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneErrorLine(r.output);
  EXPECT_NE(r.output.find("missing.json"), std::string::npos) << r.output;
  r = RunCommand(Bin("track") + " --bogus-flag");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = RunCommand(Bin("track") + " --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("--method"), std::string::npos);
}

// Outputs that would destroy an input, or that cannot be written, are refused before any work
// (issue 21): the input survives and no output is written.
TEST_F(EndToEnd, OutputsAreCheckedBeforeTracking) {
  const std::string source = std::string(SLT_SOURCE_DIR) + "/dataset/testdata/handwritten.stereo-lines.json";
  fs::copy_file(source, Path("seq.json"));
  const std::string original = ReadTextFile(Path("seq.json"));
  const std::string track = Bin("track") + " --method trifocal_line_ekf --input " + Path("seq.json");
  Result r = RunCommand(track + " --output " + Path("seq.json"));
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneErrorLine(r.output);
  EXPECT_NE(r.output.find("--output " + Path("seq.json") + ": is also an input"), std::string::npos) << r.output;
  EXPECT_EQ(ReadTextFile(Path("seq.json")), original);
  r = RunCommand(track + " --output " + Path("t.tum") + " --log " + Path("no/such/dir/log.csv"));
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneErrorLine(r.output);
  EXPECT_NE(r.output.find("--log " + Path("no/such/dir/log.csv") + ": cannot write"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(Path("t.tum"))) << "the TUM file was written before the --log error";
  r = RunCommand(track + " --output " + Path("t.tum") + " --kitti " + Path("t.tum"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--kitti " + Path("t.tum") + ": is also an input"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(Path("t.tum")));

  // A FIFO is written directly, not replaced by a regular file.
  ASSERT_EQ(::mkfifo(Path("pipe").c_str(), 0600), 0);
  r = RunCommand("(cat " + Path("pipe") + " > " + Path("from_pipe.tum") + " &) ; " + track + " --output " + Path("pipe"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::is_fifo(Path("pipe")));

  // evaluate: --out equal to --est is refused; metrics are never printed as null.
  r = RunCommand(track + " --output " + Path("t.tum"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string original_tum = ReadTextFile(Path("t.tum"));
  r = RunCommand(Bin("evaluate") + " --gt " + Path("t.tum") + " --est " + Path("t.tum") + " --out " + Path("t.tum"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--out " + Path("t.tum") + ": is also an input"), std::string::npos) << r.output;
  EXPECT_EQ(ReadTextFile(Path("t.tum")), original_tum);
  std::ofstream(Path("far.tum")) << "0 1e308 0 0 0 0 0 1\n0.05 1e308 0 0 0 0 0 1\n";
  r = RunCommand(Bin("evaluate") + " --gt " + Path("t.tum") + " --est " + Path("far.tum"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.output.find("null"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(Path("far.tum") + ":1: translation 1e+308 beyond"), std::string::npos) << r.output;
}

#ifdef SLT_HAS_BENCH_TABLE1
// A filter matching nothing wrote a table of "not run" cells over the measured one; an
// unwritable --out was noticed after minutes of benchmarks.
TEST_F(EndToEnd, BenchTable1RefusesEmptyRunsAndUnwritableOutputs) {
  std::ofstream(Path("table1.md")) << "measured\n";
  Result r = RunCommand(Bin("bench_table1") + " --benchmark_filter=no_such_benchmark --out " + dir_.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("bench_table1: error: --benchmark_filter matches no benchmark"), std::string::npos) << r.output;
  EXPECT_EQ(ReadTextFile(Path("table1.md")), "measured\n");
  // The filter would run a benchmark: the --out error must come first.
  std::ofstream(Path("file")) << "";
  r = RunCommand(Bin("bench_table1") + " --benchmark_filter=Table1/ --out " + Path("file/sub"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("bench_table1: error: --out " + Path("file/sub")), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("Table1/"), std::string::npos) << "benchmarks ran before the --out check: " << r.output;
}
#endif

}  // namespace
}  // namespace slt
