#!/usr/bin/env python3
"""atmo-cigi-ig driven over loopback by atmo-cigi-host-emulator (docs/CIGI.md, "atmo-cigi-ig").

Starts the IG on an ephemeral 127.0.0.1 port (--port 0 --port-file), runs the emulator's script against it
(four states, two host frames each: noon in clear air, noon at 2 km, noon under an overcast deck from a
little-endian host, a clear night; seven bad datagrams between them), then checks:

(a) the state log follows the packets: one line per host frame, in order, with the host frame number, the
    time, the visibility and the cloud layers the emulator sent; every frame answered by a Start of Frame that
    echoes its host frame number, counts the IG's frames and comes in the frame's byte order;
(b) the pictures: the noon sky brighter than the night sky; at 2 km the distant terrain's contrast against the
    horizon sky and its texture lower than at 50 km; the overcast deck greys the sky (saturation) and darkens
    the ground; each state's two frames the same picture (the IG's --deferred-frames 1: a change drawn from the
    frame that brought it);
(c) each bad datagram refused with one log line naming the packet, byte and field; the unknown packets of a
    good message skipped in one line; the mapping's note and each packet's not-drawn line said once; the IG
    went on to the end (exit 0, every frame drawn).

Every wait is bounded: the IG's start (STARTUP_S), the emulator (its --sof-timeout per frame, RUN_S in all),
the IG's exit (its --idle-timeout, EXIT_S).

usage: cigi_ig_loopback.py IG EMULATOR PLUGIN OUT_DIR
"""
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'support'))
from png_rows import read_png_rgb  # noqa: E402

STARTUP_S = 120   # EGL, the plugin's gl_init and first tables on llvmpipe (~1 s here; the sanitizer build is slower)
RUN_S = 300       # the emulator's whole script
EXIT_S = 60
FRAMES = 8        # 4 states x 2 frames

# Bands of the 320 x 180 frame (the camera 6 km out on the glide path, 3 degrees down: the horizon near row 83).
SKY_ROWS = (0, 40)           # the sky well above the horizon
HORIZON_SKY_ROWS = (66, 78)  # the sky just above the horizon in clear air
FAR_TERRAIN_ROWS = (86, 100)  # terrain 5-20 km away
NEAR_TERRAIN_ROWS = (150, 180)

failures = []


def check(ok, what):
    print(('ok:   ' if ok else 'FAIL: ') + what)
    if not ok:
        failures.append(what)


def lum(p):
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]


def band(rows, rng):
    return [p for y in range(*rng) for p in rows[y]]


def mean_lum(px):
    return statistics.mean(lum(p) for p in px)


def texture(px):
    return statistics.pstdev([lum(p) for p in px])


def saturation(px):
    return statistics.mean((max(p) - min(p)) / max(max(p), 1) for p in px)


def mean_abs_diff(a, b):
    return statistics.mean(abs(x - y) for ra, rb in zip(a, b) for pa, pb in zip(ra, rb) for x, y in zip(pa, pb))


def read_lines(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def main():
    ig, emulator, plugin, out = sys.argv[1:5]
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    port_file, state_log = os.path.join(out, 'port'), os.path.join(out, 'state.jsonl')
    report_path, frames_dir = os.path.join(out, 'report.jsonl'), os.path.join(out, 'frames')
    ig_out_path = os.path.join(out, 'ig.log')

    ig_cmd = [ig, '--plugin', plugin, '--bind', '127.0.0.1', '--port', '0', '--port-file', port_file,
              '--frames', str(FRAMES), '--idle-timeout', str(EXIT_S), '--deferred-frames', '1',
              '--out', frames_dir, '--state-log', state_log]
    print(' '.join(ig_cmd))
    with open(ig_out_path, 'w') as ig_out:
        proc = subprocess.Popen(ig_cmd, stdout=ig_out, stderr=subprocess.STDOUT, text=True)
        try:
            deadline = time.monotonic() + STARTUP_S
            while not os.path.exists(port_file) and proc.poll() is None and time.monotonic() < deadline:
                time.sleep(0.05)
            if not os.path.exists(port_file):
                proc.kill()
                proc.wait()
                print(open(ig_out_path).read())
                sys.exit(f'FAIL: the IG wrote no port file within {STARTUP_S} s (exit {proc.returncode})')
            port = int(open(port_file).read())
            emu_cmd = [emulator, '--port', str(port), '--frames-per-state', '2', '--sof-timeout', '30',
                       '--report', report_path]
            print(' '.join(emu_cmd))
            emu = subprocess.run(emu_cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=RUN_S)
            print(emu.stdout, end='')
            try:
                ig_status = proc.wait(timeout=EXIT_S)
            except subprocess.TimeoutExpired:
                proc.kill()
                ig_status = f'killed after {EXIT_S} s'
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
    ig_text = open(ig_out_path).read()
    print('--- the IG ---')
    print(ig_text, end='')
    print('--- checks ---')
    check(emu.returncode == 0, f'the emulator got every Start of Frame as the ICD says (exit {emu.returncode})')
    check(ig_status == 0, f'the IG drew {FRAMES} frames and exited 0 (exit {ig_status})')

    # (a) the state log against what the emulator sent and got back.
    report = read_lines(report_path) if os.path.exists(report_path) else []
    sent = [r for r in report if r['frame']]
    bad = [r for r in report if not r['frame']]
    states = read_lines(state_log) if os.path.exists(state_log) else []
    check(len(sent) == FRAMES and len(states) == FRAMES,
          f'{len(sent)} host frames sent and answered, {len(states)} state-log lines (want {FRAMES} each)')
    for r, s in zip(sent, states):
        what = f"host frame {r['host_frame']} ({r['label']})"
        check(s['host_frame'] == r['host_frame'] and s['ig_frame'] == r['sof']['ig_frame'],
              f"{what}: logged as host frame {s['host_frame']}, IG frame {s['ig_frame']}; Start of Frame "
              f"{r['sof']['ig_frame']} echoes host frame {r['sof']['last_host_frame']}")
        check(r['sof']['last_host_frame'] == r['host_frame'] and r['sof']['byte_order'] == r['byte_order'] and
              s['byte_order'] == r['byte_order'] and r['sof']['version'].split('.')[0] == r['version'].split('.')[0],
              f"{what}: CIGI {r['version']} {r['byte_order']}-endian, answered CIGI {r['sof']['version']} "
              f"{r['sof']['byte_order']}-endian after {r['sof']['ms']} ms")
        check(s['time_from_cigi'] and abs(s['utc_posix_s'] - r['utc_posix_s']) < 1e-3,
              f"{what}: time {s['utc']} ({s['utc_posix_s']:.0f} s; sent {r['utc_posix_s']:.0f} s)")
        check(abs(s['visibility_m'] - r['visibility_m']) < 1e-3,
              f"{what}: visibility {s['visibility_m']:.0f} m (sent {r['visibility_m']:.0f} m)")
        layers = s['cloud_layers']
        check(len(layers) == r['cloud_layers'], f"{what}: {len(layers)} cloud layer(s) (sent {r['cloud_layers']})")
        for layer in layers:  # Nimbostratus, 100 %, base 1 500 m MSL, 800 m thick; the datum 432 m, N = 0
            check(layer['type'] == 'overcast' and layer['coverage_oktas'] == 8 and
                  abs(layer['base_m'] - 1068) < 1e-3 and abs(layer['top_m'] - 1868) < 1e-3,
                  f"{what}: the deck {layer['type']} {layer['coverage_oktas']} oktas {layer['base_m']:.0f}-"
                  f"{layer['top_m']:.0f} m above the datum (overcast 8 oktas 1068-1868 m)")
    # The plugin's state hash by part (get_state_hash): the air and the clouds as the packets said, from the
    # frame that brought them (--deferred-frames 1), and the frame part new every frame. The deck's part may
    # move between its two frames (it holds the light the layers are lit with as well).
    air, clouds = {}, {}
    for r, s in zip(sent, states):
        air.setdefault(r['state'], set()).add(s['state_hash']['air'])
        clouds.setdefault(r['state'], set()).add(s['state_hash']['clouds'])
    if len(air) == 4 and all(len(v) == 1 for v in air.values()):
        a = [next(iter(air[k])) for k in range(4)]
        check(a[0] != a[1] and a[2] == a[0] and a[3] == a[0],
              f'the air\'s hash: 50 km {a[0]}, 2 km {a[1]}, 50 km again {a[2]}, {a[3]} (the same air, the same hash)')
    else:
        check(False, f'one air hash per state, the same in its two frames: {air}')
    if len(clouds) == 4:
        none = clouds[0] | clouds[1] | clouds[3]
        check(len(none) == 1 and not (clouds[2] & none),
              f'the clouds\' hash: {sorted(none)} without layers (noon and night), {sorted(clouds[2])} with the deck')
    else:
        check(False, f'a clouds hash per state: {clouds}')
    frame_parts = [s['state_hash']['frame'] for s in states]
    check(len(set(frame_parts)) == len(states), 'the hash\'s frame part new every frame')

    # (b) the pictures: each state's last frame.
    last = {r['state']: s for r, s in zip(sent, states) if r['last_of_state']}
    first = {r['state']: s for r, s in zip(sent, states) if not r['last_of_state']}
    if len(last) == 4 and len(first) == 4:
        img = {k: read_png_rgb(os.path.join(frames_dir, s['png'])) for k, s in last.items()}
        for k in range(4):
            d = mean_abs_diff(read_png_rgb(os.path.join(frames_dir, first[k]['png'])), img[k])
            check(d < 1.0, f'state {k}: its two frames differ by {d:.3f} levels on average (< 1: the change drawn '
                           'from the frame that brought it)')
        clear, hazy, deck, night = img[0], img[1], img[2], img[3]
        noon_sky, night_sky = mean_lum(band(clear, SKY_ROWS)), mean_lum(band(night, SKY_ROWS))
        check(noon_sky > 30 and noon_sky > 10 * (night_sky + 1),
              f'noon sky {noon_sky:.1f} levels, night sky {night_sky:.2f} (fixed exposure EV 15)')

        def contrast(rows):
            far, sky = mean_lum(band(rows, FAR_TERRAIN_ROWS)), mean_lum(band(rows, HORIZON_SKY_ROWS))
            return abs(far - sky) / sky

        c50, c2 = contrast(clear), contrast(hazy)
        t50, t2 = texture(band(clear, FAR_TERRAIN_ROWS)), texture(band(hazy, FAR_TERRAIN_ROWS))
        check(c2 < 0.6 * c50, f'distant terrain against the horizon sky: contrast {c50:.3f} at 50 km, {c2:.3f} at '
                              '2 km (want < 0.6x)')
        check(t2 < 0.5 * t50, f'distant terrain texture (std. dev.): {t50:.2f} levels at 50 km, {t2:.2f} at 2 km '
                              '(want < 0.5x)')
        s_clear, s_deck = saturation(band(clear, SKY_ROWS)), saturation(band(deck, SKY_ROWS))
        g_clear, g_deck = mean_lum(band(clear, NEAR_TERRAIN_ROWS)), mean_lum(band(deck, NEAR_TERRAIN_ROWS))
        print(f'      the sky\'s mean under the deck: {mean_lum(band(deck, SKY_ROWS)):.1f} levels '
              f'(clear blue: {noon_sky:.1f}; a white deck at noon is not darker on screen)')
        check(s_deck < 0.5 * s_clear, f'the deck greys the sky: saturation {s_clear:.3f} clear, {s_deck:.3f} '
                                      'overcast (want < 0.5x)')
        check(g_deck < 0.5 * g_clear, f'the deck darkens the ground in its shadow: {g_clear:.1f} levels clear, '
                                      f'{g_deck:.1f} overcast (want < 0.5x)')
    else:
        check(False, 'a last and a first frame for each of the four states')

    # (c) the bad datagrams: one refusal line each, in order, naming what the emulator broke.
    refusals = [line for line in ig_text.splitlines() if 'refused a ' in line]
    check(len(refusals) == len(bad) == 7, f'{len(refusals)} refusal lines for {len(bad)} bad datagrams (want 7)')
    for r, line in zip(bad, refusals):
        check(f"refused a {r['bytes']}-byte datagram" in line and r['expect'] in line,
              f"{r['label']}: '{line.split(': ', 1)[-1]}'")
    check(ig_text.count('skipped 2 packet(s) not decoded here: id 2 at byte 56 (48 bytes), id 201 at byte 104') == 1,
          'an Entity Control and a user packet in a good message: skipped, said in one line')
    check(ig_text.count('mapping: cloud layer 2: cloud type 11 has no plugin type: not drawn (said once)') == 1,
          'the user-defined cloud layer, kept for four frames: said once')
    for packet in ('IG Control', 'Celestial Sphere Control', 'Atmosphere Control', 'Environmental Region Control',
                   'Weather Control'):
        n = sum(1 for line in ig_text.splitlines() if line.startswith(f'atmo-cigi-ig: {packet}: ') and 'not drawn' in line)
        check(n == 1, f'{packet}: what is not drawn said {n} time(s) (want once)')
    check(f'{FRAMES} frame(s) drawn, 7 datagram(s) refused' in ig_text, 'the IG went on to the end')

    if failures:
        sys.exit(f'FAIL: {len(failures)} check(s)')
    print('PASS')


if __name__ == '__main__':
    main()
