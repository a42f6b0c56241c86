#include "experiments/experiment_output.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "common/json_reader.h"
#include "common/csv.h"
#include "common/table.h"
#include "experiments/experiment_runner.h"

namespace slt {
namespace {

namespace fs = std::filesystem;

struct MetricInfo {
  const char* name;
  const char* title;
};

constexpr MetricInfo kMetrics[kNumTrialMetrics] = {
#define SLT_METRIC_INFO(id, name, title) {name, title},
    SLT_TRIAL_METRICS(SLT_METRIC_INFO)
#undef SLT_METRIC_INFO
};

const char* kStatSuffixes[4] = {"_mean", "_median", "_p2_5", "_p97_5"};

// The cells that name a row of a CSV file: method id, point index, the point's sweep values.
std::vector<std::string> RowPrefix(const ExperimentConfig& config, const std::vector<SweepPoint>& points, size_t method,
                                   size_t point) {
  std::vector<std::string> row = {config.methods.at(method).Id(), std::to_string(point)};
  for (const nlohmann::json& v : points.at(point).values) row.push_back(FormatValue(v));
  return row;
}

// A CSV file's table: the columns of RowPrefix (the sweep parameters by their dotted keys), then
// `columns`.
Table CsvFileTable(const ExperimentConfig& config, const std::vector<std::string>& columns) {
  Table table;
  for (const char* c : {"method", "point"}) table.columns.emplace_back(c);
  for (const SweepAxis& a : config.sweep) table.columns.emplace_back(a.parameter);
  for (const std::string& c : columns) table.columns.emplace_back(c);
  return table;
}

// A whole number >= 0 in an index column ("not an integer: '<text>'" otherwise).
size_t ParseIndex(const std::string& text) { return ParseInteger<size_t>(text); }

// The (method, point, trial) a row of a raw file names, checked with its sweep columns against
// the config.
TrialResult RowKey(const CsvTable& table, const std::vector<std::string>& row, const ExperimentConfig& config,
                   const std::vector<SweepPoint>& points) {
  TrialResult key;
  const std::string& id = row[table.Column("method")];
  const int method = MethodIndex(config, id);
  if (method < 0) throw std::runtime_error("method '" + id + "' is not in the config");
  key.method_index = static_cast<size_t>(method);
  const size_t p = key.point_index = ParseIndex(row[table.Column("point")]);
  if (p >= points.size()) throw std::runtime_error("sweep point " + std::to_string(p) + " is not in the config");
  for (size_t a = 0; a < config.sweep.size(); ++a) {
    const std::string& value = row[table.Column(config.sweep[a].parameter)];
    if (value != FormatValue(points[p].values[a])) {
      throw std::runtime_error(config.sweep[a].parameter + " = '" + value + "' does not match sweep point " +
                               std::to_string(p) + " of the config");
    }
  }
  key.trial = static_cast<int>(ParseIndex(row[table.Column("trial")]));
  if (key.trial >= config.trials) throw std::runtime_error("trial " + std::to_string(key.trial) + " is not in the config");
  return key;
}

// The trials that pass `keep`, by (method, point) in that order, each group by trial.
template <typename Keep>
std::map<std::pair<size_t, size_t>, std::vector<const TrialResult*>> GroupTrials(const std::vector<TrialResult>& trials,
                                                                                  const Keep& keep) {
  std::map<std::pair<size_t, size_t>, std::vector<const TrialResult*>> groups;
  for (const TrialResult& t : trials) {
    if (keep(t)) groups[{t.method_index, t.point_index}].push_back(&t);
  }
  for (auto& [key, group] : groups) {
    std::sort(group.begin(), group.end(), [](const TrialResult* a, const TrialResult* b) { return a->trial < b->trial; });
  }
  return groups;
}

// Three significant digits, whole numbers from 1000 up.
std::string Sig(double v) {
  if (!std::isfinite(v)) return std::isnan(v) ? "n/a" : (v > 0 ? "inf" : "-inf");
  return std::fabs(v) >= 1000.0 ? StringPrintf("%.0f", v) : StringPrintf("%.3g", v);
}

std::string MetricsFrameText(const ExperimentConfig& config) {
  return config.metrics_frame < 0 ? std::string("the last frame")
                                  : "frame " + std::to_string(config.metrics_frame);
}

// The table of summary.md and summary.tex: method, sweep values, trials (f/n when only f were
// finite), then mean, median and 95 % interval under each table metric; a rule between methods.
Table SummaryTable(const ExperimentConfig& config, const std::vector<SummaryRow>& rows) {
  std::vector<int> metrics;
  for (const std::string& name : config.table_metrics) metrics.push_back(TrialMetricFromName(name));
  Table table;
  table.columns.emplace_back("Method", Table::Align::kLeft);
  for (const SweepAxis& a : config.sweep) table.columns.emplace_back(a.label);
  table.columns.emplace_back("Trials");
  for (int m : metrics) {
    table.groups.push_back({kMetrics[m].title, table.columns.size(), 3});
    table.columns.emplace_back("mean");
    table.columns.emplace_back("median");
    table.columns.emplace_back("95 % interval", Table::Align::kRight, "95\\,\\% interval");
  }
  const std::vector<SweepPoint> points = ExpandSweep(config.sweep);
  for (const SummaryRow& r : rows) {
    std::vector<std::string> cells = {config.methods.at(r.method).Id()};
    for (const nlohmann::json& v : points[r.point].values) cells.push_back(FormatValue(v));
    cells.push_back(r.finite_trials == r.trials ? std::to_string(r.trials)
                                                : std::to_string(r.finite_trials) + "/" + std::to_string(r.trials));
    for (int m : metrics) {
      const Summary& s = r.metrics[m];
      cells.insert(cells.end(), {Sig(s.mean), Sig(s.median), "[" + Sig(s.p2_5) + ", " + Sig(s.p97_5) + "]"});
    }
    table.AddRow(std::move(cells), /*rule_before=*/&r != &rows.front() && r.method != (&r - 1)->method);
  }
  return table;
}

}  // namespace

const char* TrialMetricName(int metric) {
  if (metric < 0 || metric >= kNumTrialMetrics) return "unknown";
  return kMetrics[metric].name;
}

int TrialMetricFromName(const std::string& name) {
  for (int m = 0; m < kNumTrialMetrics; ++m) {
    if (name == kMetrics[m].name) return m;
  }
  return -1;
}

void WriteRawResults(const std::string& dir, const ExperimentConfig& config, const std::vector<TrialResult>& trials) {
  const std::vector<SweepPoint> points = ExpandSweep(config.sweep);
  CreateDirectories(JoinPath(dir, "raw"));

  std::vector<std::string> columns = {"trial", "seed", "n_frames", "metrics_frame"};
  for (int m = 0; m < kNumTrialMetrics; ++m) columns.push_back(TrialMetricName(m));
  columns.push_back("finite");
  Table csv = CsvFileTable(config, columns);
  Table curves = CsvFileTable(config, {"trial", "frame", "time_s", "rot_err_deg", "trans_err_m"});
  Table index = CsvFileTable(config, {"trial", "estimate", "ground_truth"});
  const std::string tdir = JoinPath(dir, "raw/trajectories");
  fs::remove_all(tdir);  // this program's own folder: no stale files from an earlier run
  for (const TrialResult& t : trials) {
    std::vector<std::string> prefix = RowPrefix(config, points, t.method_index, t.point_index);
    prefix.push_back(std::to_string(t.trial));
    std::vector<std::string> row = prefix;
    row.insert(row.end(), {std::to_string(t.seed), std::to_string(t.frames), std::to_string(t.metrics_frame)});
    for (double v : t.metrics) row.push_back(FormatDouble(v));
    row.push_back(t.finite ? "true" : "false");
    csv.AddRow(std::move(row));
    for (const FrameError& e : t.curve) {
      std::vector<std::string> r = prefix;
      r.insert(r.end(), {std::to_string(e.frame), FormatDouble(e.time_s), FormatDouble(e.rot_err_deg),
                         FormatDouble(e.trans_err_m)});
      curves.AddRow(std::move(r));
    }
    if (t.estimate.empty()) continue;
    if (index.rows.empty()) CreateDirectories(tdir);
    const std::string tag = "p" + std::to_string(t.point_index) + "_t" + std::to_string(t.trial);
    const std::string est_file = "m" + std::to_string(t.method_index) + "_" + tag + ".tum";
    const std::string gt_file = "gt_" + tag + ".tum";
    WriteTumTrajectory(JoinPath(tdir, est_file), t.estimate);
    WriteTumTrajectory(JoinPath(tdir, gt_file), t.ground_truth);
    prefix.insert(prefix.end(), {est_file, gt_file});
    index.AddRow(std::move(prefix));
  }
  WriteTextFileAtomically(JoinPath(dir, "raw/trials.csv"), csv.Csv());
  if (!curves.rows.empty()) WriteTextFileAtomically(JoinPath(dir, "raw/curves.csv"), curves.Csv());
  if (!index.rows.empty()) WriteTextFileAtomically(JoinPath(tdir, "index.csv"), index.Csv());
}

std::vector<TrialResult> ReadRawResults(const std::string& dir, const ExperimentConfig& config) {
  const std::vector<SweepPoint> points = ExpandSweep(config.sweep);
  std::vector<TrialResult> trials;
  std::map<size_t, size_t> by_job;  // job index -> index into trials
  // Calls read(column, trial) for every row of `file` (if it exists), with errors naming the file
  // and line: for trials.csv a new trial (method, point and trial set), for the others the trial
  // the row belongs to.
  auto for_each_row = [&](const std::string& file, bool first, const auto& read) {
    const std::string path = JoinPath(dir, file);
    if (!first && !fs::exists(path)) return;
    const CsvTable table = ReadCsvFile(path);
    for (size_t r = 0; r < table.rows.size(); ++r) {
      const std::vector<std::string>& row = table.rows[r];
      try {
        const TrialResult key = RowKey(table, row, config, points);
        const size_t job = JobIndex(points.size(), config.trials, key.method_index, key.point_index, key.trial);
        if (first) {
          if (by_job.count(job)) throw std::runtime_error("the same (method, point, trial) appears twice");
          by_job[job] = trials.size();
          trials.push_back(key);
        } else if (!by_job.count(job)) {
          throw std::runtime_error("no row of raw/trials.csv for this row");
        }
        read([&](const char* name) -> const std::string& { return row[table.Column(name)]; }, trials[by_job[job]]);
      } catch (const std::exception& e) {
        throw std::runtime_error(table.where + ":" + std::to_string(r + 2) + ": " + e.what());
      }
    }
  };
  for_each_row("raw/trials.csv", true, [&](const auto& column, TrialResult& t) {
    t.seed = ParseInteger<std::uint64_t>(column("seed"));
    t.frames = static_cast<int>(ParseIndex(column("n_frames")));
    t.metrics_frame = static_cast<int>(ParseIndex(column("metrics_frame")));
    for (int m = 0; m < kNumTrialMetrics; ++m) t.metrics[m] = ParseDouble(column(TrialMetricName(m)));
    const std::string& finite = column("finite");
    if (finite != "true" && finite != "false") throw std::runtime_error("finite must be true or false");
    t.finite = finite == "true";
  });
  for_each_row("raw/curves.csv", false, [&](const auto& column, TrialResult& t) {
    FrameError e;
    e.frame = static_cast<int>(ParseIndex(column("frame")));
    e.time_s = ParseDouble(column("time_s"));
    e.rot_err_deg = ParseDouble(column("rot_err_deg"));
    e.trans_err_m = ParseDouble(column("trans_err_m"));
    t.curve.push_back(e);
  });
  for_each_row("raw/trajectories/index.csv", false, [&](const auto& column, TrialResult& t) {
    t.estimate = ReadTumTrajectory(JoinPath(dir, "raw/trajectories/" + column("estimate")));
    t.ground_truth = ReadTumTrajectory(JoinPath(dir, "raw/trajectories/" + column("ground_truth")));
  });
  return trials;
}

std::vector<SummaryRow> SummarizeTrials(const ExperimentConfig& /*config*/, const std::vector<TrialResult>& trials) {
  std::vector<SummaryRow> rows;
  for (const auto& [key, group] : GroupTrials(trials, [](const TrialResult&) { return true; })) {
    SummaryRow row;
    row.method = key.first;
    row.point = key.second;
    row.trials = group.size();
    for (int m = 0; m < kNumTrialMetrics; ++m) {
      std::vector<double> values;
      for (const TrialResult* t : group) values.push_back(t->finite ? t->metrics[m] : std::nan(""));
      row.metrics[m] = Summarize(values);
    }
    for (const TrialResult* t : group) row.finite_trials += t->finite ? 1 : 0;
    rows.push_back(row);
  }
  return rows;
}

std::string SummaryCsv(const ExperimentConfig& config, const std::vector<SummaryRow>& rows) {
  const std::vector<SweepPoint> points = ExpandSweep(config.sweep);
  std::vector<std::string> columns = {"trials", "finite_trials"};
  for (int m = 0; m < kNumTrialMetrics; ++m) {
    for (const char* suffix : kStatSuffixes) columns.push_back(std::string(TrialMetricName(m)) + suffix);
  }
  Table csv = CsvFileTable(config, columns);
  for (const SummaryRow& r : rows) {
    std::vector<std::string> row = RowPrefix(config, points, r.method, r.point);
    row.insert(row.end(), {std::to_string(r.trials), std::to_string(r.finite_trials)});
    for (const Summary& s : r.metrics) {
      for (double v : {s.mean, s.median, s.p2_5, s.p97_5}) row.push_back(FormatDouble(v));
    }
    csv.AddRow(std::move(row));
  }
  return csv.Csv();
}

std::string SummaryMarkdown(const ExperimentConfig& config, const std::vector<SummaryRow>& rows) {
  std::string md = "# " + config.title + "\n\n";
  if (config.datasets.empty()) {
    md += std::to_string(config.trials) + " trials per method and sweep point (trial k simulates with seed TrialSeed(" +
          std::to_string(config.seed) + ", k), the same for every method and sweep value). Errors: the accumulated error "
          "of the estimated left-camera pose against the ground truth at " + MetricsFrameText(config) +
          " (frames count from 0; alignment none). Each metric: mean, median and the 95 % interval "
          "[2.5th, 97.5th percentile] over trials (linear interpolation between order statistics). "
          "Times: wall time of one Track() call.\n\n";
  } else {
    md += "Recorded sequences through the image front end (docs/datasets.md), one run each. Errors: the estimated "
          "left-camera poses against the dataset's ground truth, re-expressed from the first frame run (alignment "
          "none). Times: wall time of one Track() call (the front end's per-stage times are in track_images' "
          "summary).\n\n";
  }
  md += SummaryTable(config, rows).Markdown();
  bool any_nonfinite = false;
  for (const SummaryRow& r : rows) any_nonfinite = any_nonfinite || r.finite_trials != r.trials;
  if (any_nonfinite) md += "\nTrials shown as f/n: only the f trials with finite poses enter the statistics.\n";
  if (!config.expect_better.empty()) {
    md += "\nMethods by mean rotation error at " + MetricsFrameText(config) + ", lowest first:\n\n" +
          OrderingText(config, rows);
  }
  return md;
}

std::string SummaryLatex(const ExperimentConfig& config, const std::vector<SummaryRow>& rows) {
  std::string tex = "% " + config.title + ": generated by run_experiment; needs \\usepackage{booktabs}\n";
  tex += "% mean, median and 95 % interval [2.5th, 97.5th percentile] over " + std::to_string(config.trials) +
         " trials; errors at " + MetricsFrameText(config) + "\n";
  return tex + SummaryTable(config, rows).Latex();
}

std::string CurvesCsv(const ExperimentConfig& config, const std::vector<TrialResult>& trials) {
  const std::vector<SweepPoint> points = ExpandSweep(config.sweep);
  const auto groups = GroupTrials(trials, [](const TrialResult& t) { return t.finite && !t.curve.empty(); });
  Table csv = CsvFileTable(
      config, {"frame", "trials", "rot_err_deg_mean", "trans_err_m_mean", "rot_err_deg_median", "trans_err_m_median"});
  for (const auto& [key, group] : groups) {
    std::vector<ErrorCurve> curves;
    for (const TrialResult* t : group) curves.push_back(t->curve);
    const ErrorCurve mean = MeanErrorCurve(curves);
    for (size_t k = 0; k < mean.size(); ++k) {
      std::vector<double> rot, trans;
      for (const ErrorCurve& c : curves) {
        rot.push_back(c[k].rot_err_deg);
        trans.push_back(c[k].trans_err_m);
      }
      std::vector<std::string> row = RowPrefix(config, points, key.first, key.second);
      row.insert(row.end(), {std::to_string(mean[k].frame), std::to_string(curves.size()),
                             FormatDouble(mean[k].rot_err_deg), FormatDouble(mean[k].trans_err_m),
                             FormatDouble(Quantile(rot, 0.5)), FormatDouble(Quantile(trans, 0.5))});
      csv.AddRow(std::move(row));
    }
  }
  return csv.Csv();
}

std::string OrderingText(const ExperimentConfig& config, const std::vector<SummaryRow>& rows) {
  const std::vector<SweepPoint> points = ExpandSweep(config.sweep);
  std::map<size_t, std::vector<const SummaryRow*>> by_point;
  for (const SummaryRow& row : rows) by_point[row.point].push_back(&row);
  std::string text;
  for (auto& [point, group] : by_point) {
    std::stable_sort(group.begin(), group.end(), [](const SummaryRow* a, const SummaryRow* b) {
      return a->metrics[kRotErrDeg].mean < b->metrics[kRotErrDeg].mean;
    });
    text += "- " + PointText(config, points[point]) + ":";
    for (size_t i = 0; i < group.size(); ++i) {
      text += std::string(i ? " <" : "") + " " + config.methods.at(group[i]->method).Id() + " (" +
              Sig(group[i]->metrics[kRotErrDeg].mean) + " deg)";
    }
    text += "\n";
  }
  return text;
}

void WriteSummaries(const std::string& dir, const ExperimentConfig& config, const std::vector<TrialResult>& trials) {
  CreateDirectories(dir);
  const std::vector<SummaryRow> rows = SummarizeTrials(config, trials);
  WriteTextFileAtomically(JoinPath(dir, "summary.csv"), SummaryCsv(config, rows));
  WriteTextFileAtomically(JoinPath(dir, "summary.md"), SummaryMarkdown(config, rows));
  WriteTextFileAtomically(JoinPath(dir, "summary.tex"), SummaryLatex(config, rows));
  if (config.per_frame_curves) WriteTextFileAtomically(JoinPath(dir, "curves.csv"), CurvesCsv(config, trials));
}

MergedRun MergeShardOutputs(const std::vector<std::string>& dirs) {
  if (dirs.empty()) throw std::runtime_error("--merge: no directory given");
  MergedRun merged;
  for (size_t d = 0; d < dirs.size(); ++d) {
    const std::string config_path = JoinPath(dirs[d], "config.resolved.json");
    const ExperimentConfig config = ReadExperimentConfig(config_path);
    if (d == 0) merged.config = config;
    if (ExperimentConfigToJson(config) != ExperimentConfigToJson(merged.config)) {
      throw std::runtime_error(config_path + ": the config differs from " + JoinPath(dirs[0], "config.resolved.json") +
                               " (shards of different experiments?)");
    }
    const std::string run_path = JoinPath(dirs[d], "run.json");
    nlohmann::json run = fs::exists(run_path) ? ReadJsonFile(run_path) : nlohmann::json::object();
    run["directory"] = dirs[d];
    merged.shards.push_back(run);
    for (TrialResult& t : ReadRawResults(dirs[d], config)) merged.trials.push_back(std::move(t));
  }
  // Every job exactly once.
  const std::vector<Job> jobs = ExperimentJobs(merged.config);
  const std::vector<SweepPoint> points = ExpandSweep(merged.config.sweep);
  auto job_index = [&](const TrialResult& t) {
    return JobIndex(points.size(), merged.config.trials, t.method_index, t.point_index, t.trial);
  };
  std::vector<int> seen(jobs.size(), 0);
  for (const TrialResult& t : merged.trials) ++seen.at(job_index(t));
  for (const Job& job : jobs) {
    if (seen[job.index] == 1) continue;
    throw std::runtime_error("--merge: job " + std::to_string(job.index) + " (" + DescribeJob(merged.config, points, job) +
                             (seen[job.index] == 0 ? ") is in none of the directories (a shard missing?)"
                                                   : ") appears in more than one directory"));
  }
  std::sort(merged.trials.begin(), merged.trials.end(),
            [&](const TrialResult& a, const TrialResult& b) { return job_index(a) < job_index(b); });
  return merged;
}

}  // namespace slt
