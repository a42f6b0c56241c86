// bench_table1: the paper's Table 1 (time per stereo frame at the minimum number of lines and
// at 10, 20 and 30 lines) for every registered tracker, in one run so the ratios hold.
//
//   bench_table1 [--out DIR] [--extra 'METHOD JSON']... [--benchmark_filter=REGEX] [--benchmark_out=FILE] [...]
//
// --extra adds a row for a registered method with the given options after the default rows
// (e.g. --extra 'taylor_line_sfm {"window_frames": 20}', labelled "taylor_line_sfm
// (window_frames=20)"), measured in the same run.
//
// Each benchmark times one Track() call (prediction and update with every line of the frame)
// per iteration on one simulated paper-protocol sequence (noise +-2.5 px, 100 frames) in which
// exactly N lines are seen in both images of every frame; for methods that need primitive
// configurations (TrackerInfo::needs_primitive_configurations) about 30 % of the N lines, and
// at least 3, are cuboid edges (scene.paper.cuboid_fraction), the rest random lines, so that
// their frames are measured rather than lost. The tracker is reset and warmed up
// on the first kWarmupFrames frames before timing, and again whenever the sequence runs out;
// that reset happens between PauseTiming() and ResumeTiming(), once every ~90 iterations, so
// its cost and the pause overhead (two clock reads) are outside the measured time or amortised
// to well below 1 % of a frame. (Timing every call by hand with UseManualTime would add two
// clock reads to every iteration instead; both are accurate at these durations.)
//
// After the benchmarks, prints Table 1 (seconds per frame) as the paper lays it out, next to
// the paper's numbers, with the machine; --out DIR also writes table1.md, table1.tex and
// table1.json there (atomically).
#include <benchmark/benchmark.h>


#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "common/file_io.h"
#include "common/json_reader.h"
#include "common/machine_info.h"
#include "common/table.h"
#include "methods/pose_tracker.h"
#include "simulator/simulator.h"

namespace slt {
namespace {

constexpr int kWarmupFrames = 10;
constexpr int kFrames = 100;
const int kCounts[] = {10, 20, 30};

// The paper's Table 1 (1.7 GHz Intel), seconds per frame; a negative value is "> |value|".
struct PaperRow {
  const char* match;  // substring of the tracker name that maps to this row
  const char* title;
  double seconds[4];  // minimum, 10, 20, 30; NaN = N/A
};
const PaperRow kPaperRows[] = {
    {"trifocal", "The proposed approach (trifocal-line EKF)", {0.0014, 0.0025, 0.0049, 0.0078}},
    {"yu", "Yu's method (point EKF)", {0.0008, 0.0016, 0.0032, 0.0051}},
    {"elqursh", "Elqursh's method", {0.0002, NAN, NAN, NAN}},
    {"taylor", "Taylor's method", {-1.0, -1.0, -1.0, -1.0}},
};

// A sequence in which exactly `count` lines are seen in both images of every frame: the
// paper's scene with more random lines than needed, restricted to the first `count` ids that
// are observed in both images throughout (noise does not change which lines are observed).
// The first `cuboid_lines` ids of the scene are cuboid edges (they come first).
StereoSequence BenchSequence(int count, int cuboid_lines) {
  SimulationConfig config;
  config.seed = 1;
  config.frames = kFrames;
  config.noise.endpoint_px = 2.5;
  config.scene.paper.lines = std::max(80, 3 * count);
  config.scene.paper.cuboid_fraction = static_cast<double>(cuboid_lines) / config.scene.paper.lines;
  const SimulatedSequence sim = Simulate(config);
  std::map<std::int64_t, int> seen;
  for (const StereoFrame& f : sim.sequence.frames) {
    std::set<std::int64_t> left;
    for (const LineObservation& o : f.left) left.insert(o.id);
    for (const LineObservation& o : f.right) {
      if (left.count(o.id)) ++seen[o.id];
    }
  }
  std::set<std::int64_t> keep;
  for (const auto& [id, frames] : seen) {
    if (frames == kFrames && static_cast<int>(keep.size()) < count) keep.insert(id);
  }
  if (static_cast<int>(keep.size()) < count) {
    throw std::runtime_error("bench_table1: only " + std::to_string(keep.size()) + " lines are seen in every frame, need " +
                             std::to_string(count));
  }
  return FilterLines(sim.sequence, [&](std::int64_t id) { return keep.count(id) > 0; });
}

void BM_TrackFrame(benchmark::State& state, const std::string& method, const nlohmann::json& options,
                   std::shared_ptr<const StereoSequence> sequence) {
  std::unique_ptr<PoseTracker> tracker = CreateTracker(method, options, "--extra");
  auto warm_up = [&]() {
    tracker->Reset(sequence->rig);
    for (int k = 0; k < kWarmupFrames; ++k) tracker->Track(sequence->frames[k]);
  };
  warm_up();
  size_t next = kWarmupFrames;
  double used = 0.0;
  for (auto _ : state) {
    if (next == sequence->frames.size()) {
      state.PauseTiming();
      warm_up();
      next = kWarmupFrames;
      state.ResumeTiming();
    }
    const TrackerOutput out = tracker->Track(sequence->frames[next++]);
    benchmark::DoNotOptimize(out);
    used += out.features_used;
  }
  state.counters["lines"] = static_cast<double>(sequence->frames[0].left.size());
  // TrackerOutput::features_used: lines for a line tracker, points (two per line) for a point one.
  state.counters["features_used"] = benchmark::Counter(used, benchmark::Counter::kAvgIterations);
  // Seconds per frame from the real time (the reported time per iteration, in us; printed
  // with an SI prefix, e.g. "23.4us").
  state.counters["time_per_frame"] =
      benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

struct Cell {
  std::string method;
  int column = 0;  // 0 = minimum, 1..3 = 10, 20, 30
  int lines = 0;
};

// Collects the real time per iteration of each benchmark while printing as usual: the median
// aggregate when repetitions are asked for (--benchmark_repetitions, with or without
// --benchmark_report_aggregates_only), otherwise the mean of the runs.
class TableReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.error_occurred) continue;
      // Seconds per iteration (GetAdjustedRealTime is in the benchmark's time unit).
      const double seconds = run.GetAdjustedRealTime() / benchmark::GetTimeUnitMultiplier(run.time_unit);
      const std::string& name = run.run_name.function_name;
      if (run.run_type == Run::RT_Iteration) {
        auto& entry = mean_[name];
        entry.first += seconds;
        entry.second += 1;
      } else if (run.aggregate_name == "median") {
        median_[name] = seconds;
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }
  // NaN when the benchmark did not run (filtered out).
  double Seconds(const std::string& name) const {
    if (const auto m = median_.find(name); m != median_.end()) return m->second;
    const auto it = mean_.find(name);
    return it == mean_.end() ? NAN : it->second.first / it->second.second;
  }

 private:
  std::map<std::string, std::pair<double, int>> mean_;
  std::map<std::string, double> median_;
};

std::string BenchmarkName(const Cell& cell) {
  return "Table1/" + cell.method + "/" + (cell.column == 0 ? "min" : std::to_string(kCounts[cell.column - 1])) +
         "_lines:" + std::to_string(cell.lines);
}

// Our measurement; "not run" when the benchmark was filtered out.
std::string Seconds(double s) {
  if (std::isnan(s)) return "not run";
  if (s < 0) return "> " + std::to_string(static_cast<int>(-s)) + " s";
  // Fixed notation like the paper's, with at least two significant digits.
  const int decimals = std::max(4, 1 - static_cast<int>(std::floor(std::log10(s))));
  return StringPrintf("%.*f s", decimals, s);
}

// The paper's numbers as printed.
std::string PaperSeconds(double s) {
  if (std::isnan(s)) return "N/A";
  if (s < 0) return "> " + std::to_string(static_cast<int>(-s)) + " s";
  return StringPrintf("%g s", s);
}

// Table 1's columns, the first titled `first`.
Table Table1Columns(const char* first) {
  Table table;
  table.columns = {{first, Table::Align::kLeft}, {"Minimum number"}, {"10"}, {"20"}, {"30"}};
  return table;
}

// The paper's rows, as printed.
Table PaperTable() {
  Table table = Table1Columns("Algorithm");
  for (const PaperRow& row : kPaperRows) {
    std::vector<std::string> cells = {row.title};
    for (double s : row.seconds) cells.push_back(PaperSeconds(s));
    table.AddRow(std::move(cells));
  }
  return table;
}

const PaperRow* PaperRowFor(const std::string& method) {
  for (const PaperRow& row : kPaperRows) {
    if (method.find(row.match) != std::string::npos) return &row;
  }
  return nullptr;
}

}  // namespace
}  // namespace slt

int main(int argc, char** argv) {
  using namespace slt;
  // Our own flags (--out DIR or --out=DIR, --extra 'METHOD JSON'); everything else goes to
  // Google Benchmark.
  std::string out_dir;
  std::vector<std::string> extras;
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) {
      out_dir = argv[++i];
    } else if (a.rfind("--out=", 0) == 0) {
      out_dir = a.substr(6);
    } else if (a == "--extra" && i + 1 < argc) {
      extras.push_back(argv[++i]);
    } else if (a.rfind("--extra=", 0) == 0) {
      extras.push_back(a.substr(8));
    } else {
      args.push_back(argv[i]);
    }
  }
  int bench_argc = static_cast<int>(args.size());
  benchmark::Initialize(&bench_argc, args.data());
  if (benchmark::ReportUnrecognizedArguments(bench_argc, args.data())) return 2;
  // The outputs are checked before the benchmarks run (minutes), not after.
  const std::vector<std::string> out_files = {"table1.json", "table1.md", "table1.tex"};
  if (!out_dir.empty()) {
    try {
      std::error_code error;
      std::filesystem::create_directories(out_dir, error);
      if (error) throw std::runtime_error("--out " + out_dir + ": cannot create directory (" + error.message() + ")");
      for (const std::string& file : out_files) CheckWritable("--out", (std::filesystem::path(out_dir) / file).string());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_table1: error: %s\n", e.what());
      return 1;
    }
  }

  std::vector<Cell> cells;
  std::vector<std::string> methods;
  try {
    std::map<std::pair<int, int>, std::shared_ptr<const StereoSequence>> sequences;
    auto sequence_for = [&](int lines, bool cuboids) {
      const std::pair<int, int> key(lines, cuboids ? std::max(3, static_cast<int>(std::lround(0.3 * lines))) : 0);
      if (!sequences.count(key)) sequences[key] = std::make_shared<const StereoSequence>(BenchSequence(key.first, key.second));
      return sequences[key];
    };
    // Rows: every registered tracker with its defaults, then the --extra ones.
    std::vector<std::pair<std::string, nlohmann::json>> rows;
    for (const TrackerInfo& info : RegisteredTrackers()) {
      if (!info.plumbing_only) rows.emplace_back(info.name, nlohmann::json::object());
    }
    for (const std::string& extra : extras) {
      const size_t space = extra.find(' ');
      const std::string method = extra.substr(0, space);
      nlohmann::json options = nlohmann::json::object();
      if (space != std::string::npos) {
        try {
          options = nlohmann::json::parse(extra.substr(space + 1));
        } catch (const nlohmann::json::exception& e) {
          throw std::invalid_argument("--extra '" + extra + "': not JSON after the method name: " + e.what());
        }
      }
      CreateTracker(method, options, "--extra '" + extra + "'");  // throws on a bad name or option
      rows.emplace_back(method, options);
    }
    for (const auto& [method, options] : rows) {
      // "taylor_line_sfm (window_frames=20)": no braces or quotes for the Markdown and LaTeX tables.
      std::string label = method;
      for (const auto& [key, value] : options.items()) {
        label += (label == method ? " (" : ", ") + key + "=" + (value.is_string() ? value.get<std::string>() : value.dump());
      }
      if (label != method) label += ")";
      methods.push_back(label);
      for (int column = 0; column < 4; ++column) {
        Cell cell{label, column, column == 0 ? FindTracker(method).minimum_lines : kCounts[column - 1]};
        cells.push_back(cell);
        benchmark::RegisterBenchmark(BenchmarkName(cell).c_str(), BM_TrackFrame, method, options,
                                     sequence_for(cell.lines, FindTracker(method).needs_primitive_configurations))
            ->Unit(benchmark::kMicrosecond)
            ->UseRealTime();
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_table1: error: %s\n", e.what());
    return 1;
  }

  TableReporter reporter;
  const size_t benchmarks_run = benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  if (benchmarks_run == 0) {
    // A table of "not run" cells would overwrite the measured one.
    std::fprintf(stderr, "bench_table1: error: --benchmark_filter matches no benchmark; nothing written\n");
    return 1;
  }

  // Table 1, ours and the paper's.
  const std::string machine = CpuModel() + ", " + std::to_string(CpuCores()) + " cores, " + CompilerName() + " " + BuildType();
  std::map<std::string, std::array<double, 4>> ours;
  std::map<std::string, std::array<int, 4>> lines;
  for (const Cell& cell : cells) {
    ours[cell.method][cell.column] = reporter.Seconds(BenchmarkName(cell));
    lines[cell.method][cell.column] = cell.lines;
  }
  std::string md = "## Table 1: time per stereo frame (s)\n\nThis machine: " + machine +
                   "; one Track() call (prediction and update with every line), single thread, paper protocol "
                   "(noise ±2.5 px), exactly N lines in both images of every frame (about 30 % of them, at "
                   "least 3, on cuboids for methods that need primitive configurations).\n\n";
  // Our rows; the Markdown table gives the minimum's number of lines in its cell.
  auto ours_table = [&](bool line_counts) {
    Table table = Table1Columns("Method");
    for (const std::string& m : methods) {
      std::vector<std::string> cells = {m};
      for (int c = 0; c < 4; ++c) cells.push_back(Seconds(ours[m][c]));
      const int n = lines[m][0];
      if (line_counts) cells[1] += " (" + std::to_string(n) + (n == 1 ? " line)" : " lines)");
      table.AddRow(std::move(cells));
    }
    return table;
  };
  md += ours_table(true).Markdown();
  md += "\nThe paper (Lee et al. 2015, Table 1; 1.7 GHz Intel processor):\n\n" + PaperTable().Markdown();
  md += "\nRatios (time at 30 lines / time at 10 lines):";
  for (const std::string& m : methods) {
    md += m == methods.front() ? " " : "; ";
    md += StringPrintf("%s %.2f", m.c_str(), ours[m][3] / ours[m][1]);
    if (const PaperRow* row = PaperRowFor(m); row != nullptr && row->seconds[1] > 0) {
      md += StringPrintf(" (paper %.2f)", row->seconds[3] / row->seconds[1]);
    }
  }
  md += ".\n";
  std::cout << "\n" << md << std::flush;

  if (!out_dir.empty()) {
    try {
      std::filesystem::create_directories(out_dir);
      nlohmann::json j = VersionAndMachineJson(SourceDir());
      j["program"] = "bench_table1";
      j["started_utc"] = UtcNow();
      j["unit"] = "seconds per stereo frame";
      j["columns"] = {"minimum", "10", "20", "30"};
      for (const std::string& m : methods) {
        nlohmann::json row;
        for (int c = 0; c < 4; ++c) {
          row["seconds"].push_back(std::isnan(ours[m][c]) ? nlohmann::json(nullptr) : nlohmann::json(ours[m][c]));
          row["lines"].push_back(lines[m][c]);
        }
        j["methods"][m] = row;
      }
      for (const PaperRow& row : kPaperRows) {
        nlohmann::json r;
        for (double s : row.seconds) {
          r.push_back(std::isnan(s) ? nlohmann::json(nullptr) : s < 0 ? nlohmann::json("> " + std::to_string(int(-s)) + " s") : nlohmann::json(s));
        }
        j["paper"][row.title] = r;
      }
      std::string tex = "% Table 1, generated by bench_table1 on " + machine + "; needs \\usepackage{booktabs}\n";
      Table tex_table = ours_table(false);
      tex_table.AddSection("Paper (1.7 GHz Intel)");
      tex_table.Append(PaperTable());
      tex += tex_table.Latex();
      WriteJsonFile((std::filesystem::path(out_dir) / out_files[0]).string(), j);
      WriteTextFileAtomically((std::filesystem::path(out_dir) / out_files[1]).string(), md);
      WriteTextFileAtomically((std::filesystem::path(out_dir) / out_files[2]).string(), tex);
      std::cout << "bench_table1: wrote " << out_dir << "/table1.{md,tex,json}" << std::endl;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_table1: error: %s\n", e.what());
      return 1;
    }
  }
  return 0;
}
