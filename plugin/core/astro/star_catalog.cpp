// star_catalog.cpp — parser of the bright-star catalog text (format:
// docs/STAR_CATALOG.md). std::from_chars, no locale, no exceptions.
#include "core/astro/star_catalog.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

namespace atmo::core::astro {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kMasToRad = kPi / (180.0 * 3600.0 * 1000.0);
constexpr int kColumnCount = 11;
constexpr const char* kColumnNames[kColumnCount] = {"hd",           "kstars_line",   "ra_deg", "dec_deg",
                                                    "pm_ra_mas_yr", "pm_dec_mas_yr", "parallax_mas", "v_mag",
                                                    "b_minus_v",    "bayer",         "name"};

// Builds "source:line: message".
std::string at_line(std::string_view source, size_t line, const std::string& message) {
  std::ostringstream out;
  out << source << ":" << line << ": " << message;
  return out.str();
}

// Shows a field in an error message: quoted, at most 40 characters, control
// characters escaped.
std::string quoted(std::string_view field) {
  std::string out = "'";
  for (size_t i = 0; i < field.size() && i < 40; ++i) {
    unsigned char c = static_cast<unsigned char>(field[i]);
    if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  if (field.size() > 40) out += "...";
  return out + "'";
}

std::string column_label(int column) {
  return "column " + std::to_string(column + 1) + " (" + kColumnNames[column] + ")";
}

// Parses the whole field as a finite double within [lo, hi] (or (lo, hi) when
// open); returns an error message or empty.
std::string parse_double(std::string_view field, int column, double lo, double hi, bool open_range, double* out) {
  if (field.empty()) return column_label(column) + ": empty";
  double value = 0.0;
  auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (ec != std::errc() || end != field.data() + field.size())
    return column_label(column) + ": " + quoted(field) + " is not a number";
  if (!std::isfinite(value)) return column_label(column) + ": " + quoted(field) + " is not finite";
  bool inside = open_range ? (value > lo && value < hi) : (value >= lo && value <= hi);
  if (!inside) {
    std::ostringstream msg;
    msg << column_label(column) << ": " << quoted(field) << " is outside " << (open_range ? "(" : "[") << lo << ", "
        << hi << (open_range ? ")" : "]");
    return msg.str();
  }
  *out = value;
  return {};
}

std::string parse_uint(std::string_view field, int column, uint32_t* out) {
  if (field.empty()) return column_label(column) + ": empty";
  uint32_t value = 0;
  auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (ec != std::errc() || end != field.data() + field.size())
    return column_label(column) + ": " + quoted(field) + " is not an unsigned integer";
  *out = value;
  return {};
}

// "-" stands for "none"; other text is taken as is.
std::string parse_text(std::string_view field, int column, std::string* out) {
  if (field.empty()) return column_label(column) + ": empty (write - for none)";
  for (char c : field)
    if (static_cast<unsigned char>(c) < 0x20) return column_label(column) + ": control character in " + quoted(field);
  if (field != "-") out->assign(field);
  return {};
}

// Parses one data line into `star`; returns an error message or empty.
std::string parse_star_line(std::string_view line, CatalogStar* star) {
  std::string_view fields[kColumnCount];
  int count = 0;
  size_t start = 0;
  while (true) {
    size_t tab = line.find('\t', start);
    std::string_view field = line.substr(start, tab == std::string_view::npos ? std::string_view::npos : tab - start);
    if (count < kColumnCount) fields[count] = field;
    ++count;
    if (tab == std::string_view::npos) break;
    start = tab + 1;
  }
  if (count != kColumnCount)
    return "expected " + std::to_string(kColumnCount) + " tab-separated columns, found " + std::to_string(count);

  std::string err;
  double ra_deg = 0.0, dec_deg = 0.0, pm_ra = 0.0, pm_dec = 0.0, parallax = 0.0;
  if (!(err = parse_uint(fields[0], 0, &star->hd)).empty()) return err;
  if (!(err = parse_uint(fields[1], 1, &star->kstars_line)).empty()) return err;
  if (star->kstars_line == 0) return column_label(1) + ": must be at least 1";
  // RA in [0, 360); Dec strictly inside (-90, 90), where dRA/dt is defined.
  if (!(err = parse_double(fields[2], 2, 0.0, 360.0, false, &ra_deg)).empty()) return err;
  if (ra_deg >= 360.0) return column_label(2) + ": " + quoted(fields[2]) + " is outside [0, 360)";
  if (!(err = parse_double(fields[3], 3, -90.0, 90.0, true, &dec_deg)).empty()) return err;
  // Proper motion: the fastest star, Barnard's, moves 10.4"/yr.
  if (!(err = parse_double(fields[4], 4, -20000.0, 20000.0, false, &pm_ra)).empty()) return err;
  if (!(err = parse_double(fields[5], 5, -20000.0, 20000.0, false, &pm_dec)).empty()) return err;
  // Parallax: Proxima Centauri's is 768 mas; Hipparcos has small negative values.
  if (!(err = parse_double(fields[6], 6, -100.0, 1000.0, false, &parallax)).empty()) return err;
  if (!(err = parse_double(fields[7], 7, -2.0, 16.0, false, &star->v_mag)).empty()) return err;
  if (!(err = parse_double(fields[8], 8, -1.0, 4.0, false, &star->b_minus_v)).empty()) return err;
  if (!(err = parse_text(fields[9], 9, &star->bayer)).empty()) return err;
  if (!(err = parse_text(fields[10], 10, &star->name)).empty()) return err;

  star->ra_rad = ra_deg * kDegToRad;
  star->dec_rad = dec_deg * kDegToRad;
  // The file holds mu_alpha* = dRA/dt cos(dec); ERFA wants dRA/dt.
  star->pm_ra_rad_per_year = pm_ra * kMasToRad / std::cos(star->dec_rad);
  star->pm_dec_rad_per_year = pm_dec * kMasToRad;
  star->parallax_arcsec = parallax / 1000.0;
  return {};
}

}  // namespace

StarCatalogLoad parse_star_catalog(std::string_view text, std::string_view source) {
  StarCatalogLoad result;
  auto fail = [&](size_t line, const std::string& message) {
    result.stars.clear();
    result.error = at_line(source, line, message);
    return result;
  };
  if (text.empty())
    return fail(1, "empty file (expected the header line \"" + std::string(kStarCatalogMagic) + "\")");
  if (text.back() != '\n') {
    size_t lines = 1;
    for (char c : text) lines += c == '\n';
    return fail(lines, "truncated: the last line has no end of line");
  }

  bool have_count = false, have_columns = false;
  uint64_t declared = 0;
  size_t line_number = 0, last_data_line = 0;
  size_t pos = 0;
  result.stars.reserve(10000);
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);

    if (line_number == 1) {
      if (line != kStarCatalogMagic)
        return fail(1, "not an atmo star catalog: the first line is " + quoted(line) + ", expected \"" +
                           std::string(kStarCatalogMagic) + "\"");
      continue;
    }
    if (line.empty()) continue;
    if (line.front() == '#') {
      constexpr std::string_view kCount = "# count: ", kColumns = "# columns: ";
      if (line.substr(0, kCount.size()) == kCount) {
        std::string_view number = line.substr(kCount.size());
        auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), declared);
        if (ec != std::errc() || end != number.data() + number.size() || declared == 0)
          return fail(line_number, "bad star count " + quoted(number));
        have_count = true;
      } else if (line.substr(0, kColumns.size()) == kColumns) {
        if (line.substr(kColumns.size()) != kStarCatalogColumns)
          return fail(line_number, "unexpected columns " + quoted(line.substr(kColumns.size())) +
                                       " (this reader knows format 1)");
        have_columns = true;
      }
      continue;
    }
    if (!have_count || !have_columns)
      return fail(line_number, std::string("data before the header's ") +
                                   (have_count ? "\"# columns: \"" : "\"# count: \"") + " line");
    if (result.stars.size() >= declared)
      return fail(line_number, "more stars than the header's count of " + std::to_string(declared));
    CatalogStar star;
    std::string err = parse_star_line(line, &star);
    if (!err.empty()) return fail(line_number, err);
    result.stars.push_back(std::move(star));
    last_data_line = line_number;
  }
  if (!have_count || !have_columns)
    return fail(line_number, std::string("header incomplete: no ") + (have_count ? "\"# columns: \"" : "\"# count: \"") +
                                 " line");
  if (result.stars.size() != declared)
    return fail(last_data_line ? last_data_line : line_number,
                "truncated: the header declares " + std::to_string(declared) + " stars, the file has " +
                    std::to_string(result.stars.size()));
  return result;
}

StarCatalogLoad load_star_catalog(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    StarCatalogLoad result;
    result.error = path + ": cannot open (" + std::strerror(errno) + ")";
    return result;
  }
  in.seekg(0, std::ios::end);
  std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  std::string text(size > 0 ? static_cast<size_t>(size) : 0, '\0');
  if (size > 0) in.read(text.data(), size);
  if (size < 0 || !in) {
    StarCatalogLoad result;
    result.error = path + ": read error";
    return result;
  }
  return parse_star_catalog(text, path);
}

const CatalogStar* find_star(const std::vector<CatalogStar>& stars, uint32_t hd) {
  if (hd == 0) return nullptr;
  for (const CatalogStar& s : stars)
    if (s.hd == hd) return &s;
  return nullptr;
}

const CatalogStar* find_star_by_name(const std::vector<CatalogStar>& stars, std::string_view name) {
  if (name.empty()) return nullptr;
  for (const CatalogStar& s : stars)
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace atmo::core::astro
