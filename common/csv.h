// A small CSV table reader with the checks every input reader needs.
//
// Lines starting with '#' are comments; blank lines are skipped. The header is the first
// non-comment line, unless that line is all numbers and the last comment line before it looks like
// a header (the TUMFTM track files: "# x_m,y_m,w_tr_right_m,w_tr_left_m"). Cells are trimmed and
// may be double-quoted. Column names match case-insensitively.
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

namespace ttz {

struct CsvTable {
  std::string file;
  std::vector<std::string> header;             // as written (trimmed)
  std::vector<std::vector<std::string>> rows;  // data rows, each with header.size() cells
  std::vector<long> lines;                     // 1-based line number of each data row in the file

  // Index of the first column whose name equals one of `aliases` (case-insensitive), or -1.
  int FindColumn(std::initializer_list<const char*> aliases) const;
  int FindColumn(const std::vector<std::string>& aliases) const;

  // The cell as a finite double. Throws InputError "file:line: column 'name': 'text' is not a
  // number" (or "is not finite" for nan/inf).
  double Number(size_t row, int column) const;
  const std::string& Cell(size_t row, int column) const { return rows[row][column]; }
};

// Throws InputError for a missing or unreadable file, an empty file, a file without a header, or
// a row whose cell count differs from the header's (naming the line).
CsvTable ReadCsv(const std::string& path);

// Lower-case copy, for case-insensitive comparisons.
std::string ToLower(std::string s);

// Copy without leading and trailing blanks (spaces, tabs, CR, LF).
std::string TrimSpace(const std::string& s);

}  // namespace ttz
