#include "common/csv.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "common/error.h"

namespace ttz {
namespace {

// A cell or line without surrounding blanks and, if quoted, without its quotes.
std::string Trim(const std::string& s) {
  std::string t = TrimSpace(s);
  if (t.size() >= 2 && t.front() == '"' && t.back() == '"') t = t.substr(1, t.size() - 2);
  return t;
}

std::vector<std::string> SplitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    if (c == ',' && !quoted) {
      cells.push_back(Trim(cell));
      cell.clear();
    } else {
      cell += c;
    }
  }
  cells.push_back(Trim(cell));
  return cells;
}

bool IsNumber(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end && *end == '\0';
}

bool AllNumbers(const std::vector<std::string>& cells) { return std::all_of(cells.begin(), cells.end(), IsNumber); }

}  // namespace

std::string TrimSpace(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t\r\n");
  return s.substr(begin, end - begin + 1);
}

std::string ToLower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

int CsvTable::FindColumn(const std::vector<std::string>& aliases) const {
  for (size_t i = 0; i < header.size(); ++i)
    for (const auto& a : aliases)
      if (ToLower(header[i]) == ToLower(a)) return static_cast<int>(i);
  return -1;
}

int CsvTable::FindColumn(std::initializer_list<const char*> aliases) const {
  return FindColumn(std::vector<std::string>(aliases.begin(), aliases.end()));
}

double CsvTable::Number(size_t row, int column) const {
  const std::string& text = rows[row][column];
  const std::string where = Where(file, lines[row]) + ": column '" + header[column] + "'";
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || !end || *end != '\0') throw InputError(where, "'" + text + "' is not a number");
  if (!std::isfinite(value)) throw InputError(where, "'" + text + "' is not finite (a finite number expected)");
  return value;
}

CsvTable ReadCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be read (file missing or not readable)");
  CsvTable table;
  table.file = path;
  std::string line, last_comment;
  long number = 0;
  bool have_header = false;
  while (std::getline(in, line)) {
    ++number;
    const std::string trimmed = Trim(line);
    if (trimmed.empty()) continue;
    if (trimmed[0] == '#') {
      last_comment = Trim(trimmed.substr(1));
      continue;
    }
    std::vector<std::string> cells = SplitCells(trimmed);
    if (!have_header) {
      have_header = true;
      if (!AllNumbers(cells)) {
        table.header = cells;
        continue;
      }
      const auto comment_cells = SplitCells(last_comment);
      if (last_comment.empty() || AllNumbers(comment_cells) || comment_cells.size() != cells.size())
        throw InputError(Where(path, number), "no header line (column names such as lat,lon expected before the data)");
      table.header = comment_cells;
    }
    if (cells.size() != table.header.size())
      throw InputError(Where(path, number), std::to_string(cells.size()) + " cells, " +
                                                std::to_string(table.header.size()) + " expected (as in the header)");
    table.rows.push_back(std::move(cells));
    table.lines.push_back(number);
  }
  if (!have_header) throw InputError(path, "empty file (a header and data rows expected)");
  return table;
}

}  // namespace ttz
