// kstars_catalog.cpp — KStars star data in, Atmo's bright-star catalog out.
// Layout of the binary files (read from the files' own headers, checked
// against KStars' binfilehelper / starcomponent sources):
//
//   0    char[124]  text preamble, NUL padded
//   124  uint16     0x4B53 ("SK" little-endian) in the writer's byte order
//   126  uint8      format version
//   127  uint16     number of field descriptors, n
//   129  n x 16     descriptors: char name[10], int8 size, uint8 type, int32 scale
//        uint32     number of index entries (HTM trixels), m
//        m x 12     index: uint32 trixel id (= i), uint32 byte offset, uint32 record count
//        int16      faintest magnitude x 100; uint8 HTM level; uint16 max stars per trixel
//        records    32 bytes each, at the offsets of the index, one after another
//
// Record (starData): int32 RA (hours x 1e6), int32 Dec (deg x 1e5), int32 dRA,
// int32 dDec (mas/yr x 10; dRA is mu_alpha* = dRA/dt cos dec), int32 parallax
// (mas x 10), int32 HD (unscaled, although its descriptor says 10), int16 mag
// (x 100), int16 B-V (x 100), char[2] spectral type, char flags, char unused.
#include "kstars_catalog.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

namespace atmo::tools::star_catalog {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr size_t kRecordSize = 32;
// Epoch of the Hipparcos and Tycho-1 catalogues, in years before J2000.0.
constexpr double kHipparcosEpochYearsBeforeJ2000 = 8.75;
// Cross-match limits (stars.dat star to binary record).
constexpr double kMatchRadiusArcsec = 1.5;
constexpr double kMatchMaxDeltaMag = 1.5;  // components of doubles differ from the combined V

std::vector<unsigned char> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FormatError(path + ": cannot open (" + std::strerror(errno) + ")");
  in.seekg(0, std::ios::end);
  std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  if (size < 0) throw FormatError(path + ": cannot determine the size");
  std::vector<unsigned char> bytes(static_cast<size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size)) throw FormatError(path + ": read error");
  return bytes;
}

std::string trim(const std::string& s) {
  size_t a = s.find_first_not_of(' '), b = s.find_last_not_of(' ');
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

// Little/big-endian reads with bounds checks that name the byte offset.
class ByteReader {
 public:
  ByteReader(const std::vector<unsigned char>& bytes, const std::string& name) : b_(bytes), name_(name) {}
  void set_big_endian(bool big) { big_ = big; }
  void need(size_t off, size_t n, const std::string& what) const {
    if (off > b_.size() || n > b_.size() - off) {
      std::ostringstream msg;
      msg << name_ << ": byte " << off << ": file ends (at " << b_.size() << " bytes) inside " << what;
      throw FormatError(msg.str());
    }
  }
  uint32_t u(size_t off, size_t n, const std::string& what) const {
    need(off, n, what);
    uint32_t v = 0;
    for (size_t i = 0; i < n; ++i) {
      size_t k = big_ ? i : n - 1 - i;
      v = (v << 8) | b_[off + k];
    }
    return v;
  }
  uint8_t u8(size_t off, const std::string& what) const { return static_cast<uint8_t>(u(off, 1, what)); }
  uint16_t u16(size_t off, const std::string& what) const { return static_cast<uint16_t>(u(off, 2, what)); }
  uint32_t u32(size_t off, const std::string& what) const { return u(off, 4, what); }
  int16_t i16(size_t off, const std::string& what) const { return static_cast<int16_t>(u16(off, what)); }
  int32_t i32(size_t off, const std::string& what) const { return static_cast<int32_t>(u32(off, what)); }
  std::string error_at(size_t off, const std::string& message) const {
    std::ostringstream msg;
    msg << name_ << ": byte " << off << ": " << message;
    return msg.str();
  }

 private:
  const std::vector<unsigned char>& b_;
  const std::string& name_;
  bool big_ = false;
};

struct FieldSpec {
  const char* name;
  int size;
};
// KStars' 32-byte starData, in order.
constexpr FieldSpec kStarFields[] = {{"RA", 4},       {"Dec", 4},      {"dRA", 4},       {"dDec", 4},
                                     {"parallax", 4}, {"HD", 4},       {"mag", 2},       {"bv_index", 2},
                                     {"spec_type", 2}, {"flags", 1},   {"unused", 1}};
constexpr size_t kFieldCount = sizeof(kStarFields) / sizeof(kStarFields[0]);

// Unit vector of (ra, dec) in degrees.
void unit(double ra_deg, double dec_deg, double v[3]) {
  double a = ra_deg * kDeg, d = dec_deg * kDeg;
  v[0] = std::cos(d) * std::cos(a);
  v[1] = std::cos(d) * std::sin(a);
  v[2] = std::sin(d);
}

double separation_arcsec(double ra1, double dec1, double ra2, double dec2) {
  double p[3], q[3];
  unit(ra1, dec1, p);
  unit(ra2, dec2, q);
  double c[3] = {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
  double s = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  double d = p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
  return std::atan2(s, d) / kDeg * 3600.0;
}

// A fixed-point value with `decimals` decimals, e.g. -5460 (1) -> "-546.0".
std::string fixed(int64_t value, int decimals) {
  int64_t scale = 1;
  for (int i = 0; i < decimals; ++i) scale *= 10;
  int64_t a = value < 0 ? -value : value;
  char buf[48];
  std::snprintf(buf, sizeof buf, "%s%lld.%0*lld", value < 0 ? "-" : "", static_cast<long long>(a / scale), decimals,
                static_cast<long long>(a % scale));
  return buf;
}

// Sorted-copy quantile (nearest rank).
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  size_t i = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size()))) ;
  i = i == 0 ? 0 : i - 1;
  return v[std::min(i, v.size() - 1)];
}

}  // namespace

// ---------------------------------------------------------------------------
// Binary files

KStarsBinaryFile parse_kstars_binary(const std::vector<unsigned char>& bytes, const std::string& name) {
  ByteReader r(bytes, name);
  KStarsBinaryFile file;
  r.need(0, 124, "the 124-byte text preamble");
  for (size_t i = 0; i < 124 && bytes[i] != 0; ++i) file.preamble += static_cast<char>(bytes[i]);

  r.need(124, 2, "the byte-order mark");
  if (bytes[124] == 0x53 && bytes[125] == 0x4B) {
    file.big_endian = false;
  } else if (bytes[124] == 0x4B && bytes[125] == 0x53) {
    file.big_endian = true;
  } else {
    char buf[64];
    std::snprintf(buf, sizeof buf, "byte-order mark %02x %02x, expected 53 4b (or 4b 53)", bytes[124], bytes[125]);
    throw FormatError(r.error_at(124, buf) + " (not a KStars binary file?)");
  }
  r.set_big_endian(file.big_endian);
  file.version = r.u8(126, "the version byte");

  // Field descriptors: must be KStars' 32-byte starData.
  uint16_t nfields = r.u16(127, "the field count");
  if (nfields != kFieldCount)
    throw FormatError(r.error_at(127, std::to_string(nfields) + " field descriptors, expected " +
                                          std::to_string(kFieldCount) + " (the 32-byte starData)"));
  size_t off = 129;
  std::map<std::string, double> scale;
  size_t record_size = 0;
  for (size_t i = 0; i < nfields; ++i, off += 16) {
    r.need(off, 16, "field descriptor " + std::to_string(i));
    std::string fname;
    for (size_t k = 0; k < 10 && bytes[off + k] != 0; ++k) fname += static_cast<char>(bytes[off + k]);
    int size = static_cast<int8_t>(bytes[off + 10]);
    int32_t fscale = r.i32(off + 12, "field descriptor " + std::to_string(i));
    if (fname != kStarFields[i].name || size != kStarFields[i].size)
      throw FormatError(r.error_at(off, "field descriptor " + std::to_string(i) + " is '" + fname + "' (" +
                                            std::to_string(size) + " bytes), expected '" + kStarFields[i].name +
                                            "' (" + std::to_string(kStarFields[i].size) + " bytes)"));
    scale[fname] = fscale;
    record_size += static_cast<size_t>(size);
  }
  for (const char* f : {"RA", "Dec", "dRA", "dDec", "parallax", "mag", "bv_index"})
    if (!(scale[f] > 0.0))
      throw FormatError(name + ": field '" + f + "' has scale " + std::to_string(scale[f]) + ", expected > 0");
  if (record_size != kRecordSize) throw FormatError(name + ": record size " + std::to_string(record_size));

  // Index of HTM trixels.
  uint32_t ntrixels = r.u32(off, "the index size");
  size_t index_off = off + 4;
  size_t data_off = index_off + size_t{12} * ntrixels;
  r.need(index_off, size_t{12} * ntrixels, "the index of " + std::to_string(ntrixels) + " entries");
  file.faint_mag = r.i16(data_off, "the data header") / 100.0;
  file.htm_level = r.u8(data_off + 2, "the data header");
  r.u16(data_off + 3, "the data header");  // max stars per trixel: unused
  size_t expect = data_off + 5;
  for (uint32_t i = 0; i < ntrixels; ++i) {
    size_t e = index_off + size_t{12} * i;
    uint32_t id = r.u32(e, "index entry " + std::to_string(i));
    uint32_t roff = r.u32(e + 4, "index entry " + std::to_string(i));
    uint32_t nrec = r.u32(e + 8, "index entry " + std::to_string(i));
    if (id != i)
      throw FormatError(r.error_at(e, "index entry " + std::to_string(i) + " has trixel id " + std::to_string(id)));
    if (roff != expect)
      throw FormatError(r.error_at(e, "index entry " + std::to_string(i) + " puts its records at byte " +
                                          std::to_string(roff) + ", expected " + std::to_string(expect)));
    for (uint32_t k = 0; k < nrec; ++k) {
      size_t p = roff + kRecordSize * k;
      std::string what = "star record " + std::to_string(k) + " of trixel " + std::to_string(i);
      r.need(p, kRecordSize, what);
      KStarsBinaryStar s;
      s.offset = p;
      s.ra_deg = r.i32(p, what) / scale["RA"] * 15.0;
      s.dec_deg = r.i32(p + 4, what) / scale["Dec"];
      s.pm_ra_mas_yr = r.i32(p + 8, what) / scale["dRA"];
      s.pm_dec_mas_yr = r.i32(p + 12, what) / scale["dDec"];
      s.parallax_mas = r.i32(p + 16, what) / scale["parallax"];
      int32_t hd = r.i32(p + 20, what);
      s.mag = r.i16(p + 24, what) / scale["mag"];
      s.b_minus_v = r.i16(p + 26, what) / scale["bv_index"];
      s.flags = r.u8(p + 30, what);
      if (hd < 0) throw FormatError(r.error_at(p + 20, what + ": negative HD number " + std::to_string(hd)));
      s.hd = static_cast<uint32_t>(hd);
      if (!(s.ra_deg >= 0.0 && s.ra_deg < 360.0))
        throw FormatError(r.error_at(p, what + ": RA " + std::to_string(s.ra_deg / 15.0) + " h outside [0, 24)"));
      if (!(s.dec_deg >= -90.0 && s.dec_deg <= 90.0))
        throw FormatError(r.error_at(p + 4, what + ": Dec " + std::to_string(s.dec_deg) + " deg outside [-90, 90]"));
      file.stars.push_back(s);
    }
    expect = roff + kRecordSize * nrec;
  }
  if (expect != bytes.size())
    throw FormatError(r.error_at(expect, std::to_string(bytes.size() - std::min(expect, bytes.size())) +
                                             " bytes after the last record (expected the end of the file)"));
  return file;
}

KStarsBinaryFile read_kstars_binary(const std::string& path) { return parse_kstars_binary(read_file(path), path); }

// ---------------------------------------------------------------------------
// stars.dat: fixed columns (0-based), as KStars' StarComponent::processStar read them
//   0-8 RA hhmmss.ss, 10 sign, 11-18 Dec ddmmss.s, 20-28 pmRA, 29-37 pmDec
//   (mas/yr, signed, 1 decimal), 38-44 parallax (mas), 46-50 V, 51-55 B-V,
//   56-57 spectral type, 59 multiplicity, 60-71 variability,
//   72- names: ",", Bayer designation (8 columns), ",", proper name.

namespace {

class LineParser {
 public:
  LineParser(const std::string& line, const std::string& file, uint32_t number)
      : line_(line), file_(file), number_(number) {}

  [[noreturn]] void fail(size_t col, size_t width, const std::string& what, const std::string& message) const {
    std::ostringstream msg;
    msg << file_ << ":" << number_ << ": columns " << col + 1 << "-" << col + width << " (" << what << "): ";
    std::string field = col < line_.size() ? line_.substr(col, width) : std::string();
    msg << "'" << field << "' " << message;
    throw FormatError(msg.str());
  }
  // `width` digits as an integer.
  int64_t digits(size_t col, size_t width, const std::string& what) const {
    if (col + width > line_.size()) fail(col, width, what, "is cut short (the line ends)");
    int64_t v = 0;
    for (size_t i = col; i < col + width; ++i) {
      char c = line_[i];
      if (c < '0' || c > '9') fail(col, width, what, "is not a number");
      v = v * 10 + (c - '0');
    }
    return v;
  }
  void expect(size_t col, char c, const std::string& what) const {
    if (col >= line_.size() || line_[col] != c)
      fail(col, 1, what, std::string("where '") + c + "' was expected");
  }
  // A fixed-point field: optional sign, digits, '.', exactly `decimals` digits.
  int64_t fixed_point(size_t col, size_t width, int decimals, const std::string& what) const {
    if (col + width > line_.size()) fail(col, width, what, "is cut short (the line ends)");
    std::string f = line_.substr(col, width);
    size_t i = 0;
    bool neg = false;
    if (f[0] == '-' || f[0] == '+') {
      neg = f[0] == '-';
      i = 1;
    }
    size_t dot = f.find('.');
    if (dot == std::string::npos || dot == i || f.size() - dot - 1 != static_cast<size_t>(decimals))
      fail(col, width, what, "is not a number with " + std::to_string(decimals) + " decimals");
    int64_t v = 0;
    for (size_t k = i; k < f.size(); ++k) {
      if (k == dot) continue;
      if (f[k] < '0' || f[k] > '9') fail(col, width, what, "is not a number");
      v = v * 10 + (f[k] - '0');
    }
    return neg ? -v : v;
  }

 private:
  const std::string& line_;
  const std::string& file_;
  uint32_t number_;
};

// Calls fn(line, number) for each line of `text` (split at '\n', numbered from 1; a '\r' is left to fn).
template <typename Fn>
void for_each_line(const std::string& text, Fn&& fn) {
  size_t pos = 0;
  uint32_t number = 0;
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    std::string line = text.substr(pos, eol - pos);
    pos = eol + 1;
    fn(std::move(line), ++number);
  }
}

}  // namespace

std::vector<KStarsTextStar> parse_kstars_text(const std::string& text, const std::string& name) {
  std::vector<KStarsTextStar> stars;
  for_each_line(text, [&](std::string line, uint32_t number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') return;
    LineParser p(line, name, number);
    if (line.size() < 60) p.fail(0, line.size(), "star line", "is shorter than 60 columns");
    for (char c : line)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f)
        p.fail(0, line.size(), "star line", "holds a control or non-ASCII character");

    KStarsTextStar s;
    s.line = number;
    int64_t h = p.digits(0, 2, "RA hours"), m = p.digits(2, 2, "RA minutes");
    int64_t sec = p.digits(4, 2, "RA seconds");
    p.expect(6, '.', "RA seconds");
    int64_t csec = p.digits(7, 2, "RA seconds");
    if (h > 23) p.fail(0, 2, "RA hours", "is above 23");
    if (m > 59) p.fail(2, 2, "RA minutes", "is above 59");
    // KStars rounded some seconds up to "60.00" (12 lines): the next minute.
    if (sec * 100 + csec > 6000) p.fail(4, 5, "RA seconds", "is above 60");
    s.ra_centisec = (((h * 60 + m) * 60 + sec) * 100 + csec) % 8640000;

    p.expect(9, ' ', "separator");
    if (line[10] != '+' && line[10] != '-') p.fail(10, 1, "Dec sign", "is not + or -");
    int64_t dd = p.digits(11, 2, "Dec degrees"), dm = p.digits(13, 2, "Dec minutes");
    int64_t ds = p.digits(15, 2, "Dec seconds");
    p.expect(17, '.', "Dec seconds");
    int64_t dds = p.digits(18, 1, "Dec seconds");
    if (dm > 59) p.fail(13, 2, "Dec minutes", "is above 59");
    if (ds * 10 + dds > 600) p.fail(15, 4, "Dec seconds", "is above 60");
    int64_t dec = ((dd * 60 + dm) * 60 + ds) * 10 + dds;
    if (dec > 90 * 36000) p.fail(11, 8, "Dec", "is beyond 90 degrees");
    s.dec_decisec = line[10] == '-' ? -dec : dec;

    p.expect(19, ' ', "separator");
    s.pm_ra_dmas = p.fixed_point(20, 9, 1, "pmRA");
    s.pm_dec_dmas = p.fixed_point(29, 9, 1, "pmDec");
    s.parallax_dmas = p.fixed_point(38, 7, 1, "parallax");
    p.expect(45, ' ', "separator");
    s.v_cmag = p.fixed_point(46, 5, 2, "V magnitude");
    s.bv_cmag = p.fixed_point(51, 5, 2, "B-V");

    if (line.size() > 72) {
      p.expect(72, ',', "names");
      s.bayer = trim(line.substr(73, 8));
      if (line.size() > 81) {
        p.expect(81, ',', "names");
        s.name = trim(line.substr(82));
      }
    }
    stars.push_back(std::move(s));
  });
  if (stars.empty()) throw FormatError(name + ": no star lines");
  return stars;
}

std::vector<KStarsTextStar> read_kstars_text(const std::string& path) {
  std::vector<unsigned char> bytes = read_file(path);
  return parse_kstars_text(std::string(bytes.begin(), bytes.end()), path);
}

// ---------------------------------------------------------------------------
// Conversion

Conversion convert_kstars(const std::string& kstars_dir, double max_mag, const std::string& source_note) {
  if (!std::isfinite(max_mag)) throw FormatError("--max-mag must be finite");
  const std::string dir = kstars_dir.empty() || kstars_dir.back() == '/' ? kstars_dir : kstars_dir + "/";
  std::vector<KStarsTextStar> text = read_kstars_text(dir + "stars.dat");
  std::vector<KStarsBinaryStar> binary;
  for (const char* f : {"namedstars.dat", "unnamedstars.dat"}) {
    KStarsBinaryFile b = read_kstars_binary(dir + f);
    binary.insert(binary.end(), b.stars.begin(), b.stars.end());
  }

  Conversion out;
  out.report.text_stars = text.size();
  out.report.binary_records = binary.size();
  const int64_t max_cmag = static_cast<int64_t>(std::floor(max_mag * 100.0 + 0.5));

  // Binary records by quarter-degree declination band.
  std::unordered_map<int, std::vector<size_t>> bands;
  for (size_t i = 0; i < binary.size(); ++i)
    bands[static_cast<int>(std::floor(binary[i].dec_deg * 4.0))].push_back(i);
  std::vector<bool> used(binary.size(), false);

  for (const KStarsTextStar& t : text) {
    if (t.v_cmag > max_cmag) continue;
    OutputStar o;
    o.text = t;
    const double ra = t.ra_deg(), dec = t.dec_deg(), v = t.v_cmag / 100.0;
    // Records within the radius, positions taken at epoch J2000.0 or moved on
    // from J1991.25 with their own proper motion (the files mix both epochs).
    // Many stars appear twice, as a Hipparcos record with the HD number and a
    // Tycho record without: the nearest record that has an HD number wins.
    struct Pick {
      double sep = 1e30, sep_epoch[2] = {0.0, 0.0};
      size_t i = 0;
    } best_hd, best_any;
    int band = static_cast<int>(std::floor(dec * 4.0));
    for (int b = band - 1; b <= band + 1; ++b) {
      auto it = bands.find(b);
      if (it == bands.end()) continue;
      for (size_t i : it->second) {
        const KStarsBinaryStar& s = binary[i];
        if (used[i] || std::fabs(s.mag - v) > kMatchMaxDeltaMag || std::fabs(s.dec_deg - dec) > 0.05) continue;
        Pick p;
        p.i = i;
        for (int e = 0; e < 2; ++e) {
          double years = e == 0 ? 0.0 : kHipparcosEpochYearsBeforeJ2000;
          double d = s.dec_deg + s.pm_dec_mas_yr * years / 3.6e6;
          double a = s.ra_deg + s.pm_ra_mas_yr * years / 3.6e6 / std::cos(s.dec_deg * kDeg);
          p.sep_epoch[e] = separation_arcsec(ra, dec, a, d);
        }
        p.sep = std::min(p.sep_epoch[0], p.sep_epoch[1]);
        if (p.sep < best_any.sep) best_any = p;
        if (s.hd != 0 && p.sep < best_hd.sep) best_hd = p;
      }
    }
    const Pick& best = best_hd.sep <= kMatchRadiusArcsec ? best_hd : best_any;
    if (best.sep <= kMatchRadiusArcsec) {
      used[best.i] = true;
      const KStarsBinaryStar& s = binary[best.i];
      o.hd = s.hd;
      if (s.hd != 0)
        ++out.report.hd_matched;
      else
        ++out.report.matched_no_hd;
      out.report.max_match_sep_arcsec = std::max(out.report.max_match_sep_arcsec, best.sep);
      // Which epoch fits, where the proper motion tells them apart (> 0.5").
      double shift = std::hypot(s.pm_ra_mas_yr, s.pm_dec_mas_yr) * kHipparcosEpochYearsBeforeJ2000 / 1000.0;
      if (shift > 0.5) ++(best.sep_epoch[0] <= best.sep_epoch[1] ? out.report.epoch_j2000 : out.report.epoch_j1991);
    } else {
      ++out.report.unmatched;
    }
    out.stars.push_back(std::move(o));
  }
  out.report.written = out.stars.size();

  // The text.
  std::ostringstream f;
  char maxbuf[32];
  std::snprintf(maxbuf, sizeof maxbuf, "%.2f", max_cmag / 100.0);
  f << "# atmo-star-catalog 1\n"
    << "# count: " << out.stars.size() << "\n"
    << "#\n"
    << "# Atmo's bright-star catalog: every star of KStars' stars.dat with V <= " << maxbuf << ".\n"
    << "# Generated by atmo-star-convert (tools/star_catalog); do not edit. Regenerate with\n"
    << "#   atmo-star-convert --kstars-dir /usr/share/kstars --max-mag " << maxbuf
    << " --source-note '" << source_note << "' --out <this file>\n"
    << "# Format, provenance and checks: docs/STAR_CATALOG.md.\n"
    << "#\n"
    << "# Source: KStars (https://kstars.kde.org) star data, Debian package kstars-data"
    << (source_note.empty() ? "" : " " + source_note) << ":\n"
    << "#   stars.dat: Hipparcos astrometry and photometry, positions at epoch J2000.0;\n"
    << "#   namedstars.dat, unnamedstars.dat: only the HD numbers, by a position cross-match.\n"
    << "# License: GPL-2+, as the KStars data it is derived from (Debian:\n"
    << "#   /usr/share/doc/kstars-data/copyright). Underlying data: ESA, 1997, The Hipparcos\n"
    << "#   and Tycho Catalogues, ESA SP-1200.\n"
    << "#\n"
    << "# Column meanings (tab-separated, one star per line, '-' for no text):\n"
    << "#   hd             Henry Draper number; 0 where the cross-match found none\n"
    << "#   kstars_line    line of the star in KStars' stars.dat: a unique key\n"
    << "#   ra_deg         right ascension, ICRS, epoch J2000.0, degrees\n"
    << "#   dec_deg        declination, ICRS, epoch J2000.0, degrees\n"
    << "#   pm_ra_mas_yr   proper motion in RA times cos(dec) (mu_alpha*), mas per Julian year\n"
    << "#   pm_dec_mas_yr  proper motion in declination, mas per Julian year\n"
    << "#   parallax_mas   parallax, mas\n"
    << "#   v_mag          Johnson V magnitude\n"
    << "#   b_minus_v      Johnson B-V colour index\n"
    << "#   bayer          Bayer (or Flamsteed) designation as KStars writes it (e.g. 'alp CMa')\n"
    << "#   name           proper name\n"
    << "# columns: hd\tkstars_line\tra_deg\tdec_deg\tpm_ra_mas_yr\tpm_dec_mas_yr\tparallax_mas\tv_mag\tb_minus_v\tbayer"
       "\tname\n";
  char buf[64];
  for (const OutputStar& o : out.stars) {
    const KStarsTextStar& t = o.text;
    f << o.hd << '\t' << t.line << '\t';
    std::snprintf(buf, sizeof buf, "%.8f\t%.8f", t.ra_deg(), t.dec_deg());
    f << buf << '\t' << fixed(t.pm_ra_dmas, 1) << '\t' << fixed(t.pm_dec_dmas, 1) << '\t'
      << fixed(t.parallax_dmas, 1) << '\t' << fixed(t.v_cmag, 2) << '\t' << fixed(t.bv_cmag, 2) << '\t'
      << (t.bayer.empty() ? "-" : t.bayer) << '\t' << (t.name.empty() ? "-" : t.name) << '\n';
  }
  out.text = f.str();
  return out;
}

// ---------------------------------------------------------------------------
// Cross-match with xplanet's Bright Star Catalogue subset

BscCrossmatch crossmatch_bsc(const std::vector<OutputStar>& stars, const std::string& bsc_path, double max_mag) {
  std::vector<unsigned char> bytes = read_file(bsc_path);
  std::string text(bytes.begin(), bytes.end());
  std::unordered_map<uint32_t, const OutputStar*> by_hd;
  for (const OutputStar& s : stars)
    if (s.hd != 0) by_hd.emplace(s.hd, &s);

  BscCrossmatch x;
  std::vector<BscMatch> matches;
  for_each_line(text, [&](const std::string& line, uint32_t number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') return;
    // Dec RA V "name" BSN HD SAO
    double dec = 0.0, ra_h = 0.0, v = 0.0;
    size_t q1 = line.find('"'), q2 = q1 == std::string::npos ? q1 : line.find('"', q1 + 1);
    long bsn = 0, hd = 0, sao = 0;
    if (q2 == std::string::npos || std::sscanf(line.c_str(), "%lf %lf %lf", &dec, &ra_h, &v) != 3 ||
        std::sscanf(line.c_str() + q2 + 1, "%ld %ld %ld", &bsn, &hd, &sao) != 3)
      throw FormatError(bsc_path + ":" + std::to_string(number) + ": not 'Dec RA V \"name\" BSN HD SAO'");
    ++x.bsc_entries;
    bool bright = v <= max_mag && hd > 0;
    x.bsc_bright += bright;
    auto it = hd > 0 ? by_hd.find(static_cast<uint32_t>(hd)) : by_hd.end();
    if (it == by_hd.end()) {
      x.bright_missing += bright;
      return;
    }
    const KStarsTextStar& t = it->second->text;
    BscMatch m;
    m.hd = static_cast<uint32_t>(hd);
    m.bsc_name = trim(line.substr(q1 + 1, q2 - q1 - 1));
    m.sep_arcsec = separation_arcsec(t.ra_deg(), t.dec_deg(), ra_h * 15.0, dec);
    m.ddec_arcsec = (t.dec_deg() - dec) * 3600.0;
    m.dmag = t.v_cmag / 100.0 - v;
    matches.push_back(m);
  });
  x.matched = matches.size();
  std::vector<double> sep, ddec, dmag, admag;
  for (const BscMatch& m : matches) {
    sep.push_back(m.sep_arcsec);
    ddec.push_back(std::fabs(m.ddec_arcsec));
    dmag.push_back(m.dmag);
    admag.push_back(std::fabs(m.dmag));
  }
  x.sep_median = quantile(sep, 0.5);
  x.sep_p95 = quantile(sep, 0.95);
  x.sep_max = quantile(sep, 1.0);
  x.ddec_median = quantile(ddec, 0.5);
  x.ddec_p95 = quantile(ddec, 0.95);
  x.ddec_max = quantile(ddec, 1.0);
  x.dmag_median = quantile(dmag, 0.5);
  x.dmag_abs_median = quantile(admag, 0.5);
  x.dmag_p95 = quantile(admag, 0.95);
  x.dmag_max = quantile(admag, 1.0);
  std::vector<BscMatch> by_sep = matches, by_mag = matches;
  std::sort(by_sep.begin(), by_sep.end(), [](const BscMatch& a, const BscMatch& b) { return a.sep_arcsec > b.sep_arcsec; });
  std::sort(by_mag.begin(), by_mag.end(),
            [](const BscMatch& a, const BscMatch& b) { return std::fabs(a.dmag) > std::fabs(b.dmag); });
  by_sep.resize(std::min<size_t>(5, by_sep.size()));
  by_mag.resize(std::min<size_t>(5, by_mag.size()));
  x.worst_sep = by_sep;
  x.worst_mag = by_mag;
  return x;
}

}  // namespace atmo::tools::star_catalog
