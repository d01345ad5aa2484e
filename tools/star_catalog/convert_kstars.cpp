// atmo-star-convert: writes Atmo's bright-star catalog (data/stars/*.tsv) from
// KStars' star data (Debian package kstars-data, /usr/share/kstars), and
// optionally cross-matches it with xplanet's Bright Star Catalogue subset.
// See docs/STAR_CATALOG.md.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>

#include "kstars_catalog.h"

using namespace atmo::tools::star_catalog;

int main(int argc, char** argv) {
  CLI::App app{"atmo-star-convert: Atmo's bright-star catalog from KStars' star data (kstars-data)"};
  std::string kstars_dir, out_path, bsc_path, source_note;
  double max_mag = 6.6;
  app.add_option("--kstars-dir", kstars_dir, "folder with stars.dat, namedstars.dat, unnamedstars.dat (/usr/share/kstars)")
      ->required();
  app.add_option("--max-mag", max_mag, "keep stars with V <= this (default 6.6)");
  app.add_option("--out", out_path, "catalog file to write (data/stars/hipparcos_v6_6.tsv)");
  app.add_option("--source-note", source_note, "written into the header after the package name, e.g. '5:3.6.2-2'");
  app.add_option("--bsc", bsc_path, "cross-match by HD with xplanet's stars/BSC and print the differences");
  CLI11_PARSE(app, argc, argv);

  try {
    Conversion c = convert_kstars(kstars_dir, max_mag, source_note);
    const ConversionReport& r = c.report;
    std::printf("stars.dat: %zu stars; namedstars.dat + unnamedstars.dat: %zu records\n", r.text_stars,
                r.binary_records);
    std::printf("written: %zu stars with V <= %.2f\n", r.written, max_mag);
    std::printf("HD numbers: %zu matched, %zu matched a record without HD, %zu without a record within 1.5\" "
                "(largest match distance %.2f\")\n",
                r.hd_matched, r.matched_no_hd, r.unmatched, r.max_match_sep_arcsec);
    std::printf("epoch of the matched binary records (where proper motion tells): J2000.0 %zu, J1991.25 %zu\n",
                r.epoch_j2000, r.epoch_j1991);
    if (!out_path.empty()) {
      std::ofstream out(out_path, std::ios::binary);
      out << c.text;
      out.close();
      if (!out) {
        std::fprintf(stderr, "atmo-star-convert: cannot write %s\n", out_path.c_str());
        return 1;
      }
      std::printf("wrote %s (%zu bytes)\n", out_path.c_str(), c.text.size());
    }
    if (!bsc_path.empty()) {
      BscCrossmatch x = crossmatch_bsc(c.stars, bsc_path, max_mag);
      std::printf("BSC (%s): %zu entries, %zu matched by HD; %zu with V <= %.2f and an HD number, %zu of them not "
                  "found\n",
                  bsc_path.c_str(), x.bsc_entries, x.matched, x.bsc_bright, max_mag, x.bright_missing);
      std::printf("  position difference: median %.2f\", 95%% %.2f\", max %.2f\"\n", x.sep_median, x.sep_p95,
                  x.sep_max);
      std::printf("  |Dec difference|:    median %.2f\", 95%% %.2f\", max %.2f\"\n", x.ddec_median, x.ddec_p95,
                  x.ddec_max);
      std::printf("  V difference (ours - BSC): median %+.3f, |median| %.3f, 95%% %.3f, max %.2f mag\n",
                  x.dmag_median, x.dmag_abs_median, x.dmag_p95, x.dmag_max);
      for (const BscMatch& m : x.worst_sep)
        std::printf("  largest position difference: HD %u (%s) %.2f\"\n", m.hd, m.bsc_name.c_str(), m.sep_arcsec);
      for (const BscMatch& m : x.worst_mag)
        std::printf("  largest V difference: HD %u (%s) %+.2f mag\n", m.hd, m.bsc_name.c_str(), m.dmag);
    }
  } catch (const FormatError& e) {
    std::fprintf(stderr, "atmo-star-convert: %s\n", e.what());
    return 1;
  }
  return 0;
}
