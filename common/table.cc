#include "common/table.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <stdexcept>

#include "common/csv.h"

namespace slt {
namespace {

// The column titles, each group's title before the title of its first column.
std::vector<std::string> FlatTitles(const Table& table) {
  std::vector<std::string> titles;
  for (const Table::Column& c : table.columns) titles.push_back(c.title);
  for (const Table::Group& g : table.groups) titles.at(g.first) = g.title + " " + titles.at(g.first);
  return titles;
}

// A section's text in the first column, the others empty.
std::vector<std::string> Cells(const Table& table, const Table::Row& row) {
  if (!row.section) return row.cells;
  std::vector<std::string> cells(table.columns.size());
  cells.at(0) = row.cells.at(0);
  return cells;
}

std::string Join(const std::vector<std::string>& cells, std::string (*escape)(const std::string&),
                 const std::string& separator) {
  std::string line;
  for (size_t i = 0; i < cells.size(); ++i) line += (i ? separator : "") + escape(cells[i]);
  return line;
}

}  // namespace

std::string StringPrintf(const char* format, ...) {
  // Most cells fit the stack buffer; longer text is printed again at its measured length.
  char buffer[256];
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  const int length = std::vsnprintf(buffer, sizeof(buffer), format, args);
  va_end(args);
  if (length < 0) {
    va_end(again);
    throw std::invalid_argument(std::string("StringPrintf: cannot format '") + format + "'");
  }
  if (static_cast<size_t>(length) < sizeof(buffer)) {
    va_end(again);
    return std::string(buffer, static_cast<size_t>(length));
  }
  std::string text(static_cast<size_t>(length), '\0');
  std::vsnprintf(text.data(), text.size() + 1, format, again);
  va_end(again);
  return text;
}

void Table::AddRow(std::vector<std::string> cells, bool rule_before) {
  if (cells.size() != columns.size()) {
    throw std::invalid_argument("Table::AddRow: " + std::to_string(cells.size()) + " cells for " +
                                std::to_string(columns.size()) + " columns");
  }
  rows.push_back({std::move(cells), false, rule_before});
}

void Table::AddSection(std::string title) { rows.push_back({{std::move(title)}, true, true}); }

void Table::Append(const Table& other) {
  if (other.columns.size() != columns.size()) throw std::invalid_argument("Table::Append: different numbers of columns");
  rows.insert(rows.end(), other.rows.begin(), other.rows.end());
}

std::string Table::Markdown() const {
  std::string md = "| " + Join(FlatTitles(*this), MarkdownEscape, " | ") + " |\n|";
  for (const Column& c : columns) md += c.align == Align::kLeft ? "---|" : "---:|";
  md += "\n";
  for (const Row& row : rows) md += "| " + Join(Cells(*this, row), MarkdownEscape, " | ") + " |\n";
  return md;
}

std::string Table::Latex() const {
  std::string tex = "\\begin{tabular}{";
  for (const Column& c : columns) tex += c.align == Align::kLeft ? 'l' : 'r';
  tex += "}\n\\toprule\n";
  if (!groups.empty()) {
    std::string rules;
    for (size_t c = 0; c < columns.size(); ++c) {
      const auto group = std::find_if(groups.begin(), groups.end(),
                                      [&](const Group& g) { return c >= g.first && c < g.first + g.count; });
      if (group == groups.end()) {
        tex += c ? "&" : "";
      } else if (group->first == c) {
        tex += std::string(c ? " & " : "") + "\\multicolumn{" + std::to_string(group->count) + "}{c}{" +
               TexEscape(group->title) + "}";
        rules += "\\cmidrule(lr){" + std::to_string(c + 1) + "-" + std::to_string(c + group->count) + "}";
      }
    }
    tex += " \\\\\n" + rules + "\n";
  }
  for (size_t c = 0; c < columns.size(); ++c) {
    tex += (c ? " & " : "") + (columns[c].tex_title.empty() ? TexEscape(columns[c].title) : columns[c].tex_title);
  }
  tex += " \\\\\n\\midrule\n";
  for (const Row& row : rows) {
    if (row.rule_before) tex += "\\midrule\n";
    if (row.section) {
      tex += "\\multicolumn{" + std::to_string(columns.size()) + "}{l}{" + TexEscape(row.cells.at(0)) + "}";
    } else {
      tex += Join(row.cells, TexEscape, " & ");
    }
    tex += " \\\\\n";
  }
  return tex + "\\bottomrule\n\\end{tabular}\n";
}

std::string Table::Csv() const {
  std::string csv = CsvLine(FlatTitles(*this));
  for (const Row& row : rows) csv += CsvLine(Cells(*this, row));
  return csv;
}

std::string Table::Text() const {
  std::vector<std::vector<std::string>> lines = {FlatTitles(*this)};
  for (const Row& row : rows) lines.push_back(Cells(*this, row));
  std::vector<size_t> widths;
  for (const Column& c : columns) widths.push_back(c.min_width);
  for (const std::vector<std::string>& line : lines) {
    for (size_t c = 0; c < line.size(); ++c) widths[c] = std::max(widths[c], line[c].size());
  }
  std::string text;
  for (const std::vector<std::string>& line : lines) {
    for (size_t c = 0; c < line.size(); ++c) {
      const std::string padding(widths[c] - line[c].size(), ' ');
      text += (c ? " " : "") + (columns[c].align == Align::kLeft ? line[c] + padding : padding + line[c]);
    }
    text += "\n";
  }
  return text;
}

}  // namespace slt
