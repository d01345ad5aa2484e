#!/usr/bin/env python3
"""Converts colord's CGATS-style spectral files (Debian package colord-data:
/usr/share/colord/cmf/*.cmf, /usr/share/colord/illuminant/*.sp) into the CSV
files under data/ that the build embeds into atmo_spectral.

Usage: convert_cmf.py INPUT OUTPUT
  .cmf (3 sets)  -> wavelength_nm,x,y,z
  .sp  (1 set)   -> wavelength_nm,value
Values are copied digit for digit (no rounding); wavelengths come from
SPECTRAL_START_NM / SPECTRAL_END_NM / SPECTRAL_BANDS.
"""
import sys


def read_cgats(path):
    keys, rows, in_data = {}, [], False
    with open(path, encoding="ascii") as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "BEGIN_DATA":
                in_data = True
            elif words[0] == "END_DATA":
                in_data = False
            elif in_data:
                rows.append(words)
            elif len(words) >= 2:
                keys[words[0]] = words[1].strip('"')
    start = float(keys["SPECTRAL_START_NM"])
    end = float(keys["SPECTRAL_END_NM"])
    bands = int(keys["SPECTRAL_BANDS"])
    step = (end - start) / (bands - 1)
    for r in rows:
        if len(r) != bands:
            sys.exit(f"{path}: a data row has {len(r)} values, expected {bands}")
        for v in r:
            float(v)  # refuse anything that is not a number
    wavelengths = [start + i * step for i in range(bands)]
    return wavelengths, rows


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    src, dst = sys.argv[1], sys.argv[2]
    wavelengths, rows = read_cgats(src)
    header = "wavelength_nm,x,y,z" if len(rows) == 3 else "wavelength_nm,value"
    if len(rows) not in (1, 3):
        sys.exit(f"{src}: {len(rows)} data sets, expected 1 or 3")
    with open(dst, "w", encoding="ascii") as out:
        out.write(f"# converted by tools/reference/convert_cmf.py from {src} (Debian colord-data)\n")
        out.write(header + "\n")
        for i, w in enumerate(wavelengths):
            out.write(f"{w:g}," + ",".join(r[i] for r in rows) + "\n")


if __name__ == "__main__":
    main()
