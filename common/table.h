// A table of text cells, written as Markdown, LaTeX (booktabs), CSV or aligned plain text: the
// one table writer of the tools (run_experiment's summaries and raw CSV files, bench_table1's
// Table 1, evaluate's error table). The caller formats the numbers; the table escapes the text
// for each format (common/csv.h: MarkdownEscape, TexEscape, CsvField).
//
//   Table t;
//   t.columns = {{"Method", Table::Align::kLeft}, {"mean"}, {"median"}};
//   t.groups = {{"Rotation error (deg)", 1, 2}};
//   t.AddRow({"trifocal_line_ekf", "0.153", "0.12"});
//   t.Markdown();  // | Method | Rotation error (deg) mean | median |  ...
//   t.Latex();     // \begin{tabular}{lrr} \toprule & \multicolumn{2}{c}{Rotation error (deg)} ...
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace slt {

// printf-style text of a cell ("%.3f"), of any length.
std::string StringPrintf(const char* format, ...) __attribute__((format(printf, 1, 2)));

struct Table {
  enum class Align { kLeft, kRight };
  struct Column {
    Column(std::string title_, Align align_ = Align::kRight, std::string tex_title_ = "", size_t min_width_ = 0)
        : title(std::move(title_)), align(align_), tex_title(std::move(tex_title_)), min_width(min_width_) {}
    std::string title;
    Align align;
    // The title as LaTeX markup, when it needs more than TexEscape(title) ("95\\,\\% interval").
    std::string tex_title;
    size_t min_width;  // Text(): the column is at least this many characters wide
  };
  // Columns [first, first + count) under one title. LaTeX spans it over them (\multicolumn with
  // a \cmidrule); the other formats, which have no spanning header, prefix it to the title of
  // the first of them ("Rotation error (deg) mean").
  struct Group {
    std::string title;
    size_t first = 0;
    size_t count = 0;
  };
  struct Row {
    std::vector<std::string> cells;  // one per column; one for a section
    // One cell across every column, a heading inside the table ("Paper (1.7 GHz Intel)"):
    // LaTeX \multicolumn{n}{l}; the other formats put it in the first column.
    bool section = false;
    bool rule_before = false;  // LaTeX: a \midrule above this row (a new method, a new section)
  };

  std::vector<Column> columns;
  std::vector<Group> groups;
  std::vector<Row> rows;

  // Throws std::invalid_argument unless there is one cell per column.
  void AddRow(std::vector<std::string> cells, bool rule_before = false);
  // A section row, with a rule above it.
  void AddSection(std::string title);
  // The rows of `other` (with the same number of columns) appended below these.
  void Append(const Table& other);

  // "| a | b |" lines: the header, the alignment rule ("---" or "---:"), the rows; every cell
  // MarkdownEscape'd.
  std::string Markdown() const;
  // \begin{tabular}{l r ...} with \toprule, the group row and its \cmidrule's (if any groups),
  // the header, \midrule, the rows, \bottomrule, \end{tabular}; every cell TexEscape'd. Columns
  // outside every group have an empty cell in the group row.
  std::string Latex() const;
  // The header and the rows, one CsvLine each.
  std::string Csv() const;
  // Columns padded to their widest cell (at least min_width), left or right as aligned, one
  // space apart; the header first. Widths count bytes: for ASCII tables.
  std::string Text() const;
};

}  // namespace slt
