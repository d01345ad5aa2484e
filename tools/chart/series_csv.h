// Reads the points of an error-versus-cost chart from a CSV file: an x and a y
// numeric column, an optional group column (one series per distinct value) and
// an optional label column (text drawn next to each point).
#pragma once

#include <string>
#include <vector>

namespace atmo::chart {

struct Point {
  double x = 0.0, y = 0.0;
  std::string label;  // empty when no label column was asked for
  int line = 0;       // 1-based line in the file, for messages
};

struct Series {
  std::string name;           // the group value ("" when no group column)
  std::vector<Point> points;  // in increasing x (stable for equal x)
};

struct ColumnNames {
  std::string x, y;
  std::string group;  // optional: empty means one series
  std::string label;  // optional
};

// Format: the first line that is neither blank nor a comment ('#' first, after
// spaces) is the header of comma-separated column names; every later such line
// is a row. No quoting; spaces around fields are ignored; CRLF is accepted;
// columns not named in `names` are ignored and may hold anything.
// Series come in the order their group value first appears.
// On failure returns false and a message naming the file, the line and the
// column (e.g. "data.csv:7: column 'psnr_db' (field 3): 'n/a' is not a number").
bool read_series_csv(const std::string& path, const ColumnNames& names, std::vector<Series>* out,
                     std::string* error);

// Parses a whole field as a finite double ("1e3", " 2.5 " are fine; "", "nan",
// "inf", "3x" are not).
bool parse_number(const std::string& text, double* value);

}  // namespace atmo::chart
