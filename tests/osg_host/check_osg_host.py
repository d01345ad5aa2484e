#!/usr/bin/env python3
"""atmo-osg-host's frames, with the plugin and without it (--no-atmo). Run it under Xvfb
(xvfb-run -a): the host draws into a GLX pbuffer.

  image: the frame with the plugin: the sky above the horizon is bright and blue (not black), and the
         terrain is hazed with distance: far terrain (>= FAR_M) lies closer to the horizon sky's colour
         than near terrain (<= NEAR_M), by a factor below MAX_FAR_NEAR, and closer than the same far
         terrain without the plugin (where nothing hazes it). The host exits 0: no GL error, no plugin
         error, no difference between GL's state and osg::State's after any plugin call.
  hud:   OSG's own drawing after the plugin's passes is unchanged: the HUD panel (textures on units 0
         and 1 through a program, a fixed-function quad, blending, a quad the depth test hides), drawn by
         OSG after the passes, is bit-identical in every frame with and without the plugin, and shows
         the fixed-function quad's colour and not the hidden quad's.
  hud_leak: the same comparison can fail: with --inject-leak (front-face culling left on behind
         osg::State's back after the aerial perspective; the host exits 1) the HUD's pixels differ.

usage: check_osg_host.py image|hud|hud_leak HOST PLUGIN OUT_DIR
"""
import os
import re
import shutil
import subprocess
import sys

FRAMES = 3
WIDTH, HEIGHT = 256, 144
NEAR_M, FAR_M = 2500, 9000
MAX_FAR_NEAR = 0.6


def read_netpbm(path):
    """Binary P6 (8-bit RGB) or P5 (16-bit grey) as (width, height, rows of pixels), top row first."""
    data = open(path, 'rb').read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    pos += 1
    kind, w, h, maxval = fields[0], int(fields[1]), int(fields[2]), int(fields[3])
    if kind == b'P6' and maxval == 255:
        px = [tuple(data[pos + 3 * i:pos + 3 * i + 3]) for i in range(w * h)]
    elif kind == b'P5' and maxval == 65535:
        px = [data[pos + 2 * i] << 8 | data[pos + 2 * i + 1] for i in range(w * h)]
    else:
        sys.exit(f'{path}: {kind} with maxval {maxval} is not read here')
    return w, h, [px[y * w:(y + 1) * w] for y in range(h)]


def render(host, plugin, out, extra, want_exit=0):
    shutil.rmtree(out, ignore_errors=True)
    cmd = [host, '--plugin', plugin, '--frames', str(FRAMES),
           '--width', str(WIDTH), '--height', str(HEIGHT), '--out', out] + extra
    run = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=240)
    print(run.stdout, end='')
    if run.returncode != want_exit:
        sys.exit(f'{" ".join(cmd)} exited with {run.returncode}, not {want_exit}')
    if not extra and not re.search(r'GL state checks: [1-9]\d* .*, 0 mismatches', run.stdout):
        sys.exit('no state checks were made, or some mismatched')
    return run.stdout


def mean(colours):
    n = len(colours)
    return tuple(sum(c[k] for c in colours) / n for k in range(3)) if n else None


def dist(a, b):
    return sum((a[k] - b[k]) ** 2 for k in range(3)) ** 0.5


def regions(out, frame):
    """Upper sky, horizon sky, near and far terrain mean colours of one frame."""
    w, h, rgb = read_netpbm(os.path.join(out, f'frame_{frame:03d}.ppm'))
    _, _, metres = read_netpbm(os.path.join(out, f'frame_{frame:03d}_distance.pgm'))
    sky, horizon, near, far = [], [], [], []
    for x in range(w):
        top = next((y for y in range(h) if metres[y][x] != 65535), h)  # the terrain's silhouette in this column
        sky += [rgb[y][x] for y in range(0, max(1, top // 3))]
        horizon += [rgb[y][x] for y in range(max(0, top - 4), max(0, top - 1))]
        for y in range(top, h):
            d = metres[y][x]
            if d <= NEAR_M:
                near.append(rgb[y][x])
            elif FAR_M <= d < 65535:
                far.append(rgb[y][x])
    return mean(sky), mean(horizon), mean(near), mean(far), (len(sky), len(horizon), len(near), len(far))


def check_image(with_atmo, without):
    frame = FRAMES - 1
    sky, horizon, near, far, counts = regions(with_atmo, frame)
    _, _, near0, far0, _ = regions(without, frame)
    print(f'pixels: upper sky {counts[0]}, horizon sky {counts[1]}, near terrain (<= {NEAR_M} m) {counts[2]}, '
          f'far terrain (>= {FAR_M} m) {counts[3]}')
    if min(counts) == 0:
        sys.exit('a region is empty: the camera no longer sees sky, horizon, near and far terrain')
    fmt = lambda c: '(%.1f, %.1f, %.1f)' % c
    print(f'upper sky {fmt(sky)}, horizon sky {fmt(horizon)}; near terrain {fmt(near)}, far terrain {fmt(far)}; '
          f'without the plugin: near {fmt(near0)}, far {fmt(far0)}')
    failures = []
    if not (max(sky) >= 100 and sky[2] > sky[0] + 20 and sky[2] >= sky[1]):
        failures.append(f'the upper sky {fmt(sky)} is not bright blue (max >= 100, B > R + 20, B >= G)')
    d_near, d_far, d_far0 = dist(near, horizon), dist(far, horizon), dist(far0, horizon)
    print(f'distance to the horizon sky colour: near terrain {d_near:.1f}, far terrain {d_far:.1f} '
          f'(far/near {d_far / d_near:.3f}, at most {MAX_FAR_NEAR}); far terrain without the plugin {d_far0:.1f}')
    if d_far >= MAX_FAR_NEAR * d_near:
        failures.append('far terrain is not hazed towards the horizon sky')
    if d_far >= d_far0:
        failures.append('far terrain is no closer to the horizon sky than without the plugin')
    if failures:
        sys.exit('; '.join(failures))


class HudDiffers(Exception):
    pass


def check_hud(with_atmo, without, log, frames=FRAMES):
    m = re.search(r'hud panel: (\d+) (\d+) (\d+) (\d+)', log)
    if not m:
        sys.exit('the host did not say where the HUD panel is')
    x0, y0, w, h = map(int, m.groups())
    total = 0
    for frame in range(frames):
        _, height, a = read_netpbm(os.path.join(with_atmo, f'frame_{frame:03d}.ppm'))
        _, _, b = read_netpbm(os.path.join(without, f'frame_{frame:03d}.ppm'))
        rows = range(height - y0 - h, height - y0)  # the panel's rows, top row first
        differing = [(x, y) for y in rows for x in range(x0, x0 + w) if a[y][x] != b[y][x]]
        total += w * h
        if differing:
            raise HudDiffers(f'frame {frame}: {len(differing)} of {w * h} HUD pixels differ with the plugin, e.g. at '
                     f'{differing[0]}: {a[differing[0][1]][differing[0][0]]} against {b[differing[0][1]][differing[0][0]]}')
        # The fixed-function quad (1, 0.8, 0) fills the panel's middle; the hidden green quad is not seen.
        centre = a[height - y0 - h // 2][x0 + w // 2]
        left = a[height - y0 - h // 2][x0 + 2]
        if centre != (255, 204, 0):
            sys.exit(f'frame {frame}: the HUD centre is {centre}, not the fixed-function quad\'s (255, 204, 0)')
        if left[1] == 255 and left[0] == 0:
            sys.exit(f'frame {frame}: the quad behind the panel shows through ({left}): depth test broken')
    print(f'HUD panel {w}x{h} at ({x0}, {y0}): {total} pixels in {frames} frames bit-identical with and without '
          'the plugin')


def main():
    if len(sys.argv) != 5 or sys.argv[1] not in ('image', 'hud', 'hud_leak'):
        sys.exit(__doc__)
    mode, host, plugin, out = sys.argv[1:]
    if not os.environ.get('DISPLAY'):
        sys.exit('no DISPLAY: run under xvfb-run -a (Debian package xvfb, tools/install-deps.sh)')
    with_atmo, without = os.path.join(out, 'atmo'), os.path.join(out, 'no_atmo')
    if mode == 'hud_leak':
        # The host stops after the first frame with a mismatch.
        log = render(host, plugin, with_atmo, ['--inject-leak'], want_exit=1)
        render(host, plugin, without, ['--no-atmo'])
        try:
            check_hud(with_atmo, without, log, frames=1)
        except HudDiffers as e:
            print(f'with the injected leak: {e}')
            return
        sys.exit('the HUD did not change with the injected leak: the comparison cannot fail')
    log = render(host, plugin, with_atmo, [])
    render(host, plugin, without, ['--no-atmo'])
    try:
        if mode == 'image':
            check_image(with_atmo, without)
        else:
            check_hud(with_atmo, without, log)
    except HudDiffers as e:
        sys.exit(str(e))


if __name__ == '__main__':
    main()
