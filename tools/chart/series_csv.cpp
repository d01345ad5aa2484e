#include "series_csv.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace atmo::chart {

namespace {

std::string trim(const std::string& s) {
  const char* ws = " \t\r\n";
  const size_t b = s.find_first_not_of(ws);
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(ws);
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  size_t start = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return fields;
}

bool is_skipped(const std::string& trimmed) { return trimmed.empty() || trimmed[0] == '#'; }

bool fail(std::string* error, const std::string& msg) {
  if (error) *error = msg;
  return false;
}

std::string quoted(const std::string& s) { return "'" + s + "'"; }

}  // namespace

bool parse_number(const std::string& text, double* value) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE || !std::isfinite(v)) return false;
  *value = v;
  return true;
}

bool read_series_csv(const std::string& path, const ColumnNames& names, std::vector<Series>* out,
                     std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(error, path + ": cannot open: " + std::strerror(errno));

  // Requested columns: role (for messages), name, index in the header.
  struct Wanted {
    const char* option;
    std::string name;
    int index = -1;
  };
  Wanted x{"--x", names.x}, y{"--y", names.y}, group{"--group", names.group}, label{"--label", names.label};
  Wanted* wanted[] = {&x, &y, &group, &label};

  std::string line;
  int line_no = 0, header_line = 0;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    ++line_no;
    if (is_skipped(trim(line))) continue;
    header = split_fields(line);
    header_line = line_no;
    break;
  }
  if (header_line == 0) return fail(error, path + ": no header line (the file is empty or only comments)");

  std::string all_columns;
  for (const auto& h : header) all_columns += (all_columns.empty() ? "" : ", ") + h;
  for (Wanted* w : wanted) {
    if (w->name.empty()) continue;
    for (size_t i = 0; i < header.size(); ++i) {
      if (header[i] != w->name) continue;
      if (w->index >= 0)
        return fail(error, path + ":" + std::to_string(header_line) + ": column " + quoted(w->name) + " (" +
                               w->option + ") appears more than once in the header");
      w->index = static_cast<int>(i);
    }
    if (w->index < 0)
      return fail(error, path + ":" + std::to_string(header_line) + ": no column " + quoted(w->name) + " (" +
                             w->option + ") in the header; columns are: " + all_columns);
  }

  std::vector<Series> series;
  std::map<std::string, size_t> series_index;
  while (std::getline(in, line)) {
    ++line_no;
    if (is_skipped(trim(line))) continue;
    const std::vector<std::string> fields = split_fields(line);
    const std::string where = path + ":" + std::to_string(line_no) + ": ";
    auto field = [&](const Wanted& w, std::string* value) {
      if (w.index >= static_cast<int>(fields.size()))
        return fail(error, where + "column " + quoted(w.name) + " (field " + std::to_string(w.index + 1) +
                               ") is missing: the line has " + std::to_string(fields.size()) + " field" +
                               (fields.size() == 1 ? "" : "s"));
      *value = fields[static_cast<size_t>(w.index)];
      return true;
    };
    auto number = [&](const Wanted& w, double* value) {
      std::string text;
      if (!field(w, &text)) return false;
      if (!parse_number(text, value))
        return fail(error, where + "column " + quoted(w.name) + " (field " + std::to_string(w.index + 1) + "): " +
                               quoted(text) + " is not a number");
      return true;
    };
    Point p;
    p.line = line_no;
    std::string group_value;
    if (!number(x, &p.x) || !number(y, &p.y)) return false;
    if (group.index >= 0 && !field(group, &group_value)) return false;
    if (label.index >= 0 && !field(label, &p.label)) return false;
    auto [it, inserted] = series_index.emplace(group_value, series.size());
    if (inserted) series.push_back(Series{group_value, {}});
    series[it->second].points.push_back(std::move(p));
  }
  if (in.bad()) return fail(error, path + ": read error after line " + std::to_string(line_no));
  if (series.empty())
    return fail(error, path + ": no data rows after the header (line " + std::to_string(header_line) + ")");

  for (Series& s : series)
    std::stable_sort(s.points.begin(), s.points.end(), [](const Point& a, const Point& b) { return a.x < b.x; });
  *out = std::move(series);
  return true;
}

}  // namespace atmo::chart
