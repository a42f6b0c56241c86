// Table text. Minimal CSV (RFC 4180): fields containing a comma, a quote or a line break are
// quoted, with quotes doubled; numbers are written in the shortest form that reads back to the
// same double. Strict number parsing (a double, an integer: the whole text or an error). And the
// escaping of a cell of a Markdown or LaTeX table.
#pragma once

#include <charconv>
#include <stdexcept>
#include <string>
#include <vector>

namespace slt {

std::string CsvField(const std::string& field);
std::string CsvLine(const std::vector<std::string>& fields);  // with the trailing '\n'
// Shortest round-trip form; "nan", "inf", "-inf" for non-finite values.
std::string FormatDouble(double value);
// Parses FormatDouble's output (and any decimal number); throws std::invalid_argument.
double ParseDouble(const std::string& text);
// A whole number of type T, in decimal and nothing else (leading zeros allowed: "007" is 7; no
// '+', no '-' for an unsigned T, no space, no fraction or exponent); throws std::invalid_argument
// "not an integer: '<text>'", also when out of T's range.
template <typename T>
T ParseInteger(const std::string& text) {
  T value{};
  const char* last = text.data() + text.size();
  const std::from_chars_result r = std::from_chars(text.data(), last, value);
  if (text.empty() || r.ec != std::errc() || r.ptr != last) throw std::invalid_argument("not an integer: '" + text + "'");
  return value;
}

// '|' escaped for a Markdown table cell.
std::string MarkdownEscape(const std::string& text);
// LaTeX's special characters escaped for text mode.
std::string TexEscape(const std::string& text);

struct CsvTable {
  std::string where;  // file name, for errors
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // every row has header.size() fields

  // Index of the column; throws std::runtime_error naming the file when it is missing.
  size_t Column(const std::string& name) const;
  bool HasColumn(const std::string& name) const;
};

// Throws std::runtime_error "<where>:<line>: <reason>" on malformed input (unterminated quote,
// a row with the wrong number of fields).
CsvTable ParseCsv(const std::string& text, const std::string& where);
CsvTable ReadCsvFile(const std::string& path);
std::string ReadTextFile(const std::string& path);

}  // namespace slt
