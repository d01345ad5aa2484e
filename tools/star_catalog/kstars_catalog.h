// kstars_catalog.h — reads KStars' star data (Debian package kstars-data:
// stars.dat, namedstars.dat, unnamedstars.dat) and writes Atmo's bright-star
// catalog text (format: docs/STAR_CATALOG.md; parser:
// plugin/core/astro/star_catalog.h). Also cross-matches the result with the
// Yale Bright Star Catalogue subset that Debian's xplanet ships.
//
// Every reader throws FormatError on malformed input, naming the file and the
// byte offset (binary files) or the line and columns (text files).
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace atmo::tools::star_catalog {

class FormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One 32-byte "starData" record of KStars' binary star files, scaled with the
// file's own field descriptors. Positions are ICRS, but the epoch is not
// uniform (J2000.0 for most records, J1991.25 for some; docs/STAR_CATALOG.md).
struct KStarsBinaryStar {
  double ra_deg = 0.0, dec_deg = 0.0;
  double pm_ra_mas_yr = 0.0;   // mu_alpha* = dRA/dt cos(dec)
  double pm_dec_mas_yr = 0.0;
  double parallax_mas = 0.0;
  uint32_t hd = 0;             // Henry Draper number, 0 when none (stored unscaled)
  double mag = 0.0, b_minus_v = 0.0;
  uint8_t flags = 0;           // 1: named, 2: multiple, 4: variable
  size_t offset = 0;           // byte offset of the record in its file
};

struct KStarsBinaryFile {
  std::string preamble;        // the 124-byte text at the start, NULs removed
  int version = 0;
  bool big_endian = false;
  double faint_mag = 0.0;      // from the data section's header
  int htm_level = 0;
  std::vector<KStarsBinaryStar> stars;
};

// Reads namedstars.dat / unnamedstars.dat (any file of 32-byte starData records).
KStarsBinaryFile read_kstars_binary(const std::string& path);
KStarsBinaryFile parse_kstars_binary(const std::vector<unsigned char>& bytes, const std::string& name);

// One line of KStars' text catalog stars.dat (Hipparcos; ICRS, epoch J2000.0),
// kept in the file's fixed-point units so that the output repeats its digits.
struct KStarsTextStar {
  uint32_t line = 0;
  int64_t ra_centisec = 0;     // RA in 0.01 s of time, 0 .. 8 640 000
  int64_t dec_decisec = 0;     // Dec in 0.1", signed
  int64_t pm_ra_dmas = 0;      // mu_alpha* in 0.1 mas/yr
  int64_t pm_dec_dmas = 0;     // mu_delta in 0.1 mas/yr
  int64_t parallax_dmas = 0;   // 0.1 mas
  int64_t v_cmag = 0;          // V in 0.01 mag
  int64_t bv_cmag = 0;         // B-V in 0.01 mag
  std::string bayer, name;     // empty when none
  double ra_deg() const { return static_cast<double>(ra_centisec) / 24000.0; }
  double dec_deg() const { return static_cast<double>(dec_decisec) / 36000.0; }
};

std::vector<KStarsTextStar> read_kstars_text(const std::string& path);
std::vector<KStarsTextStar> parse_kstars_text(const std::string& text, const std::string& name);

struct OutputStar {
  KStarsTextStar text;
  uint32_t hd = 0;             // from the matched binary record, 0 when none
};

struct ConversionReport {
  size_t text_stars = 0;            // lines of stars.dat
  size_t binary_records = 0;        // records of namedstars.dat + unnamedstars.dat
  size_t written = 0;               // stars with V <= max_mag
  size_t hd_matched = 0;            // of those, given an HD number
  size_t matched_no_hd = 0;         // matched a binary record whose HD is 0
  size_t unmatched = 0;             // no binary record within the limits
  size_t epoch_j2000 = 0;           // matched records that sit at epoch J2000.0
  size_t epoch_j1991 = 0;           // ... at epoch J1991.25
  double max_match_sep_arcsec = 0.0;
};

struct Conversion {
  std::vector<OutputStar> stars;
  std::string text;                 // the catalog file's content
  ConversionReport report;
};

// Reads DIR/stars.dat, DIR/namedstars.dat and DIR/unnamedstars.dat.
// `source_note` is written into the header (e.g. the package version).
Conversion convert_kstars(const std::string& kstars_dir, double max_mag, const std::string& source_note);

// Cross-match by HD number with xplanet's stars/BSC (Yale BSC 5th ed. subset:
// Dec deg, RA hours, V, "name", BSN, HD, SAO; J2000, 4 decimals).
struct BscMatch {
  uint32_t hd = 0;
  std::string bsc_name;
  double sep_arcsec = 0.0, ddec_arcsec = 0.0, dmag = 0.0;  // ours minus BSC
};
struct BscCrossmatch {
  size_t bsc_entries = 0;
  size_t bsc_bright = 0;           // BSC entries with V <= max_mag and an HD number
  size_t matched = 0;              // of all BSC entries, found in ours by HD
  size_t bright_missing = 0;       // bright BSC entries whose HD is not in ours
  double sep_median = 0.0, sep_p95 = 0.0, sep_max = 0.0;
  double ddec_median = 0.0, ddec_p95 = 0.0, ddec_max = 0.0;       // |Dec difference|
  double dmag_median = 0.0, dmag_abs_median = 0.0, dmag_p95 = 0.0, dmag_max = 0.0;
  std::vector<BscMatch> worst_sep, worst_mag;  // five each
};
BscCrossmatch crossmatch_bsc(const std::vector<OutputStar>& stars, const std::string& bsc_path, double max_mag);

}  // namespace atmo::tools::star_catalog
