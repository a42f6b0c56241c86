// The command-line programs end to end: simulate -> track -> evaluate, a sequence written by
// another program (hand-written file), and the one-line errors.
#include <gtest/gtest.h>

#include <algorithm>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>

#include "common/csv.h"
#include "common/json_reader.h"
#include "dataset/trajectory.h"
#include "frontend/frontend_audit.h"
#include "simulator/simulation_config.h"
#include "simulator/simulator.h"

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
    r = RunCommand(Bin("evaluate") + " --gt " + Path("run/gt.tum") + " --est " + traj + " --json " +
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

// evaluate as a person uses it: the table by default, positional files, evo's alignment flags,
// JSON on request, the association check and the plot.
TEST_F(EndToEnd, EvaluatePrintsATableAndWarnsWhenTheRunsDoNotMatch) {
  {
    std::ofstream(Path("sim.json")) << R"({"frames": 30, "noise": {"endpoint_px": 1.0}})";
  }
  Result r = RunCommand(Bin("simulate") + " " + Path("sim.json") + " --out " + Path("run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(Bin("track") + " --method trifocal_line_ekf --input " + Path("run/seq.json") + " --output " +
                 Path("est.tum"));
  ASSERT_EQ(r.exit_code, 0) << r.output;

  r = RunCommand(Bin("evaluate") + " " + Path("run/gt.tum") + " " + Path("est.tum"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("associated 30 of 30 estimate and 30 of 30 ground-truth poses"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("metric                       rmse       mean     median        std        min        max\n"
                          "ATE translation (m) "), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find('{'), std::string::npos) << "no JSON by default: " << r.output;
  EXPECT_LE(std::count(r.output.begin(), r.output.end(), '\n'), 10) << r.output;

  // evo's -as: Sim(3) alignment; --format json prints what --json writes.
  r = RunCommand(Bin("evaluate") + " -as --format json --json " + Path("m.json") + " " + Path("run/gt.tum") + " " +
                 Path("est.tum"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json printed = nlohmann::json::parse(r.output);
  EXPECT_EQ(printed.at("alignment"), "sim3");
  EXPECT_EQ(printed, ReadJsonFile(Path("m.json")));
  r = RunCommand(Bin("evaluate") + " -a --gt " + Path("run/gt.tum") + " --est " + Path("est.tum"));
  EXPECT_NE(r.output.find("; alignment se3\n"), std::string::npos) << r.output;
  r = RunCommand(Bin("evaluate") + " -s " + Path("run/gt.tum") + " " + Path("est.tum"));
  EXPECT_EQ(r.exit_code, 2) << r.output;

  // A ground truth of 10 poses against the estimate's 30: a warning, an error with --strict
  // (and then no output file).
  {
    std::ifstream in(Path("run/gt.tum"));
    std::ofstream out(Path("short_gt.tum"));
    std::string line;
    for (int k = 0; k < 11 && std::getline(in, line); ++k) out << line << "\n";  // header + 10 poses
  }
  r = RunCommand("(" + Bin("evaluate") + " " + Path("short_gt.tum") + " " + Path("est.tum") + " > /dev/null)");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("evaluate: warning: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("only 10 of 30 estimate poses (33.3 %)"), std::string::npos) << r.output;
  r = RunCommand(Bin("evaluate") + " --strict --json " + Path("strict.json") + " " + Path("short_gt.tum") + " " +
                 Path("est.tum"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.rfind("evaluate: error: ", 0), 0u) << r.output;
  EXPECT_FALSE(fs::exists(Path("strict.json")));
  r = RunCommand(Bin("evaluate") + " --strict " + Path("run/gt.tum") + " " + Path("est.tum"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST_F(EndToEnd, EvaluatePlotsAndSimulateWritesItsScene) {
  Result r = RunCommand("echo '{\"frames\": 20}' | " + Bin("simulate") + " - --out " + Path("run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The scene: a header and the paper protocol's 40 segments.
  std::ifstream scene(Path("run/scene.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(scene, line));
  EXPECT_EQ(line, "id,x1,y1,z1,x2,y2,z2");
  int segments = 0;
  while (std::getline(scene, line)) ++segments;
  EXPECT_EQ(segments, 40);

  r = RunCommand(Bin("evaluate") + " " + Path("run/gt.tum") + " " + Path("run/gt.tum") + " --plot " + Path("p.png"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream png(Path("p.png"), std::ios::binary);
  char magic[4] = {};
  png.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  r = RunCommand(Bin("evaluate") + " " + Path("run/gt.tum") + " " + Path("run/gt.tum") + " --plot " + Path("p.jpg"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

double AteRmse(const std::string& metrics_path) {
  return ReadJsonFile(metrics_path).at("ate_trans_m").at("rmse").get<double>();
}

// Issue 18: simulate --images -> track_images -> evaluate on a rendered room loop, against
// the same tracker on the perfect observations of the same sequence (seq.json: the visible
// ground-truth edges, noise-free); the saved observations replay with `track` to the same
// trajectory. docs/frontend.md gives the numbers measured on longer runs.
TEST_F(EndToEnd, TrackImagesOnARenderedRoom) {
  {
    // The room loop of results/frontend (frontend_audit.h RenderedRoomConfig(200, true): EuRoC's
    // image size, focal length and baseline, 1.1 cm per frame), the setting docs/frontend.md
    // measures the front end on.
    std::ofstream(Path("sim.json")) << RenderedRoomConfig(200, true).dump();
  }
  Result r = RunCommand(Bin("simulate") + " " + Path("sim.json") + " --out " + Path("run") + " --images --threads 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string images_traj = Path("images.tum"), perfect_traj = Path("perfect.tum");
  // --viz replaces its folder whole: a folder of the user's own files is refused before any work.
  fs::create_directories(Path("mine"));
  std::ofstream(Path("mine/notes.txt")) << "mine";
  r = RunCommand(Bin("track_images") + " --path " + Path("run") + " --method trifocal_line_ekf --output " +
                 Path("refused.tum") + " --viz " + Path("mine"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--viz " + Path("mine") + ": holds files no track_images wrote"), std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(Path("mine/notes.txt")));
  EXPECT_FALSE(fs::exists(Path("refused.tum")));
  r = RunCommand(Bin("track_images") + " --path " + Path("run") + " --method trifocal_line_ekf --output " + images_traj +
                 " --save-observations " + Path("obs.json") + " --viz " + Path("viz") + " --log " + Path("log.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string summary = r.output;
  EXPECT_NE(summary.find("200 frames"), std::string::npos) << summary;
  EXPECT_TRUE(fs::exists(Path("viz/detections_first_pair.png")));
  EXPECT_TRUE(fs::exists(Path("viz/reprojection_error.png")));
  EXPECT_TRUE(fs::exists(Path("viz/reprojection_000199.png")));
  // An earlier --viz folder may be replaced, but not with an output of the run inside it: the
  // replacement would delete it.
  r = RunCommand(Bin("track_images") + " --path " + Path("run") + " --method trifocal_line_ekf --output " +
                 Path("viz/traj.tum") + " --viz " + Path("viz"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--viz " + Path("viz") + ": holds --output " + Path("viz/traj.tum")), std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(Path("viz/reprojection_error.png")));
  // A frame range is integers and nothing else (the whole text is read).
  r = RunCommand(Bin("track_images") + " --path " + Path("run") + " --method trifocal_line_ekf --output " +
                 Path("frames.tum") + " --frames 1x:5");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--frames: expected A:B with integers, got '1x:5'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(Path("frames.tum")));
  const Trajectory from_images = ReadTumTrajectory(images_traj);
  ASSERT_EQ(from_images.size(), 200u);

  r = RunCommand(Bin("track") + " --method trifocal_line_ekf --input " + Path("run/seq.json") + " --output " +
                 perfect_traj);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const std::string name : {"images", "perfect"}) {
    r = RunCommand(Bin("evaluate") + " --gt " + Path("run/gt.tum") + " --est " + Path(name + ".tum") + " --out " +
                   Path(name + ".metrics.json"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const double ate_images = AteRmse(Path("images.metrics.json")), ate_perfect = AteRmse(Path("perfect.metrics.json"));
  // The ATE of this sequence (a 2.2 m loop) from the images and from the perfect observations is
  // the room row of results/frontend/sequences.md; docs/frontend.md gives it over ten draws of
  // the scene. Issue 18 asks for 1.5x the perfect run; the front end does not reach it
  // (docs/frontend.md says why): these bounds guard what it does today. (The earlier 40-frame loop at 1.8 cm per frame swung between 27 and
  // 244 mm with small changes of the front end: no guard at all.)
  EXPECT_LT(ate_images, 0.015) << "perfect observations: " << ate_perfect;
  EXPECT_LT(ate_perfect, 0.005);
  RecordProperty("ate_images_mm", std::to_string(1e3 * ate_images));
  RecordProperty("ate_perfect_mm", std::to_string(1e3 * ate_perfect));
  EXPECT_NE(summary.find(", 0 lost;"), std::string::npos) << summary;
  // Every lost line has one reason: per frame the log's lost_* columns add up to its lost
  // column, and over the run to the summary's "lines lost".
  const CsvTable log = ReadCsvFile(Path("log.csv"));
  const size_t lost_column = log.Column("lost");
  std::vector<size_t> reason_columns;
  for (const char* reason : {"flow_at_border", "flow_points", "refit", "snap", "direction", "short", "stereo"}) {
    reason_columns.push_back(log.Column(std::string("lost_") + reason));
  }
  long lost_lines = 0;
  for (const std::vector<std::string>& row : log.rows) {
    int by_reason = 0;
    for (const size_t c : reason_columns) by_reason += std::stoi(row[c]);
    EXPECT_EQ(by_reason, std::stoi(row[lost_column])) << row[0];
    lost_lines += by_reason;
  }
  EXPECT_GT(lost_lines, 0);
  EXPECT_NE(summary.find("lines lost: " + std::to_string(lost_lines) + " ("), std::string::npos) << summary;
  // Fig. 9: over the first 40 frames (the paper's figure spans a short run), the first pair's
  // lines re-projected with the recovered motion stay within 0.5 deg of the tracked ones; the
  // curve goes on while any of them is tracked.
  std::ifstream curve(Path("viz/reprojection_error.csv"));
  std::string line;
  std::getline(curve, line);
  int points = 0, early_points = 0;
  double early_max = 0.0;
  while (std::getline(curve, line)) {
    const int frame = std::stoi(line.substr(0, line.find(',')));
    const double angle = std::stod(line.substr(line.find(',') + 1));
    if (frame < 40) {
      EXPECT_LT(angle, 0.5) << line;
      early_max = std::max(early_max, angle);
      ++early_points;
    }
    ++points;
  }
  EXPECT_GE(early_points, 30);
  EXPECT_GE(points, early_points);
  RecordProperty("fig9_max_angle_first_40_frames_deg", std::to_string(early_max));

  // The saved observations replay to the same trajectory.
  r = RunCommand(Bin("track") + " --method trifocal_line_ekf --input " + Path("obs.json") + " --output " +
                 Path("replay.tum"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Trajectory replay = ReadTumTrajectory(Path("replay.tum"));
  ASSERT_EQ(replay.size(), from_images.size());
  for (size_t k = 0; k < replay.size(); ++k) {
    EXPECT_LT((replay[k].world_from_cam.translation - from_images[k].world_from_cam.translation).norm(), 1e-6) << k;
  }
}

// A table cell of a Markdown row: the `column`-th between the pipes.
std::string Cell(const std::string& row, int column) {
  std::stringstream cells(row);
  std::string cell;
  for (int c = 0; c <= column + 1; ++c) std::getline(cells, cell, '|');
  return cell.substr(cell.find_first_not_of(' '), cell.find_last_not_of(' ') - cell.find_first_not_of(' ') + 1);
}

// The lines of `path` that start with `prefix`.
std::vector<std::string> RowsStartingWith(const std::string& path, const std::string& prefix) {
  std::ifstream in(path);
  std::vector<std::string> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(prefix, 0) == 0) rows.push_back(line);
  }
  return rows;
}

TEST_F(EndToEnd, MeasureFrontendOverSeveralDraws) {
  const Result r = RunCommand(Bin("measure_frontend") + " --frames 12 --skip-detectors --scene paper --seed 3 --draws 2 --out " +
                              Path("m"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(Path("m/detectors.md")));
  const std::string scene = "| paper scene";
  const std::vector<std::string> first = RowsStartingWith(Path("m/sequences.md"), scene);
  const std::vector<std::string> draws = RowsStartingWith(Path("m/draws.md"), scene);
  // The summary, then each draw: --seed 3 and 4, the first of them the draw of sequences.md.
  ASSERT_EQ(first.size(), 2u);  // its row in the accuracy table and in the times table
  ASSERT_EQ(draws.size(), 3u) << r.output;
  EXPECT_EQ(Cell(draws[0], 1), "2");
  EXPECT_EQ(Cell(draws[1], 1), "3");
  EXPECT_EQ(Cell(draws[2], 1), "4");
  EXPECT_EQ(Cell(draws[1], 9), Cell(first[0], 16)) << "ATE images of draw 3";
  const double a = std::stod(Cell(draws[1], 9)), b = std::stod(Cell(draws[2], 9));
  EXPECT_NE(a, b) << "two draws of the scene gave the same ATE";
  EXPECT_NEAR(std::stod(Cell(draws[0], 4)), std::max(a, b), 0.006) << "the largest ATE";
  EXPECT_NEAR(std::stod(Cell(draws[0], 3)), 0.5 * (a + b), 0.006) << "the mean ATE";
  std::ifstream header(Path("m/draws.md"));
  std::string line;
  std::getline(header, line);
  EXPECT_NE(line.find("--seed 3 --draws 2"), std::string::npos) << line;
  EXPECT_EQ(line.find("--step"), std::string::npos) << "the sequences do not depend on the detector table's step: " << line;
  // The detector table alone: no draws.md (the draws are the sequences'), and its header names
  // the detector table's options, not the tracker's.
  const Result detectors = RunCommand(Bin("measure_frontend") +
                                      " --frames 4 --step 2 --skip-sequences --scene paper --draws 2 --out " + Path("d"));
  ASSERT_EQ(detectors.exit_code, 0) << detectors.output;
  EXPECT_FALSE(fs::exists(Path("d/draws.md")));
  EXPECT_FALSE(fs::exists(Path("d/sequences.md")));
  const std::string detector_header = ReadTextFile(Path("d/detectors.md")).substr(0, 120);
  EXPECT_EQ(detector_header.rfind("Generated by `measure_frontend --frames 4 --step 2 --draws 2`", 0), 0u)
      << detector_header;
  // With --draws, the front end's detector on each draw: the first draw's recall is the detector
  // table's, the pooled count the draws' sum.
  const std::vector<std::string> detector_rows = RowsStartingWith(Path("d/detectors.md"), scene);
  ASSERT_EQ(detector_rows.size(), 5u + 1u + 2u) << ReadTextFile(Path("d/detectors.md"));
  const std::string& table_edlines = detector_rows[1];
  ASSERT_EQ(Cell(table_edlines, 1), "edlines");
  const std::string& pooled = detector_rows[5];
  EXPECT_EQ(Cell(pooled, 1), "edlines");
  EXPECT_EQ(Cell(pooled, 2), "2");
  EXPECT_EQ(Cell(detector_rows[6], 1), "1");
  EXPECT_EQ(Cell(detector_rows[7], 1), "2");
  EXPECT_EQ(Cell(detector_rows[6], 4), Cell(table_edlines, 4)) << "draw 1's recall";
  EXPECT_EQ(std::stoi(Cell(pooled, 3)), std::stoi(Cell(detector_rows[6], 2)) + std::stoi(Cell(detector_rows[7], 2)));
  for (const std::string& draw : {detector_rows[6], detector_rows[7]}) {
    EXPECT_NEAR(std::stod(Cell(draw, 3)) / std::stod(Cell(draw, 2)), std::stod(Cell(draw, 4)), 5e-4) << draw;
  }
  const double worst = std::stod(Cell(pooled, 5)), best = std::stod(Cell(pooled, 6));
  EXPECT_EQ(worst, std::min(std::stod(Cell(detector_rows[6], 4)), std::stod(Cell(detector_rows[7], 4))));
  EXPECT_EQ(best, std::max(std::stod(Cell(detector_rows[6], 4)), std::stod(Cell(detector_rows[7], 4))));
  EXPECT_LE(worst, std::stod(Cell(pooled, 4)));
  EXPECT_GE(best, std::stod(Cell(pooled, 4)));
  // --config's front-end options go over the scene's own (PaperSceneOptions: three earlier
  // pairs), and the note names the options the scene ran with; the paper scene's shipped
  // front-end options are valid and reach it.
  {
    std::ofstream(Path("one_pair.json")) << R"({"matching": {"previous_pairs": 1}})";
  }
  for (const auto& [config, expected] :
       {std::pair{Path("one_pair.json"), std::string(R"("previous_pairs":1)")},
        {std::string(SLT_SOURCE_DIR) + "/frontend/frontend_configs/paper_scene.json",
         std::string(R"("msld_ratio":0.9)")}}) {
    const Result run = RunCommand(Bin("measure_frontend") + " --frames 4 --skip-detectors --scene paper --config " + config +
                                  " --out " + Path("c"));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const std::string text = ReadTextFile(Path("c/sequences.md"));
    const size_t note = text.find("Front-end options of paper scene");
    ASSERT_NE(note, std::string::npos) << text;
    const std::string note_line = text.substr(note, text.find('\n', note) - note);
    EXPECT_NE(note_line.find(expected), std::string::npos) << note_line;
    EXPECT_NE(note_line.find(R"("min_disparity_px")"), std::string::npos) << "the scene's own options: " << note_line;
  }
}

// The cell of `row` under the column named `name` of the table whose header is `header`.
std::string CellNamed(const std::string& header, const std::string& row, const std::string& name) {
  std::stringstream cells(header);
  std::string cell;
  std::getline(cells, cell, '|');  // before the first pipe
  for (int column = 0; std::getline(cells, cell, '|'); ++column) {
    const size_t first = cell.find_first_not_of(' ');
    if (first != std::string::npos && cell.substr(first, cell.find_last_not_of(' ') - first + 1) == name) {
      return Cell(row, column);
    }
  }
  ADD_FAILURE() << "no column '" << name << "' in " << header;
  return "nan";
}

// Issue 18's numbers on the rendered room (752 x 480) and corridor (640 x 480) at the issue's
// motion (200 frames, about 1 cm per frame), one draw each, as results/frontend measures them
// over ten: the default detector's recall of the visible ground-truth segments >= 40 px (within
// 2 px and 2 deg) >= 90 %, stereo matches and temporal tracks >= 99 % correct (same criteria), and
// the ATE of trifocal_line_ekf on the images within 1.5x of the same tracker on the scene's
// visible ground-truth lines with Gaussian noise of the front end's endpoint RMS. Bounds are the
// issue's; the numbers measured on this draw are in docs/frontend.md (Tests). The paper scene's
// bound is a median over hundreds of draws (results/frontend/paper_scene_100_frames), not a
// test.
TEST_F(EndToEnd, MeasureFrontendMeetsIssue18sBoundsOnTheRoomAndCorridor) {
  for (const auto& [scene, out] : {std::pair{std::string("room 752x480"), std::string("room")},
                                   std::pair{std::string("corridor 640x480"), std::string("corridor")}}) {
    const Result r = RunCommand(Bin("measure_frontend") + " --frames 200 --step 20 --detector edlines --scene '" +
                                scene + "' --out " + Path(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::vector<std::string> detector_rows = RowsStartingWith(Path(out + "/detectors.md"), "| ");
    const std::vector<std::string> sequence_rows = RowsStartingWith(Path(out + "/sequences.md"), "| ");
    // Each table: its header, then the scene's row (sequences.md: the accuracy table first).
    ASSERT_EQ(detector_rows.size(), 2u) << r.output;
    ASSERT_GE(sequence_rows.size(), 2u) << r.output;
    const std::string& detector = detector_rows[1];
    const std::string& sequence = sequence_rows[1];
    ASSERT_EQ(detector.rfind("| " + scene, 0), 0u) << detector;
    ASSERT_EQ(sequence.rfind("| " + scene, 0), 0u) << sequence;
    const auto value = [](const std::string& header, const std::string& row, const std::string& name) {
      return std::stod(CellNamed(header, row, name));
    };
    EXPECT_GE(value(detector_rows[0], detector, "GT segments >= 40 px"), 1000) << detector;
    EXPECT_GE(value(detector_rows[0], detector, "recall"), 0.90) << detector;
    const std::string& header = sequence_rows[0];
    EXPECT_EQ(CellNamed(header, sequence, "frames"), "200");
    EXPECT_EQ(CellNamed(header, sequence, "lost"), "0") << sequence;
    EXPECT_GE(value(header, sequence, "stereo matches"), 100) << sequence;
    EXPECT_GE(value(header, sequence, "correct (of judged)"), 0.99) << sequence;
    EXPECT_GE(value(header, sequence, "tracks (>= 2 frames, judged)"), 90) << sequence;
    EXPECT_GE(value(header, sequence, "correct"), 0.99) << sequence;
    EXPECT_LE(value(header, sequence, "ratio images / noisy"), 1.5) << sequence;
    RecordProperty(out + "_recall", CellNamed(detector_rows[0], detector, "recall"));
    RecordProperty(out + "_ratio_images_noisy", CellNamed(header, sequence, "ratio images / noisy"));
  }
}

// The tracker configs shipped beside the front end are valid for trifocal_line_ekf and set what
// docs/frontend.md says they set.
TEST_F(EndToEnd, ShippedTrackerConfigsAreValid) {
  for (const auto& [file, expected] :
       {std::pair{std::string("paper_scene.json"), std::string(R"("keyframe_interval": 3)")},
        {std::string("paper_scene.json"), std::string(R"("map_association_px": 1.0)")},
        {std::string("endpoint_placement.json"), std::string(R"("endpoint_placement_sigma_px": 6.0)")}}) {
    const Result r = RunCommand(Bin("track") + " --method trifocal_line_ekf --print-config --tracker-config " +
                                std::string(SLT_SOURCE_DIR) + "/frontend/tracker_configs/" + file);
    ASSERT_EQ(r.exit_code, 0) << file << ": " << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << file << ": " << r.output;
  }
}

// The front-end config shipped for the rendered paper scene holds every option the scene runs with
// in measure_frontend (PaperSceneOptions for the rig of frontend/configs/paper_640x480.json: its
// disparity range, match verification, extension and snap bound), so that track_images with it
// measures what results/frontend reports.
TEST_F(EndToEnd, ShippedPaperSceneFrontEndConfigHoldsTheScenesOwnOptions) {
  const std::string source(SLT_SOURCE_DIR);
  nlohmann::json scene = ReadJsonFile(source + "/frontend/configs/paper_640x480.json");
  scene["frames"] = 2;
  const StereoRig rig = Simulate(SimulationConfigFromJson(scene, "paper_640x480.json")).true_rig;
  const nlohmann::json shipped = ReadJsonFile(source + "/frontend/frontend_configs/paper_scene.json").flatten();
  const nlohmann::json own = PaperSceneOptions(rig).flatten();
  ASSERT_GE(own.size(), 5u);
  for (const auto& [key, value] : own.items()) {
    ASSERT_TRUE(shipped.contains(key)) << key;
    EXPECT_EQ(shipped.at(key), value) << key;
  }
}

// What a user runs on the rendered paper scene (docs/frontend.md): simulate paper_640x480
// --images, then track_images with the two shipped paper_scene.json configs, gives the trajectory
// measure_frontend measures on draw 1 of the scene with the same configs.
TEST_F(EndToEnd, TrackImagesOnTheRenderedPaperSceneWithTheShippedConfigs) {
  Result r = RunCommand(Bin("simulate") + " paper_640x480 --out " + Path("paper") + " --images --threads 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string configs = " --config " + std::string(SLT_SOURCE_DIR) +
                              "/frontend/frontend_configs/paper_scene.json --tracker-config " +
                              std::string(SLT_SOURCE_DIR) + "/frontend/tracker_configs/paper_scene.json";
  r = RunCommand(Bin("track_images") + " --path " + Path("paper") + " --method trifocal_line_ekf --output " +
                 Path("paper.tum") + configs);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("100 frames"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(", 0 lost;"), std::string::npos) << r.output;
  r = RunCommand(Bin("evaluate") + " --gt " + Path("paper/gt.tum") + " --est " + Path("paper.tum") + " --out " +
                 Path("paper.metrics.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const double ate_mm = 1e3 * AteRmse(Path("paper.metrics.json"));
  r = RunCommand(Bin("measure_frontend") + " --frames 100 --skip-detectors --scene paper" + configs + " --out " +
                 Path("m"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::string> rows = RowsStartingWith(Path("m/sequences.md"), "| ");
  ASSERT_GE(rows.size(), 2u) << r.output;
  EXPECT_NEAR(ate_mm, std::stod(CellNamed(rows[0], rows[1], "ATE images, mm")), 0.0051) << rows[1];
  // Draw 1 of results/frontend/paper_scene_100_frames (its ATE 0.07 mm, the median of the three
  // hundred draws 0.13 mm; with the MSLD options alone, as the file held before, 1.96 mm).
  EXPECT_LT(ate_mm, 0.2);
  RecordProperty("ate_mm", std::to_string(ate_mm));
}

void ExpectOneErrorLine(const std::string& output, const std::string& program = "track") {
  EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
  EXPECT_EQ(output.rfind(program + ": error: ", 0), 0u) << output;
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
  // The same options under the name track_images and measure_frontend give them.
  r = RunCommand(Bin("track") + " --method trifocal_line_ekf --tracker-config " + Path("bad.json") + " --print-config");
  EXPECT_EQ(r.exit_code, 1);
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
  // measure_frontend checks --config over each scene's own options before any work: the paper
  // scene's disparity range starts above this largest disparity.
  {
    std::ofstream(Path("narrow.json")) << R"({"matching": {"max_disparity_px": 60}})";
  }
  r = RunCommand(Bin("measure_frontend") + " --frames 4 --scene paper --config " + Path("narrow.json") + " --out " +
                 Path("narrow"));
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneErrorLine(r.output, "measure_frontend");
  EXPECT_NE(r.output.find("paper scene 640x480 (paper motion), --config over its own options: key "
                          "'matching.max_disparity_px'"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(Path("narrow")));
  // simulate takes a rendered scene by name (frontend/configs/) and lists them when it has none.
  r = RunCommand(Bin("simulate") + " no_such_scene --out " + Path("scene"));
  EXPECT_EQ(r.exit_code, 1);
  ExpectOneErrorLine(r.output, "simulate");
  EXPECT_NE(r.output.find("simulation config 'no_such_scene' not found"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("available: corridor_640x480, paper_640x480, room_752x480, room_ci_640x480, room_handheld_752x480, room_mav_752x480, street, street_turn_start\n"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(Path("scene")));
  r = RunCommand(Bin("simulate") + " --help");
  EXPECT_NE(r.output.find("CONFIG names in frontend/configs/"), std::string::npos) << r.output;
  r = RunCommand(Bin("simulate") + " paper_640x480 --out " + Path("scene"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(ReadJsonFile(Path("scene/config.resolved.json"))["scene"]["type"], "paper");
  // Seeds are decimal numbers in [0, 2^64 - 1] and nothing else (CLI11 alone took -1 as 2^64 - 1).
  for (const std::string& command : {Bin("simulate") + " --out " + Path("seeded"), Bin("measure_frontend")}) {
    for (const char* seed : {"-1", "0x10", "1e3", "18446744073709551616", ""}) {
      r = RunCommand(command + " --seed '" + seed + "'");
      EXPECT_EQ(r.exit_code, 2) << command << " --seed " << seed << ": " << r.output;
      EXPECT_NE(r.output.find("--seed: expected an integer in [0, 2^64-1], got '" + std::string(seed) + "'"),
                std::string::npos)
          << r.output;
    }
  }
  EXPECT_FALSE(fs::exists(Path("seeded")));
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

  // evaluate: --out (--json) equal to --est is refused; metrics are never printed as null.
  r = RunCommand(track + " --output " + Path("t.tum"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string original_tum = ReadTextFile(Path("t.tum"));
  r = RunCommand(Bin("evaluate") + " --gt " + Path("t.tum") + " --est " + Path("t.tum") + " --out " + Path("t.tum"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--json " + Path("t.tum") + ": is also an input"), std::string::npos) << r.output;
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
