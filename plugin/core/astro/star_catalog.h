// star_catalog.h — the bright-star catalog (data/stars/hipparcos_v6_6.tsv,
// written by tools/star_catalog/atmo-star-convert from Debian's kstars-data;
// format and provenance: docs/STAR_CATALOG.md), parsed into the form ERFA's
// eraAtco13 / eraPmsafe take: ICRS place at epoch J2000.0, proper motion as
// dRA/dt and dDec/dt in radians per Julian year, parallax in arcseconds.
//
// The parser never throws on bad input and never crashes: malformed text
// (wrong column count, a non-number, NaN, a value out of range, a truncated
// or empty file) comes back as StarCatalogLoad::error naming the line.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace atmo::core::astro {

struct CatalogStar {
  // Henry Draper number (0 when the converter matched none). KStars' star
  // files carry no Hipparcos number, so HD is the catalogue identifier here.
  uint32_t hd = 0;
  // Line of the star in KStars' stars.dat (kstars-data 3.6.2): unique in the
  // file and traceable to the source, also for the stars without an HD number.
  uint32_t kstars_line = 0;
  double ra_rad = 0.0, dec_rad = 0.0;    // ICRS, epoch J2000.0
  double pm_ra_rad_per_year = 0.0;       // dRA/dt (NOT times cos dec): ERFA's form
  double pm_dec_rad_per_year = 0.0;      // dDec/dt
  double parallax_arcsec = 0.0;          // Hipparcos parallax (0 where the source has none)
  double v_mag = 0.0;                    // Johnson V (Hipparcos field H5)
  double b_minus_v = 0.0;                // Johnson B-V
  std::string bayer;                     // e.g. "alp CMa"; empty when none
  std::string name;                      // proper name, e.g. "Sirius"; empty when none
};

struct StarCatalogLoad {
  std::vector<CatalogStar> stars;  // in file order (brightest first)
  std::string error;               // empty on success; names the source, line and column
};

// The text header's first line; the format version changes with the columns.
inline constexpr std::string_view kStarCatalogMagic = "# atmo-star-catalog 1";
// The header line naming the columns, tab-separated, after "# columns: ".
inline constexpr std::string_view kStarCatalogColumns =
    "hd\tkstars_line\tra_deg\tdec_deg\tpm_ra_mas_yr\tpm_dec_mas_yr\tparallax_mas\tv_mag\tb_minus_v\tbayer\tname";

// Reads and parses a catalog file; on any error `stars` is empty.
StarCatalogLoad load_star_catalog(const std::string& path);
// Parses catalog text; `source` names it in error messages.
StarCatalogLoad parse_star_catalog(std::string_view text, std::string_view source = "<text>");

// The star with this HD number (HD numbers are unique in the shipped file),
// or nullptr; hd == 0 finds nothing. Linear search (about 10 000 stars).
const CatalogStar* find_star(const std::vector<CatalogStar>& stars, uint32_t hd);
// The star with this proper name (exact, case-sensitive), or nullptr.
const CatalogStar* find_star_by_name(const std::vector<CatalogStar>& stars, std::string_view name);

}  // namespace atmo::core::astro
