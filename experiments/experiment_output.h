// What an experiment writes (docs/experiments.md, "Outputs"), how shard outputs are read back
// and merged, and the summary statistics over trials.
//
//   DIR/raw/trials.csv           one row per (method, sweep point, trial)
//   DIR/raw/curves.csv           per-frame errors of every trial (per_frame_curves)
//   DIR/raw/trajectories/        TUM files of the saved trials, index.csv
//   DIR/summary.csv, .md, .tex   mean, median, 95 % interval per (method, sweep point)
//   DIR/curves.csv               mean (and median) error per frame over trials (per_frame_curves)
//   DIR/config.resolved.json     the config with every default filled in
//   DIR/run.json                 version, machine, threads, wall time, shard
// Every file is written atomically (temporary file + rename).
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "experiments/experiment_config.h"
#include "evaluation/statistics.h"
#include "experiments/trial_result.h"

namespace slt {

// raw/trials.csv, raw/curves.csv (when any trial has a curve) and raw/trajectories/.
void WriteRawResults(const std::string& dir, const ExperimentConfig& config, const std::vector<TrialResult>& trials);
// Reads them back (what WriteRawResults wrote, exactly: numbers round-trip). Throws
// std::runtime_error naming the file and line on malformed or foreign rows.
std::vector<TrialResult> ReadRawResults(const std::string& dir, const ExperimentConfig& config);

struct SummaryRow {
  size_t method = 0;
  size_t point = 0;
  size_t trials = 0;         // trials of this (method, point)
  size_t finite_trials = 0;  // with finite poses throughout; the statistics use these
  std::array<Summary, kNumTrialMetrics> metrics;
};
// One row per (method, point) present in `trials`, in (method, point) order.
std::vector<SummaryRow> SummarizeTrials(const ExperimentConfig& config, const std::vector<TrialResult>& trials);

std::string SummaryCsv(const ExperimentConfig& config, const std::vector<SummaryRow>& rows);
std::string SummaryMarkdown(const ExperimentConfig& config, const std::vector<SummaryRow>& rows);
std::string SummaryLatex(const ExperimentConfig& config, const std::vector<SummaryRow>& rows);
// Mean and median error per frame over the finite trials of each (method, point).
std::string CurvesCsv(const ExperimentConfig& config, const std::vector<TrialResult>& trials);

// "- <point>: a (0.18) < b (1.5)\n" per sweep point: the methods from the lowest mean rotation
// error at the metrics frame up (the full ordering, of which a config's expect_better are pairs).
std::string OrderingText(const ExperimentConfig& config, const std::vector<SummaryRow>& rows);

// summary.csv, summary.md, summary.tex and (per_frame_curves) curves.csv.
void WriteSummaries(const std::string& dir, const ExperimentConfig& config, const std::vector<TrialResult>& trials);

// Shard outputs combined: the config (identical in every shard) and every trial, in job
// order. Throws std::runtime_error when the configs differ, a job is missing or appears twice.
struct MergedRun {
  ExperimentConfig config;
  std::vector<TrialResult> trials;
  nlohmann::json shards = nlohmann::json::array();  // each shard's run.json
};
MergedRun MergeShardOutputs(const std::vector<std::string>& dirs);

}  // namespace slt
