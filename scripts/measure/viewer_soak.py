#!/usr/bin/env python3
"""Soak test of rast-viewer: many frames with an orbiting camera and every mode
key toggled in turn, memory sampled along the way (docs/viewer.md).

  python3 scripts/measure/viewer_soak.py --viewer build/openmp/rast-viewer [--frames 100000]
      [--size 640x360] [--sample-every 5000] [--scene SCENE] [--json F] [--max-growth-mib 16]
      [-- extra viewer args]

Writes an input script (orbit drag every 10 frames; every --key-every (500) frames the next
of the keys 2, 3, 1, C, M, L, T, P, O; print-memory every --sample-every
frames), runs the viewer with it, and prints one line per memory sample and a
summary: RSS and (GPU builds) device memory at the first sample and at the end.
The first sample is taken after one full cycle of the keys, so every buffer a
mode needs has been allocated once; from there on memory must stay flat.

Exit status: the viewer's when it failed, 1 when resident memory or device
memory grew by more than --max-growth-mib between the first and last sample,
else 0. Run it under a display (DISPLAY set, e.g. xvfb-run -a).
"""
import argparse
import json
import re
import subprocess
import sys
import tempfile
import time

KEYS = ["2", "3", "1", "C", "M", "L", "T", "P", "O"]
MEM = re.compile(r"memory: frame (\d+) rss ([\d.]+) MiB renderer ([\d.]+) MiB(?: device-used ([\d.]+) MiB of ([\d.]+) MiB)?")


def make_script(frames, sample_every, key_every):
    lines = ["# rast-viewer soak (scripts/measure/viewer_soak.py)"]
    cycle = key_every * len(KEYS)  # frames for one pass over every key
    warm = min(cycle, frames // 2)
    done, k = 0, 0
    next_sample = warm
    while done < frames:
        step = min(10, frames - done)
        lines.append("drag left 6 0")  # orbit: 6 px to the right every 10 frames
        lines.append(f"frame {step}")
        done += step
        if done % key_every == 0:
            lines.append(f"key {KEYS[k % len(KEYS)]}")
            k += 1
        if done >= next_sample:
            lines.append("print-memory")
            next_sample += sample_every
    lines.append("print-memory")
    lines.append("quit")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--viewer", required=True)
    ap.add_argument("--frames", type=int, default=100000)
    ap.add_argument("--size", default="640x360")
    ap.add_argument("--sample-every", type=int, default=5000)
    ap.add_argument("--key-every", type=int, default=500, help="frames between mode keys (a multiple of 10)")
    ap.add_argument("--scene", default=None)
    ap.add_argument("--json", default=None)
    ap.add_argument("--max-growth-mib", type=float, default=16.0)
    ap.add_argument("extra", nargs="*", help="more rast-viewer arguments (after --)")
    a = ap.parse_args()

    with tempfile.NamedTemporaryFile("w", suffix=".script", delete=False) as f:
        f.write(make_script(a.frames, a.sample_every, a.key_every))
        script = f.name
    cmd = [a.viewer, "--size", a.size, "--no-vsync", "--script", script] + ([a.scene] if a.scene else []) + a.extra
    t0 = time.time()
    r = subprocess.run(cmd, capture_output=True, text=True)
    secs = time.time() - t0
    samples = []
    for line in r.stdout.splitlines():
        m = MEM.search(line)
        if m:
            samples.append({"frame": int(m[1]), "rss_mib": float(m[2]), "renderer_mib": float(m[3]),
                            "device_used_mib": float(m[4]) if m[4] else None,
                            "device_total_mib": float(m[5]) if m[5] else None})
            print(line)
    summary = [l for l in r.stdout.splitlines() if l.startswith("rast-viewer: ") and " frames at " in l]
    errors = [l for l in r.stderr.splitlines() if "error" in l.lower()]
    for l in summary:
        print(l)
    result = {"command": cmd, "rc": r.returncode, "seconds": round(secs, 1), "frames": a.frames,
              "samples": samples, "summary": summary[-1] if summary else None, "stderr_errors": errors}
    status = 0
    if r.returncode != 0 or len(samples) < 2:
        print(f"viewer_soak: viewer failed (rc {r.returncode}, {len(samples)} memory samples): "
              f"{r.stderr.strip()[-500:]}", file=sys.stderr)
        status = r.returncode or 1
    else:
        first, last = samples[0], samples[-1]
        growth = {"rss_mib": last["rss_mib"] - first["rss_mib"],
                  "renderer_mib": last["renderer_mib"] - first["renderer_mib"]}
        if first["device_used_mib"] is not None:
            growth["device_used_mib"] = last["device_used_mib"] - first["device_used_mib"]
        result["growth"] = growth
        print(f"viewer_soak: {a.frames} frames in {secs:.1f} s; from frame {first['frame']} to {last['frame']}: "
              + ", ".join(f"{k} {first[k]:.1f} -> {last[k]:.1f}" for k in growth) + f"; errors on stderr: {len(errors)}")
        if any(v > a.max_growth_mib for v in growth.values()) or errors:
            print(f"viewer_soak: FAIL: memory grew by more than {a.max_growth_mib} MiB or errors were printed",
                  file=sys.stderr)
            status = 1
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=1)
    return status


if __name__ == "__main__":
    sys.exit(main())
