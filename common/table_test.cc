#include "common/table.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace slt {
namespace {

// Method, one sweep value, then a group of two statistics; two methods, a rule between them.
Table GroupedTable() {
  Table t;
  t.columns = {{"Method", Table::Align::kLeft}, {"noise_px"}, {"mean"}, {"95 % interval", Table::Align::kRight, "95\\,\\% int."}};
  t.groups = {{"Rot | err_deg", 2, 2}};
  t.AddRow({"a_1", "0.5", "1.5", "[1, 2]"});
  t.AddRow({"b|c", "1", "2", "[2, 3]"}, /*rule_before=*/true);
  return t;
}

TEST(StringPrintf, FormatsLikePrintf) {
  EXPECT_EQ(StringPrintf("%s %.3f %d", "a", 0.12345, 7), "a 0.123 7");
  EXPECT_EQ(StringPrintf("%.4g", 12345.0), "1.234e+04");
}

// measure_frontend's header holds a whole config file's JSON: no length limit, nothing cut.
TEST(StringPrintf, KeepsTextLongerThanAnyFixedBuffer) {
  const std::string long_text(5000, 'x');
  const std::string printed = StringPrintf("`%s`", long_text.c_str());
  EXPECT_EQ(printed.size(), 5002u);
  EXPECT_EQ(printed, "`" + long_text + "`");
}

TEST(Table, MarkdownPrefixesGroupTitlesAndEscapesPipes) {
  EXPECT_EQ(GroupedTable().Markdown(),
            "| Method | noise_px | Rot \\| err_deg mean | 95 % interval |\n"
            "|---|---:|---:|---:|\n"
            "| a_1 | 0.5 | 1.5 | [1, 2] |\n"
            "| b\\|c | 1 | 2 | [2, 3] |\n");
}

TEST(Table, LatexSpansGroupsAndEscapesCells) {
  EXPECT_EQ(GroupedTable().Latex(),
            "\\begin{tabular}{lrrr}\n\\toprule\n"
            "& & \\multicolumn{2}{c}{Rot | err\\_deg} \\\\\n"
            "\\cmidrule(lr){3-4}\n"
            "Method & noise\\_px & mean & 95\\,\\% int. \\\\\n\\midrule\n"
            "a\\_1 & 0.5 & 1.5 & [1, 2] \\\\\n"
            "\\midrule\n"
            "b|c & 1 & 2 & [2, 3] \\\\\n"
            "\\bottomrule\n\\end{tabular}\n");
}

TEST(Table, SectionSpansTheLatexRowAndFillsTheFirstColumnElsewhere) {
  Table t;
  t.columns = {{"Method", Table::Align::kLeft}, {"10"}};
  t.AddRow({"ours", "1 s"});
  Table paper = t;
  paper.rows.clear();
  paper.AddRow({"theirs", "2 s"});
  t.AddSection("Paper (1.7 GHz)");
  t.Append(paper);
  EXPECT_EQ(t.Latex(),
            "\\begin{tabular}{lr}\n\\toprule\nMethod & 10 \\\\\n\\midrule\n"
            "ours & 1 s \\\\\n"
            "\\midrule\n\\multicolumn{2}{l}{Paper (1.7 GHz)} \\\\\n"
            "theirs & 2 s \\\\\n"
            "\\bottomrule\n\\end{tabular}\n");
  EXPECT_EQ(t.Csv(), "Method,10\nours,1 s\nPaper (1.7 GHz),\ntheirs,2 s\n");
}

TEST(Table, CsvQuotesFields) {
  EXPECT_EQ(GroupedTable().Csv(),
            "Method,noise_px,Rot | err_deg mean,95 % interval\n"
            "a_1,0.5,1.5,\"[1, 2]\"\n"
            "b|c,1,2,\"[2, 3]\"\n");
}

TEST(Table, TextPadsToTheWidestCellOrTheMinimumWidth) {
  Table t;
  t.columns = {{"metric", Table::Align::kLeft, "", 8}, {"rmse", Table::Align::kRight, "", 6}};
  t.AddRow({"ATE", "0.5"});
  t.AddRow({"translation", "12.25"});
  EXPECT_EQ(t.Text(),
            "metric        rmse\n"
            "ATE            0.5\n"
            "translation  12.25\n");
}

TEST(Table, RowsMustHaveOneCellPerColumn) {
  Table t;
  t.columns = {{"a"}, {"b"}};
  EXPECT_THROW(t.AddRow({"1"}), std::invalid_argument);
  Table other;
  other.columns = {{"a"}};
  EXPECT_THROW(t.Append(other), std::invalid_argument);
}

}  // namespace
}  // namespace slt
