#!/usr/bin/env python3
"""The sample host draws ATMO_PASS_CLOUDS after ATMO_PASS_NIGHT_SKY (atmo.h), so
an overcast deck hides the stars.

Renders the headless frame at a moonless night (2024-12-01 22:00 UTC, new
moon) without clouds and under an 8-okta stratus deck (800-1200 m over 20 km,
which fills the view above ~2 degrees), finds the stars of the clear frame
(pixels that are the maximum of their 3x3 block and exceed the mean of the
5x5 ring around them by PEAK display levels of 255), and checks that none of
them is still a peak under the deck. Before the order was fixed (clouds, then
night sky) all three stars of the clear frame shone through the deck.

usage: clouds_hide_stars.py SAMPLE_HOST PLUGIN OUT_DIR
"""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'support'))
from png_rows import read_png  # noqa: E402

PEAK = 20.0      # display levels (of 255) above the ring's mean
SKY_ROWS = 56    # rows 0..55 of 144: above the deck's edge (~2 degrees up; the horizon is near row 65)


def excess(rows, x, y):
    """How far (x, y) stands above the mean of the 5x5 ring around it; None if not its 3x3 maximum."""
    if rows[y][x] < max(rows[y + j][x + i] for j in (-1, 0, 1) for i in (-1, 0, 1)):
        return None
    ring = [rows[y + j][x + i] for j in range(-2, 3) for i in range(-2, 3) if max(abs(i), abs(j)) == 2]
    return rows[y][x] - sum(ring) / len(ring)


def render(host, plugin, out, extra):
    shutil.rmtree(out, ignore_errors=True)
    cmd = [host, '--plugin', plugin, '--frames', '1', '--out', out, '--width', '256', '--height', '144',
           '--utc', '2024-12-01T22:00:00Z', '--ev', '-3'] + extra
    run = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(run.stdout, end='')
    if run.returncode != 0:
        sys.exit(f'{" ".join(cmd)}: exit {run.returncode}')
    return read_png(os.path.join(out, 'frame_000.png'))


def main():
    host, plugin, out = sys.argv[1:4]
    clear = render(host, plugin, os.path.join(out, 'clear'), [])
    deck = render(host, plugin, os.path.join(out, 'deck'), ['--cloud', 'stratus:8:800:1200:20'])
    stars = [(x, y, e) for y in range(2, SKY_ROWS) for x in range(2, len(clear[0]) - 2)
             if (e := excess(clear, x, y)) is not None and e > PEAK]
    print(f'clear night: {len(stars)} stars above {PEAK} levels in rows < {SKY_ROWS}: ' +
          ', '.join(f'({x},{y}) +{e:.0f}' for x, y, e in stars))
    if len(stars) < 2:
        sys.exit('FAIL: fewer than 2 stars in the clear frame: the test could not see the deck hide them')
    through = [(x, y, e) for x, y, _ in stars if (e := excess(deck, x, y)) is not None and e > PEAK]
    print(f'under the deck: {len(through)} of them still shine: ' +
          ', '.join(f'({x},{y}) +{e:.0f}' for x, y, e in through))
    if through:
        sys.exit('FAIL: stars drawn over the clouds (ATMO_PASS_NIGHT_SKY after ATMO_PASS_CLOUDS?)')
    print('PASS')


if __name__ == '__main__':
    main()
