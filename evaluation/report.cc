#include "evaluation/report.h"

#include <algorithm>
#include <cstdio>
#include <utility>
#include <vector>

#include "common/table.h"

namespace slt {
namespace {

// "100 of 600 estimate poses (16.7 %)" when the fraction is short, "" otherwise.
std::string Shortfall(size_t associated, size_t total, const char* what, double min_fraction) {
  const double fraction = total == 0 ? 0.0 : static_cast<double>(associated) / static_cast<double>(total);
  if (fraction >= min_fraction) return "";
  return std::to_string(associated) + " of " + std::to_string(total) + " " + what + " poses" +
         StringPrintf(" (%.1f %%)", 100.0 * fraction);
}

// One row per metric: its name, then evo's statistics with six decimals.
std::string StatisticsTable(const TrajectoryErrors& errors) {
  Table table;
  table.columns.emplace_back("metric", Table::Align::kLeft, "", 22);
  for (const char* column : {"rmse", "mean", "median", "std", "min", "max"}) {
    table.columns.emplace_back(column, Table::Align::kRight, "", 10);
  }
  for (const auto& [name, s] : {std::pair<const char*, const ErrorStatistics&>{"ATE translation (m)", errors.ate_trans_m},
                                {"ATE rotation (deg)", errors.ate_rot_deg},
                                {"RPE translation (m)", errors.rpe_trans_m},
                                {"RPE rotation (deg)", errors.rpe_rot_deg}}) {
    std::vector<std::string> cells = {name};
    for (double v : {s.rmse, s.mean, s.median, s.std, s.min, s.max}) cells.push_back(StringPrintf("%.6f", v));
    table.AddRow(std::move(cells));
  }
  return table.Text();
}

}  // namespace

std::string AssociationWarning(const TrajectoryErrors& errors, double min_fraction) {
  const std::string est = Shortfall(errors.associated_poses, errors.est_poses, "estimate", min_fraction);
  const std::string gt = Shortfall(errors.associated_poses, errors.gt_poses, "ground-truth", min_fraction);
  if (est.empty() && gt.empty()) return "";
  const std::string window = StringPrintf("%g s", errors.options.max_time_diff_s);
  std::string text = "only ";
  if (!est.empty()) text += est + " are associated with a ground-truth pose within " + window;
  if (!est.empty() && !gt.empty()) text += ", and only ";
  if (!gt.empty()) text += gt + " with an estimate pose";
  return text + ": the errors describe part of the run only, or two different runs (below " +
         StringPrintf("%g %%", 100.0 * min_fraction) + " of either trajectory)";
}

std::string ErrorTable(const TrajectoryErrors& errors) {
  std::string alignment = AlignmentName(errors.options.alignment);
  if (errors.options.alignment == Alignment::kSim3) alignment += StringPrintf(" (scale %.6g)", errors.alignment.scale);
  std::string table = "associated " + std::to_string(errors.associated_poses) + " of " +
                      std::to_string(errors.est_poses) + " estimate and " + std::to_string(errors.associated_poses) +
                      " of " + std::to_string(errors.gt_poses) + " ground-truth poses (max time difference " +
                      StringPrintf("%g s", errors.options.max_time_diff_s) + "); alignment " + alignment + "\n";
  table += StatisticsTable(errors);
  const int delta = errors.options.rpe_delta_frames;
  table += "RPE: " + std::to_string(errors.rpe_trans_m.count) + " pairs (i, i + " + std::to_string(delta) + "), " +
           (errors.options.rpe_all_pairs ? "every i" : "i = 0, " + std::to_string(delta) + ", " +
                                                           std::to_string(2 * delta) + ", ...") + "\n";
  const FrameError& f = errors.Final();
  table += "final error (frame " + std::to_string(f.frame) + StringPrintf(", time %g s): ", f.time_s) +
           StringPrintf("translation %.6f m, ", f.trans_err_m) + StringPrintf("rotation %.6f deg\n", f.rot_err_deg);
  return table;
}

}  // namespace slt
