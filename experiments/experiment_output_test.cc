#include "experiments/experiment_output.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "common/json_reader.h"
#include "experiments/regression_test_support.h"

namespace slt {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string TempDir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("slt_output_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

ExperimentConfig TwoMethodConfig() {
  return ExperimentConfigFromJson(
      {{"name", "out"},
       {"trials", 3},
       {"simulation", {{"frames", 5}}},
       {"sweep", {{{"parameter", "noise.endpoint_px"}, {"values", {0, 1.5}}, {"label", "Noise (px)"}}}},
       {"methods", {"trifocal_line_ekf", {{"name", "trifocal_line_ekf"}, {"label", "paper, \"preset\" | 50%"}}}},
       {"per_frame_curves", true}},
      "out.json");
}

// Synthetic trials with known values: rot_err_deg = 1 + trial + point, NaN for a non-finite trial.
std::vector<TrialResult> SyntheticTrials(const ExperimentConfig& c) {
  std::vector<TrialResult> trials;
  for (size_t m = 0; m < 2; ++m) {
    for (size_t p = 0; p < 2; ++p) {
      for (int k = 0; k < 3; ++k) {
        TrialResult t;
        t.method_index = m;
        t.point_index = p;
        t.trial = k;
        t.seed = 1000 + static_cast<std::uint64_t>(k);
        t.frames = 5;
        t.metrics_frame = 4;
        for (int i = 0; i < kNumTrialMetrics; ++i) t.metrics[i] = 0.1 * i + 1e-17 * k + 1.0 / 3.0;
        t.metrics[kRotErrDeg] = 1.0 + k + static_cast<double>(p);
        t.metrics[kTransErrM] = 0.001 * (1 + k) * (m + 1);
        t.finite = !(m == 1 && p == 1 && k == 2);
        if (!t.finite) t.metrics[kRotErrDeg] = std::nan("");
        for (int f = 0; f < 5; ++f) {
          FrameError e;
          e.frame = f;
          e.time_s = f / 30.0;
          e.rot_err_deg = 0.01 * f * (k + 1);
          e.trans_err_m = 0.1 * f;
          t.curve.push_back(e);
        }
        trials.push_back(t);
      }
    }
  }
  (void)c;
  return trials;
}

TEST(Output, RawResultsReadBackExactly) {
  const ExperimentConfig c = TwoMethodConfig();
  const std::vector<TrialResult> trials = SyntheticTrials(c);
  const std::string dir = TempDir("raw");
  WriteRawResults(dir, c, trials);
  const std::vector<TrialResult> back = ReadRawResults(dir, c);
  ASSERT_EQ(back.size(), trials.size());
  for (size_t i = 0; i < trials.size(); ++i) {
    EXPECT_EQ(back[i].method_index, trials[i].method_index);
    EXPECT_EQ(back[i].point_index, trials[i].point_index);
    EXPECT_EQ(back[i].trial, trials[i].trial);
    EXPECT_EQ(back[i].seed, trials[i].seed);
    EXPECT_EQ(back[i].finite, trials[i].finite);
    for (int m = 0; m < kNumTrialMetrics; ++m) {
      if (std::isnan(trials[i].metrics[m])) {
        EXPECT_TRUE(std::isnan(back[i].metrics[m]));
      } else {
        EXPECT_EQ(back[i].metrics[m], trials[i].metrics[m]) << TrialMetricName(m);
      }
    }
    ASSERT_EQ(back[i].curve.size(), 5u);
    EXPECT_EQ(back[i].curve[3].rot_err_deg, trials[i].curve[3].rot_err_deg);
  }
  // A row of another experiment is refused, naming the line; so is an index that is not a whole
  // number (a trial "1.5", a point "-1").
  const std::string rows = ReadTextFile(dir + "/raw/trials.csv");
  const std::string id = c.methods[0].Id();
  const std::string rest = std::string(kNumTrialMetrics + 1, ',') + "true\n";
  for (const auto& [row, error] : std::vector<std::pair<std::string, std::string>>{
           {"nobody,0,0,0,1,5,4" + rest, "trials.csv:14: method 'nobody' is not in the config"},
           {id + ",0,0,1.5,1,5,4" + rest, "trials.csv:14: not an integer: '1.5'"},
           {id + ",-1,0,0,1,5,4" + rest, "trials.csv:14: not an integer: '-1'"}}) {
    WriteTextFileAtomically(dir + "/raw/trials.csv", rows + row);
    try {
      ReadRawResults(dir, c);
      FAIL() << row;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(error), std::string::npos) << e.what();
    }
  }
}

TEST(Output, SummaryStatisticsPerMethodAndPoint) {
  const ExperimentConfig c = TwoMethodConfig();
  const std::vector<SummaryRow> rows = SummarizeTrials(c, SyntheticTrials(c));
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[1].method, 0u);
  EXPECT_EQ(rows[1].point, 1u);
  EXPECT_EQ(rows[1].trials, 3u);
  EXPECT_DOUBLE_EQ(rows[1].metrics[kRotErrDeg].mean, 3.0);    // 2, 3, 4
  EXPECT_DOUBLE_EQ(rows[1].metrics[kRotErrDeg].p2_5, 2.05);   // 2 + 0.05 * 1
  EXPECT_DOUBLE_EQ(rows[1].metrics[kRotErrDeg].p97_5, 3.95);
  EXPECT_EQ(rows[3].finite_trials, 2u);                        // one trial lost its pose
  EXPECT_EQ(rows[3].metrics[kRotErrDeg].count, 2u);
  EXPECT_DOUBLE_EQ(rows[3].metrics[kRotErrDeg].mean, 2.5);
  EXPECT_DOUBLE_EQ(rows[3].metrics[kTransErrM].mean, 0.003);   // the non-finite trial is left out
}

TEST(Output, SummaryTablesInCsvMarkdownAndLatex) {
  const ExperimentConfig c = TwoMethodConfig();
  const std::vector<SummaryRow> rows = SummarizeTrials(c, SyntheticTrials(c));
  const CsvTable csv = ParseCsv(SummaryCsv(c, rows), "summary.csv");
  ASSERT_EQ(csv.rows.size(), 4u);
  EXPECT_EQ(csv.rows[2][csv.Column("method")], "paper, \"preset\" | 50%");
  EXPECT_EQ(csv.rows[1][csv.Column("noise.endpoint_px")], "1.5");
  EXPECT_EQ(ParseDouble(csv.rows[1][csv.Column("rot_err_deg_mean")]), 3.0);
  EXPECT_EQ(csv.rows[3][csv.Column("finite_trials")], "2");

  const std::string md = SummaryMarkdown(c, rows);
  EXPECT_NE(md.find("| Method | Noise (px) | Trials | Rotation error (deg) mean | median | 95 % interval |"), std::string::npos) << md;
  EXPECT_NE(md.find("| trifocal_line_ekf | 1.5 | 3 | 3 | 3 | [2.05, 3.95] |"), std::string::npos) << md;
  EXPECT_NE(md.find("paper, \"preset\" \\| 50%"), std::string::npos);
  EXPECT_NE(md.find("| 2/3 |"), std::string::npos);

  const std::string tex = SummaryLatex(c, rows);
  for (const char* s : {"\\toprule", "\\midrule", "\\bottomrule", "\\cmidrule(lr){4-6}", "paper, \"preset\" | 50\\%",
                        "\\multicolumn{3}{c}{Rotation error (deg)}"}) {
    EXPECT_NE(tex.find(s), std::string::npos) << s << "\n" << tex;
  }
}

TEST(Output, CurvesAreMeansOverTheFiniteTrials) {
  const ExperimentConfig c = TwoMethodConfig();
  const CsvTable curves = ParseCsv(CurvesCsv(c, SyntheticTrials(c)), "curves.csv");
  ASSERT_EQ(curves.rows.size(), 4u * 5u);
  // method 0, point 0, frame 2: rot = 0.02 * (k + 1) for k = 0, 1, 2 -> mean 0.04.
  EXPECT_NEAR(ParseDouble(curves.rows[2][curves.Column("rot_err_deg_mean")]), 0.04, 1e-15);
  EXPECT_EQ(curves.rows[2][curves.Column("trials")], "3");
  EXPECT_EQ(curves.rows[17][curves.Column("trials")], "2");  // method 1, point 1
}

TEST(Regression, ToleranceNewMethodsAndUnregisteredReferenceMethods) {
  const ExperimentConfig c = TwoMethodConfig();
  const std::vector<SummaryRow> rows = SummarizeTrials(c, SyntheticTrials(c));
  const json reference_config = ResolvedConfigJson(c);
  const CsvTable same = ParseCsv(SummaryCsv(c, rows), "ref.csv");
  const RegressionReport pass = CompareWithReference(c, rows, same, reference_config);
  EXPECT_TRUE(pass.ok()) << pass.failures.front();
  EXPECT_TRUE(pass.notes.empty());

  // 20 % worse passes, 30 % worse fails.
  auto scaled = [&](double factor) {
    std::vector<SummaryRow> r = rows;
    r[0].metrics[kRotErrDeg].mean *= factor;
    return CompareWithReference(c, r, same, reference_config);
  };
  EXPECT_TRUE(scaled(1.2).ok());
  const RegressionReport worse = scaled(1.3);
  ASSERT_EQ(worse.failures.size(), 1u);
  EXPECT_NE(worse.failures[0].find("'trifocal_line_ekf' at noise.endpoint_px = 0: rot_err_deg_mean"), std::string::npos)
      << worse.failures[0];
  // The error along the run is guarded too (a loop's final error can hide its middle): the ATE in
  // rotation and translation and the largest translation error, each on its own.
  for (const int metric : {kAteRotDeg, kAteTransM, kMaxTransErrM}) {
    std::vector<SummaryRow> r = rows;
    r[1].metrics[metric].mean *= 1.2;
    EXPECT_TRUE(CompareWithReference(c, r, same, reference_config).ok()) << TrialMetricName(metric);
    r[1].metrics[metric].mean = rows[1].metrics[metric].mean * 1.3;
    const RegressionReport along = CompareWithReference(c, r, same, reference_config);
    ASSERT_EQ(along.failures.size(), 1u) << TrialMetricName(metric);
    EXPECT_NE(along.failures[0].find(std::string(": ") + TrialMetricName(metric) + "_mean"), std::string::npos)
        << along.failures[0];
  }
  // A config comparing only its ATE (reference_metrics: a long run whose final and largest
  // errors turn on the last bits of the arithmetic) lets those errors move, but not the ATE.
  ExperimentConfig ate_only = c;
  ate_only.reference_metrics = {"ate_rot_deg", "ate_trans_m"};
  for (const int metric : {kRotErrDeg, kTransErrM, kMaxTransErrM, kAteRotDeg, kAteTransM}) {
    std::vector<SummaryRow> r = rows;
    r[1].metrics[metric].mean *= 5.0;
    const RegressionReport report = CompareWithReference(ate_only, r, same, reference_config);
    const bool compared = metric == kAteRotDeg || metric == kAteTransM;
    EXPECT_EQ(report.ok(), !compared) << TrialMetricName(metric);
    EXPECT_EQ(report.table.find(std::string(TrialMetricName(metric)) + "_mean") != std::string::npos, compared)
        << TrialMetricName(metric);
  }
  // Near zero, the absolute floors apply (0.5 mm, 0.02 deg): against a reference of 0.2 mm and
  // 0.01 deg, +0.4 mm and +0.015 deg pass although 1.25x the reference would not; +0.6 mm and
  // +0.025 deg fail.
  std::vector<SummaryRow> small = rows;
  small[0].metrics[kTransErrM].mean = 0.0002;
  small[0].metrics[kRotErrDeg].mean = 0.01;
  const CsvTable small_reference = ParseCsv(SummaryCsv(c, small), "ref.csv");
  auto shifted = [&](double trans_m, double rot_deg) {
    std::vector<SummaryRow> r = small;
    r[0].metrics[kTransErrM].mean += trans_m;
    r[0].metrics[kRotErrDeg].mean += rot_deg;
    return CompareWithReference(c, r, small_reference, reference_config).ok();
  };
  EXPECT_TRUE(shifted(0.0, 0.0));
  EXPECT_TRUE(shifted(0.0004, 0.0));
  EXPECT_FALSE(shifted(0.0006, 0.0));
  EXPECT_TRUE(shifted(0.0, 0.015));
  EXPECT_FALSE(shifted(0.0, 0.025));
  // Fewer finite trials than the reference fails.
  std::vector<SummaryRow> r = rows;
  r[0].finite_trials = 2;
  EXPECT_FALSE(CompareWithReference(c, r, same, reference_config).ok());

  // A reference made with another config (here: more trials) is stale, whatever its numbers.
  ExperimentConfig more_trials = c;
  more_trials.trials = 4;
  const RegressionReport stale = CompareWithReference(more_trials, rows, same, reference_config);
  ASSERT_EQ(stale.failures.size(), 1u);
  EXPECT_NE(stale.failures[0].find("the config's 'trials' differs from the reference's (3 there, 4 here)"), std::string::npos)
      << stale.failures[0];

  // A method absent from the reference is "no reference", not a failure.
  ExperimentConfig only_first = c;
  only_first.methods.resize(1);
  std::vector<SummaryRow> first_rows(rows.begin(), rows.begin() + 2);
  const CsvTable partial = ParseCsv(SummaryCsv(only_first, first_rows), "ref.csv");
  const RegressionReport new_method = CompareWithReference(c, rows, partial, ResolvedConfigJson(only_first));
  EXPECT_TRUE(new_method.ok());
  ASSERT_EQ(new_method.notes.size(), 1u);
  EXPECT_NE(new_method.notes[0].find("no reference"), std::string::npos);

  // A reference method that is no longer registered fails clearly.
  json gone = reference_config;
  gone["methods"][1]["name"] = "retired_tracker";
  const RegressionReport unregistered = CompareWithReference(c, rows, same, gone);
  ASSERT_FALSE(unregistered.ok());
  EXPECT_NE(unregistered.failures[0].find("tracker 'retired_tracker') is no longer registered"), std::string::npos)
      << unregistered.failures[0];
  // So does a reference method the run left out.
  const RegressionReport left_out = CompareWithReference(only_first, first_rows, same, reference_config);
  ASSERT_FALSE(left_out.ok());
  EXPECT_NE(left_out.failures[0].find("was not run"), std::string::npos);
}

TEST(Regression, ExpectedOrderingPairs) {
  ExperimentConfig c = TwoMethodConfig();
  const std::vector<SummaryRow> rows = SummarizeTrials(c, SyntheticTrials(c));
  EXPECT_TRUE(CheckExpectations(c, rows).ok());  // nothing expected
  EXPECT_EQ(SummaryMarkdown(c, rows).find("lowest first"), std::string::npos);
  // Method 0 has the same rotation error and half the translation error of method 1 at point 0,
  // but a larger rotation error at point 1 (where method 1 lost a trial).
  c.expect_better = {{"trifocal_line_ekf", c.methods[1].Id()}};
  const RegressionReport report = CheckExpectations(c, rows);
  ASSERT_EQ(report.failures.size(), 1u) << report.table;
  EXPECT_NE(report.failures[0].find("ordering is lost at noise.endpoint_px = 1.5"), std::string::npos) << report.failures[0];
  // On the translation error alone it holds at both points (method 0 has half of method 1's).
  c.expect_better[0].metrics = {"trans_err_m"};
  EXPECT_TRUE(CheckExpectations(c, rows).ok()) << CheckExpectations(c, rows).table;
  c.expect_better[0].metrics = {"rot_err_deg", "trans_err_m"};
  // Restricted to the first point, the pair holds.
  c.expect_better[0].at = {{"noise.endpoint_px", 0}};
  EXPECT_TRUE(CheckExpectations(c, rows).ok()) << CheckExpectations(c, rows).table;
  // The other way round it fails on the translation error there.
  c.expect_better = {{c.methods[1].Id(), "trifocal_line_ekf", {{"noise.endpoint_px", 0}}}};
  const RegressionReport other = CheckExpectations(c, rows);
  ASSERT_FALSE(other.ok());
  EXPECT_NE(other.failures[0].find("trans_err_m"), std::string::npos);
  // The summary lists the full ordering at every point once a config states orderings.
  const std::string md = SummaryMarkdown(c, rows);
  EXPECT_NE(md.find("- noise.endpoint_px = 1.5: " + c.methods[1].Id()), std::string::npos) << md;
}

TEST(Regression, ExpectedBounds) {
  ExperimentConfig c = TwoMethodConfig();
  const std::vector<SummaryRow> rows = SummarizeTrials(c, SyntheticTrials(c));
  // Method 1's mean translation error: 0.002 * (1, 2, 3) -> 0.004 at point 0; at point 1 its
  // last trial lost its pose, so 0.002 * (1, 2) -> 0.003.
  const std::string id = c.methods[1].Id();
  const auto bound = [&](const std::string& metric, std::optional<double> max, bool percent_of_path = false) {
    BoundCheck b;
    b.method = id;
    b.metric = metric;
    b.max = max;
    b.percent_of_path = percent_of_path;
    return b;
  };
  c.expect_bounds = {bound("trans_err_m", 0.0035)};
  RegressionReport report = CheckExpectations(c, rows);
  ASSERT_EQ(report.failures.size(), 1u) << report.table;
  EXPECT_NE(report.failures[0].find("bound is lost at noise.endpoint_px = 0: '" + id + "' trans_err_m mean = 0.004, not <= 0.0035"),
            std::string::npos)
      << report.failures[0];
  EXPECT_NE(report.table.find("ok    '" + id + "' trans_err_m mean 0.003 <= 0.0035 at noise.endpoint_px = 1.5"),
            std::string::npos)
      << report.table;
  // Selected by `at`, only the passing point is checked.
  c.expect_bounds[0].at = {{"noise.endpoint_px", 1.5}};
  EXPECT_TRUE(CheckExpectations(c, rows).ok());
  // A method without a result at a selected point fails.
  c.expect_bounds[0].at = nlohmann::json::object();
  std::vector<SummaryRow> first_point_only = {rows[0], rows[1], rows[2]};
  report = CheckExpectations(c, first_point_only);
  EXPECT_NE(report.failures.back().find("'" + id + "' has no result at noise.endpoint_px = 1.5"), std::string::npos)
      << report.failures.back();
  // As a percentage of the path: every synthetic metric m is 0.1 m + 1/3 (plus 1e-17 k), so the
  // path (kPathLengthM) is 0.1 kPathLengthM + 1/3 and the ATE 0.1 kAteTransM + 1/3.
  const double ate = 0.1 * kAteTransM + 1.0 / 3.0, path = 0.1 * kPathLengthM + 1.0 / 3.0;
  const double percent = 100.0 * ate / path;
  c.expect_bounds = {bound("ate_trans_m", percent * 1.001, true)};
  EXPECT_TRUE(CheckExpectations(c, rows).ok()) << CheckExpectations(c, rows).table;
  c.expect_bounds[0].max = percent * 0.999;
  report = CheckExpectations(c, rows);
  ASSERT_EQ(report.failures.size(), 2u) << report.table;
  EXPECT_NE(report.failures[0].find("ate_trans_m mean as % of the path"), std::string::npos) << report.failures[0];
  // A lower bound, alone or with the upper one (a band).
  c.expect_bounds = {bound("trans_err_m", std::nullopt)};
  c.expect_bounds[0].min = 0.0035;
  report = CheckExpectations(c, rows);
  ASSERT_EQ(report.failures.size(), 1u) << report.table;
  EXPECT_NE(report.failures[0].find("at noise.endpoint_px = 1.5: '" + id + "' trans_err_m mean = 0.003, not >= 0.0035"),
            std::string::npos)
      << report.failures[0];
  c.expect_bounds[0].max = 0.0039;
  report = CheckExpectations(c, rows);
  ASSERT_EQ(report.failures.size(), 2u) << report.table;
  EXPECT_NE(report.failures[0].find("trans_err_m mean = 0.004, not in [0.0035, 0.0039]"), std::string::npos)
      << report.failures[0];
  c.expect_bounds[0].min = 0.0029;
  c.expect_bounds[0].max = 0.0041;
  EXPECT_TRUE(CheckExpectations(c, rows).ok()) << CheckExpectations(c, rows).table;
}

}  // namespace
}  // namespace slt
