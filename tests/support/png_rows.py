"""A PNG reader for the Python test drivers (no third-party modules): 8-bit RGB or RGBA, non-interlaced, as
the project's write_png writes them (tools/support image.h).

    rows = read_png_rgb(path)   # rows[y][x] = (r, g, b), 0-255, row 0 at the top
    grey = read_png(path)       # rows[y][x] = mean of r, g, b
"""
import struct
import sys
import zlib


def read_png_rgb(path):
    """Rows of (r, g, b) tuples; exits with the file named if it is not a PNG this reads."""
    data = open(path, 'rb').read()
    if data[:8] != b'\x89PNG\r\n\x1a\n':
        sys.exit(f'{path}: not a PNG')
    pos, idat = 8, b''
    while pos < len(data):
        n, = struct.unpack('>I', data[pos:pos + 4])
        kind, chunk = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b'IHDR':
            w, h, depth, colour, _, _, interlace = struct.unpack('>IIBBBBB', chunk)
            if depth != 8 or colour not in (2, 6) or interlace:
                sys.exit(f'{path}: depth {depth}, colour type {colour}, interlace {interlace}: not read here')
        elif kind == b'IDAT':
            idat += chunk
    bpp = 4 if colour == 6 else 3
    raw, stride = zlib.decompress(idat), w * bpp
    rows, prev, i = [], bytearray(stride), 0
    for _ in range(h):
        f, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[x * bpp:x * bpp + 3]) for x in range(w)])
        prev = line
    return rows


def read_png(path):
    """Rows of grey levels (the mean of R, G, B)."""
    return [[sum(p) / 3.0 for p in row] for row in read_png_rgb(path)]
