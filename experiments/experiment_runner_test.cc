#include "experiments/experiment_runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "common/json_reader.h"
#include "common/random.h"
#include "common/csv.h"
#include "experiments/experiment_driver.h"

namespace slt {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A small experiment: two methods (one with a comma in its label), a 2 x 2 grid, 3 trials of
// 25 frames, curves and one saved trajectory.
ExperimentConfig TinyConfig() {
  return ExperimentConfigFromJson(
      {{"name", "tiny"},
       {"trials", 3},
       {"seed", 3},
       {"simulation", {{"frames", 25}}},
       {"sweep",
        {{{"parameter", "noise.endpoint_px"}, {"values", {0.5, 2}}}, {{"parameter", "max_features"}, {"values", {8, 20}}}}},
       {"methods", {"trifocal_line_ekf", {{"name", "trifocal_line_ekf"}, {"label", "EKF, paper"}, {"options", {{"preset", "paper"}}}}}},
       {"metrics_frame", 20},
       {"per_frame_curves", true},
       {"save_trajectories", 1}},
      "tiny.json");
}

std::string TempDir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("slt_experiments_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

// The CSV without the columns that measure time.
std::vector<std::vector<std::string>> WithoutTiming(const CsvTable& table) {
  std::vector<bool> keep;
  for (const std::string& h : table.header) keep.push_back(h.rfind("time_mean_us", 0) != 0 && h.rfind("time_median_us", 0) != 0);
  std::vector<std::vector<std::string>> out;
  for (const auto& source : std::vector<std::vector<std::string>>{table.header}) {
    std::vector<std::string> row;
    for (size_t i = 0; i < source.size(); ++i)
      if (keep[i]) row.push_back(source[i]);
    out.push_back(row);
  }
  for (const auto& source : table.rows) {
    std::vector<std::string> row;
    for (size_t i = 0; i < source.size(); ++i)
      if (keep[i]) row.push_back(source[i]);
    out.push_back(row);
  }
  return out;
}

TEST(Jobs, IndexIsMethodMajorThenPointThenTrial) {
  const ExperimentConfig c = TinyConfig();
  const std::vector<Job> jobs = ExperimentJobs(c);
  ASSERT_EQ(jobs.size(), 2u * 4u * 3u);
  for (size_t i = 0; i < jobs.size(); ++i) {
    EXPECT_EQ(jobs[i].index, i);
    EXPECT_EQ((jobs[i].method * 4 + jobs[i].point) * 3 + static_cast<size_t>(jobs[i].trial), i);
  }
}

TEST(Jobs, ParseShard) {
  const Shard s = ParseShard("1/4");
  EXPECT_EQ(s.index, 1);
  EXPECT_EQ(s.count, 4);
  EXPECT_TRUE(s.Contains(5));
  EXPECT_FALSE(s.Contains(4));
  for (const char* bad : {"4/4", "-1/2", "1", "a/b", "1/0", "1/2x", ""}) EXPECT_THROW(ParseShard(bad), std::invalid_argument) << bad;
}

TEST(Runner, SameSeedForEverySweepValueAndMethod) {
  const ExperimentConfig c = TinyConfig();
  RunOptions options;
  options.threads = 2;
  const ExperimentRun run = RunExperiment(c, options);
  ASSERT_EQ(run.trials.size(), 24u);
  for (const TrialResult& t : run.trials) {
    EXPECT_EQ(t.seed, TrialSeed(3, static_cast<std::uint64_t>(t.trial)));
    EXPECT_EQ(t.frames, 25);
    EXPECT_EQ(t.metrics_frame, 20);
    EXPECT_TRUE(t.finite);
    EXPECT_EQ(t.curve.size(), 25u);
    EXPECT_EQ(!t.estimate.empty(), t.trial == 0);
  }
  // Same trial, same scene and motion: the ground-truth path length does not depend on the
  // noise level, the line count or the method.
  for (const TrialResult& t : run.trials) {
    EXPECT_EQ(t.metrics[kPathLengthM], run.trials[static_cast<size_t>(t.trial)].metrics[kPathLengthM]);
  }
  EXPECT_NE(run.trials[0].metrics[kPathLengthM], run.trials[1].metrics[kPathLengthM]);
  // More noise, larger error (means over the trials of the default EKF at 20 lines).
  double low = 0, high = 0;
  for (const TrialResult& t : run.trials) {
    if (t.method_index == 0 && t.point_index == 1) low += t.metrics[kRotErrDeg];
    if (t.method_index == 0 && t.point_index == 3) high += t.metrics[kRotErrDeg];
  }
  EXPECT_LT(low, high);
}

TEST(Runner, CountsWhyFramesWereLostOrTookANewReference) {
  // The paper preset at 8 lines loses frames and takes new reference pairs; every one of them is
  // counted under exactly one reason, and the features left out are counted per frame.
  const ExperimentConfig c = TinyConfig();
  const ExperimentRun run = RunExperiment(c, RunOptions());
  double new_references = 0, left_out = 0;
  for (const TrialResult& t : run.trials) {
    const auto& m = t.metrics;
    EXPECT_EQ(m[kLostFrames], m[kLostFewMeasurable] + m[kLostFewInsideGate] + m[kLostNoUpdate] + m[kLostNonFinite] +
                                 m[kLostUnconstrained] + m[kLostFewAgree]);
    EXPECT_EQ(m[kNewReferences], m[kNewRefFewFeatures] + m[kNewRefFeatureFraction]);
    EXPECT_GE(m[kFeaturesUnmatched], 0.0);
    EXPECT_GE(m[kFeaturesDegenerate], 0.0);
    EXPECT_LE(m[kFeaturesUsed] + m[kFeaturesOutsideGate], m[kFeaturesAvailable]);
    new_references += m[kNewReferences];
    left_out += m[kFeaturesUnmatched] + m[kFeaturesOutsideGate];
  }
  EXPECT_GT(new_references, 0.0);
  EXPECT_GT(left_out, 0.0);
}

TEST(Runner, RawResultsDoNotDependOnTheThreadCount) {
  const ExperimentConfig c = TinyConfig();
  DriverOptions one, two;
  one.out_dir = TempDir("threads1");
  one.run.threads = 1;
  two.out_dir = TempDir("threads2");
  two.run.threads = 2;
  RunAndWrite(c, one);
  RunAndWrite(c, two);
  for (const char* file : {"raw/trials.csv", "raw/curves.csv", "summary.csv", "curves.csv"}) {
    EXPECT_EQ(WithoutTiming(ReadCsvFile(one.out_dir + "/" + file)), WithoutTiming(ReadCsvFile(two.out_dir + "/" + file)))
        << file;
  }
  EXPECT_EQ(ReadTextFile(one.out_dir + "/raw/trajectories/m1_p2_t0.tum"),
            ReadTextFile(two.out_dir + "/raw/trajectories/m1_p2_t0.tum"));
  // The timing columns are there and positive.
  const CsvTable trials = ReadCsvFile(one.out_dir + "/raw/trials.csv");
  EXPECT_GT(ParseDouble(trials.rows[0][trials.Column("time_mean_us")]), 0.0);
}

TEST(Runner, ShardsMergedEqualTheWholeRun) {
  const ExperimentConfig c = TinyConfig();
  DriverOptions whole;
  whole.out_dir = TempDir("whole");
  RunAndWrite(c, whole);
  std::vector<std::string> shard_dirs;
  for (int i = 0; i < 3; ++i) {
    DriverOptions shard;
    shard.out_dir = TempDir("shard" + std::to_string(i));
    shard.run.shard = ParseShard(std::to_string(i) + "/3");
    shard.run.threads = 1;
    const ExperimentRun run = RunAndWrite(c, shard);
    EXPECT_EQ(run.trials.size(), 8u);
    EXPECT_FALSE(fs::exists(shard.out_dir + "/summary.csv"));  // partial: no summary
    EXPECT_EQ(ReadJsonFile(shard.out_dir + "/run.json")["shard"]["count"], 3);
    shard_dirs.push_back(shard.out_dir);
  }
  DriverOptions merged;
  merged.out_dir = TempDir("merged");
  // Any order of the shard directories.
  MergeAndWrite({shard_dirs[2], shard_dirs[0], shard_dirs[1]}, merged);
  for (const char* file : {"raw/trials.csv", "raw/curves.csv", "summary.csv", "curves.csv", "raw/trajectories/index.csv"}) {
    EXPECT_EQ(WithoutTiming(ReadCsvFile(whole.out_dir + "/" + file)), WithoutTiming(ReadCsvFile(merged.out_dir + "/" + file)))
        << file;
  }
  EXPECT_EQ(ReadJsonFile(merged.out_dir + "/run.json")["merged_from"].size(), 3u);
  EXPECT_EQ(ReadJsonFile(merged.out_dir + "/config.resolved.json"), ReadJsonFile(whole.out_dir + "/config.resolved.json"));

  // A missing shard and a shard given twice are errors naming a job.
  try {
    MergeShardOutputs({shard_dirs[0], shard_dirs[1]});
    FAIL() << "a missing shard was not noticed";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is in none of the directories"), std::string::npos) << e.what();
  }
  try {
    MergeShardOutputs({shard_dirs[0], shard_dirs[1], shard_dirs[2], shard_dirs[1]});
    FAIL() << "a duplicated shard was not noticed";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("appears in more than one directory"), std::string::npos) << e.what();
  }
}

TEST(Runner, MergeRefusesShardsOfDifferentConfigs) {
  ExperimentConfig a = TinyConfig();
  a.trials = 1;
  a.save_trajectories = 1;
  ExperimentConfig b = a;
  b.seed = 4;
  DriverOptions da, db;
  da.out_dir = TempDir("config_a");
  db.out_dir = TempDir("config_b");
  da.run.shard = ParseShard("0/2");
  db.run.shard = ParseShard("1/2");
  RunAndWrite(a, da);
  RunAndWrite(b, db);
  try {
    MergeShardOutputs({da.out_dir, db.out_dir});
    FAIL() << "merged shards of different configs";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("the config differs"), std::string::npos) << e.what();
  }
}

TEST(Runner, FindsConfigsByName) {
  const std::string path = FindConfigFile("noise_sweep");
  EXPECT_NE(path.find("experiments/configs/noise_sweep.json"), std::string::npos);
  EXPECT_EQ(FindConfigFile("noise_sweep.json"), path);
  try {
    FindConfigFile("no_such_experiment");
    FAIL() << "found a config that does not exist";
  } catch (const std::runtime_error& e) {
    // The names in order, the CI configs among them (the list grows with every config).
    const std::string message = e.what();
    EXPECT_NE(message.find("; available: ablation, ablation_robust, ci/"), std::string::npos) << message;
    EXPECT_NE(message.find(", ci/error_vs_frame_ci, "), std::string::npos) << message;
  }
  const std::vector<std::string> configs = AvailableConfigs();
  EXPECT_TRUE(std::is_sorted(configs.begin(), configs.end()));
  for (const char* name : {"noise_sweep", "loop", "ci/loop_ci"}) {
    EXPECT_NE(std::find(configs.begin(), configs.end(), name), configs.end()) << name;
  }
}

// Issue 21: a run is written into a fresh directory and swapped in whole; the shard outputs
// under raw/shards/ stay; --resume reuses the journal an interrupted run leaves.
TEST(Runner, RunReplacesTheOutputDirectoryWholeAndKeepsShards) {
  ExperimentConfig c = TinyConfig();
  c.trials = 1;
  DriverOptions options;
  options.out_dir = TempDir("swap");
  WriteTextFileAtomically(options.out_dir + "/run.json", "{}\n");  // an earlier run's output
  WriteTextFileAtomically(options.out_dir + "/stale.csv", "from an earlier run\n");
  fs::create_directories(options.out_dir + "/raw/shards/0-of-2");
  WriteTextFileAtomically(options.out_dir + "/raw/shards/0-of-2/keep.txt", "a shard\n");
  RunAndWrite(c, options);
  EXPECT_FALSE(fs::exists(options.out_dir + "/stale.csv"));
  EXPECT_TRUE(fs::exists(options.out_dir + "/summary.csv"));
  EXPECT_EQ(ReadTextFile(options.out_dir + "/raw/shards/0-of-2/keep.txt"), "a shard\n");
  EXPECT_FALSE(fs::exists(StagingDir(options.out_dir)));
  for (const auto& entry : fs::directory_iterator(fs::path(options.out_dir).parent_path())) {
    EXPECT_EQ(entry.path().filename().string().find("slt_experiments_swap."), std::string::npos) << entry.path();
  }
}

// A directory no run wrote (no run.json) is not replaced: the user's files in it stay.
TEST(Runner, RunRefusesToReplaceADirectoryItDidNotWrite) {
  ExperimentConfig c = TinyConfig();
  c.trials = 1;
  DriverOptions options;
  options.out_dir = TempDir("foreign");
  WriteTextFileAtomically(options.out_dir + "/notes.md", "mine\n");
  try {
    RunAndWrite(c, options);
    ADD_FAILURE() << "expected a refusal";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(options.out_dir + ": holds files no run_experiment wrote"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(ReadTextFile(options.out_dir + "/notes.md"), "mine\n");
  EXPECT_FALSE(fs::exists(options.out_dir + "/summary.csv"));
  // Only other runs' shards: the merge target of a sharded run, accepted.
  fs::remove(options.out_dir + "/notes.md");
  fs::create_directories(options.out_dir + "/raw/shards/0-of-2");
  RunAndWrite(c, options);
  EXPECT_TRUE(fs::exists(options.out_dir + "/summary.csv"));
}

TEST(Runner, ResumeReusesTheFinishedJobsOfTheSameConfig) {
  const ExperimentConfig c = TinyConfig();
  DriverOptions fresh;
  fresh.out_dir = TempDir("resume_fresh");
  const ExperimentRun full = RunAndWrite(c, fresh);
  // What an interrupted run leaves: the config and a journal of some finished jobs.
  DriverOptions resumed;
  resumed.out_dir = TempDir("resume") + "/out";
  resumed.resume = true;
  const std::string staging = StagingDir(resumed.out_dir);
  fs::create_directories(staging);
  WriteJsonFile(staging + "/config.resolved.json", ResolvedConfigJson(c));
  const std::vector<TrialResult> half(full.trials.begin(), full.trials.begin() + 10);
  WriteRawResults(staging, c, half);
  const ExperimentRun run = RunAndWrite(c, resumed);
  EXPECT_EQ(ReadJsonFile(resumed.out_dir + "/run.json")["resumed_jobs"], 10);
  EXPECT_FALSE(fs::exists(staging));
  for (const char* file : {"raw/trials.csv", "raw/curves.csv", "summary.csv", "curves.csv"}) {
    EXPECT_EQ(WithoutTiming(ReadCsvFile(fresh.out_dir + "/" + file)),
              WithoutTiming(ReadCsvFile(resumed.out_dir + "/" + file)))
        << file;
  }
  // The reused rows are the journal's (their timing too), not new runs.
  ASSERT_EQ(run.trials.size(), full.trials.size());
  for (size_t i = 0; i < half.size(); ++i) EXPECT_EQ(run.trials[i].metrics[kTimeMeanUs], full.trials[i].metrics[kTimeMeanUs]) << i;

  // A finished run in --out is reused whole; another config's is refused.
  const ExperimentRun again = RunAndWrite(c, resumed);
  EXPECT_EQ(ReadJsonFile(resumed.out_dir + "/run.json")["resumed_jobs"], full.trials.size());
  EXPECT_EQ(again.trials.back().metrics[kTimeMeanUs], run.trials.back().metrics[kTimeMeanUs]);
  ExperimentConfig other = c;
  other.seed = 99;
  try {
    RunAndWrite(other, resumed);
    FAIL() << "resumed a run of another config";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is another config's"), std::string::npos) << e.what();
  }
}

TEST(Runner, MergeNeverOverwritesAShard) {
  ExperimentConfig c = TinyConfig();
  c.trials = 1;
  const std::string root = TempDir("merge_out");
  std::vector<std::string> shards;
  for (int i = 0; i < 2; ++i) {
    DriverOptions shard;
    shard.out_dir = root + "/result/raw/shards/" + std::to_string(i) + "-of-2";
    shard.run.shard = ParseShard(std::to_string(i) + "/2");
    RunAndWrite(c, shard);
    shards.push_back(shard.out_dir);
  }
  DriverOptions merged;
  merged.out_dir = shards[0];
  const std::string before = ReadTextFile(shards[0] + "/raw/trials.csv");
  EXPECT_THROW(MergeAndWrite(shards, merged), std::runtime_error);
  EXPECT_EQ(ReadTextFile(shards[0] + "/raw/trials.csv"), before);
  merged.out_dir = root + "/result/raw";  // holds the shards outside raw/shards/
  EXPECT_THROW(MergeAndWrite(shards, merged), std::runtime_error);
  EXPECT_EQ(ReadTextFile(shards[0] + "/raw/trials.csv"), before);
  // The usual layout: results/<name> with its shards under raw/shards/.
  merged.out_dir = root + "/result";
  MergeAndWrite(shards, merged);
  EXPECT_TRUE(fs::exists(merged.out_dir + "/summary.csv"));
  EXPECT_EQ(ReadTextFile(shards[0] + "/raw/trials.csv"), before);
}

}  // namespace
}  // namespace slt
