#include "common/csv.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <thread>

#include "common/json_reader.h"

namespace slt {
namespace {

namespace fs = std::filesystem;

std::string TempDir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("slt_csv_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

TEST(Csv, QuotesAndParsesBack) {
  const std::vector<std::string> fields = {"plain", "with, comma", "with \"quote\"", "line\nbreak", ""};
  const CsvTable t = ParseCsv(CsvLine({"a", "b", "c", "d", "e"}) + CsvLine(fields), "t.csv");
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0], fields);
  EXPECT_EQ(t.Column("c"), 2u);
  EXPECT_THROW(t.Column("z"), std::runtime_error);
  EXPECT_THROW(ParseCsv("a,b\n1,2,3\n", "t.csv"), std::runtime_error);
  EXPECT_THROW(ParseCsv("a,b\n\"1,2\n", "t.csv"), std::runtime_error);
}

TEST(Csv, NumbersRoundTripExactly) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-10, 10);
  for (int i = 0; i < 1000; ++i) {
    const double v = u(rng) * std::pow(10.0, static_cast<int>(u(rng)));
    EXPECT_EQ(ParseDouble(FormatDouble(v)), v);
  }
  EXPECT_TRUE(std::isnan(ParseDouble(FormatDouble(std::nan("")))));
  EXPECT_EQ(ParseDouble(FormatDouble(-HUGE_VAL)), -HUGE_VAL);
  EXPECT_THROW(ParseDouble("1.5x"), std::invalid_argument);
  EXPECT_THROW(ParseDouble(""), std::invalid_argument);
}

// track_images --frames, run_experiment --shard, the --seed of simulate and measure_frontend,
// raw/trials.csv's seeds: the whole text is the number.
TEST(Csv, IntegersParseStrictly) {
  EXPECT_EQ(ParseInteger<int>("42"), 42);
  EXPECT_EQ(ParseInteger<int>("-7"), -7);
  EXPECT_EQ(ParseInteger<int>("-2147483648"), -2147483647 - 1);
  EXPECT_EQ(ParseInteger<int>("007"), 7);  // decimal, not octal
  EXPECT_EQ(ParseInteger<int>("-0"), 0);
  EXPECT_EQ(ParseInteger<std::uint64_t>("18446744073709551615"), 18446744073709551615ull);
  for (const char* bad : {"", "1x", "x1", " 1", "1 ", "+1", "1.0", "1e3", "2147483648"}) {
    EXPECT_THROW(ParseInteger<int>(bad), std::invalid_argument) << bad;
  }
  for (const char* bad : {"-1", "-0", "0x10", "18446744073709551616"}) {
    EXPECT_THROW(ParseInteger<std::uint64_t>(bad), std::invalid_argument) << bad;
  }
}

TEST(AtomicWrite, ReadersSeeTheOldOrTheNewFileNeverAPart) {
  const std::string dir = TempDir("atomic");
  const std::string path = dir + "/summary.csv";
  const std::string a(1 << 20, 'a'), b(1 << 20, 'b');
  WriteTextFileAtomically(path, a);
  std::atomic<bool> done{false};
  std::atomic<int> reads{0}, torn{0};
  std::thread reader([&] {
    while (!done.load()) {
      const std::string s = ReadTextFile(path);
      if (s != a && s != b) ++torn;
      ++reads;
    }
  });
  for (int i = 0; i < 40; ++i) WriteTextFileAtomically(path, i % 2 ? a : b);
  done.store(true);
  reader.join();
  EXPECT_EQ(torn.load(), 0);
  EXPECT_GT(reads.load(), 0);
  // Nothing but the file is left in the directory (no temporary files).
  size_t entries = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    ++entries;
    EXPECT_EQ(entry.path().filename(), "summary.csv");
  }
  EXPECT_EQ(entries, 1u);
}

TEST(AtomicWrite, AFailedWriteLeavesNoFile) {
  const std::string dir = TempDir("atomic_fail");
  fs::create_directories(dir + "/target");  // a directory where the file should go: rename fails
  EXPECT_THROW(WriteTextFileAtomically(dir + "/target", "x"), std::runtime_error);
  size_t entries = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    ++entries;
    EXPECT_EQ(entry.path().filename(), "target");
  }
  EXPECT_EQ(entries, 1u);
  EXPECT_TRUE(fs::is_empty(dir + "/target"));
}

}  // namespace
}  // namespace slt
