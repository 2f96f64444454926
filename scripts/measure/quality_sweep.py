#!/usr/bin/env python3
"""Image quality against a ground truth, and what it costs: for a fixed set of
scenes and cameras, render the reference once (`rast render --reference`,
16x16 stratified supersampling), then every configuration

    aa in none ssaa2 ssaa4 msaa2 msaa4 msaa8  x  filter in nearest bilinear trilinear
    x  raster method (auto; every method with --all-methods)

(`--filters` also takes auto, the glTF samplers' own filters, and anisoN:
auto with anisotropic filtering of at most N taps, `--anisotropy N`; the
textured models render with the glTF shading, whose samplers those are)

and measure its median frame time (`rast bench --json`, same flags) and its
error against the reference (`rast compare --json`, edges from the reference
camera's primitive ids). One CSV row per configuration:

    scene, aa, filter, method, ms, rmse_linear, psnr, ssim, frac_gt1, frac_gt8, edge_rmse,
    reference, resolved_method, size, ms_min

Configurations whose flags this rast rejects (not implemented yet) are skipped
with a printed note: each flag value is probed once on a tiny render first.
`aa=none` runs without any --aa flag when rast has no --aa option (that is
what it renders then). Without a working --reference the error columns stay
empty, unless --allow-fake-reference is given: then the bilinear no-AA render
stands in as the reference, and every row says so in the `reference` column
("FAKE:bilinear-noaa") -- for exercising the pipeline only, never for results.

Python standard library only. Charts: scripts/plot/plot_quality.py.

  python3 scripts/measure/quality_sweep.py --rast build/openmp/rast --out docs/data/quality_openmp.csv
"""
import argparse
import csv
import json
import math
import os
import shlex
import subprocess

from progress import Progress
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
AA_MODES = ["none", "ssaa2", "ssaa4", "msaa2", "msaa4", "msaa8"]
FILTERS = ["nearest", "bilinear", "trilinear"]


def filter_flags(name):
    """rast flags of a --filters entry: a filter name, or anisoN (--filter
    auto --anisotropy N)."""
    if name.startswith("aniso"):
        return ["--filter", "auto", "--anisotropy", name[len("aniso"):]]
    return ["--filter", name]
OBLIQUE = ["--eye", "0.3,-1.6,2.2", "--target", "0,0,0"]
GRAZING = ["--eye", "0,0.3,1.6", "--target", "0,0,-1"]
FIELDS = ["scene", "aa", "filter", "method", "ms", "rmse_linear", "psnr", "ssim", "frac_gt1", "frac_gt8",
          "edge_rmse", "reference", "resolved_method", "size", "ms_min"]
FAKE_LABEL = "FAKE:bilinear-noaa"


def scene_list(shared):
    """(label, scene argument, camera flags): textured models at their auto
    camera, then edge-heavy built-in scenes."""
    scenes = []
    models = os.path.join(shared, "models")
    for m in ["duck.glb", "checkerboard.glb"]:
        p = os.path.join(models, m)
        if os.path.exists(p):
            scenes.append((m, p, []))
    p = os.path.join(models, "checkerboard.glb")
    if os.path.exists(p):  # the board at a grazing angle: where anisotropic filtering matters
        scenes.append(("checkerboard.glb@grazing", p, GRAZING))
    scenes.append(("builtin:default", "builtin:default", []))
    scenes.append(("builtin:slivers", "builtin:slivers", []))
    scenes.append(("builtin:grid?n=64@oblique", "builtin:grid?n=64", OBLIQUE))
    return scenes


class Rast:
    def __init__(self, exe, timeout):
        self.exe = exe
        self.timeout = timeout
        self.env = dict(os.environ)
        self.env.setdefault("OMP_PROC_BIND", "false")  # else Kokkos prints OpenMP advice

    def run(self, args):
        """(ok, stdout, one-line reason)."""
        cmd = [self.exe] + args
        try:
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=self.timeout, env=self.env)
        except subprocess.TimeoutExpired:
            return False, "", f"timed out after {self.timeout} s"
        if r.returncode != 0:
            lines = [l for l in r.stderr.strip().splitlines() if l.strip()]
            why = lines[-1] if lines else ""
            if r.returncode < 0:
                why = f"killed by signal {-r.returncode} {why}".strip()
            return False, r.stdout, why or f"exit status {r.returncode}"
        return True, r.stdout, ""


def read_json(path):
    with open(path) as f:
        return json.load(f)


def fmt(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return "inf" if math.isinf(v) else f"{v:.6g}"
    return str(v)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rast", required=True, help="the rast executable")
    ap.add_argument("--out", required=True, help="CSV file to write")
    ap.add_argument("--size", default="640x360", help="image size WxH (default 640x360: the reference is 256 spp)")
    ap.add_argument("--frames", type=int, default=20, help="timed frames per bench (median reported)")
    ap.add_argument("--warmup", type=int, default=3)
    ap.add_argument("--shared", default=os.path.join(HERE, "..", "..", "..", "shared"))
    ap.add_argument("--all-methods", action="store_true", help="every raster method of `rast info`, not only auto")
    ap.add_argument("--aa", default=",".join(AA_MODES), help="comma-separated AA modes to try")
    ap.add_argument("--filters", default=",".join(FILTERS), help="comma-separated texture filters to try")
    ap.add_argument("--scenes", default="", help="comma-separated scene labels to keep (default: all)")
    ap.add_argument("--reference-args", default="--reference", help="flags that make the reference render")
    ap.add_argument("--allow-fake-reference", action="store_true",
                    help="when --reference is rejected, use the bilinear no-AA render as a stand-in reference "
                         "(labelled FAKE in the CSV; for testing the pipeline only)")
    ap.add_argument("--keep", default="", help="keep the rendered images in this folder")
    ap.add_argument("--quick", action="store_true", help="160x90, 3 frames, 1 warm-up (smoke run)")
    ap.add_argument("--timeout", type=float, default=1800, help="seconds per rast run")
    a = ap.parse_args()
    if a.quick:
        a.size, a.frames, a.warmup = "160x90", 3, 1

    rast = Rast(os.path.abspath(a.rast), a.timeout)
    ok, info, why = rast.run(["info"])
    if not ok:
        sys.exit(f"quality_sweep: `{a.rast} info` failed: {why}")
    methods = ["auto"]
    if a.all_methods:
        for line in info.splitlines():
            if line.startswith("raster methods:"):
                methods += [m for m in line.split(":", 1)[1].split() if m != "auto"]
    aa_modes = [x for x in a.aa.split(",") if x]
    filters = [x for x in a.filters.split(",") if x]
    scenes = scene_list(a.shared)
    if a.scenes:
        keep = set(a.scenes.split(","))
        scenes = [s for s in scenes if s[0] in keep]
    work = a.keep or tempfile.mkdtemp(prefix="quality_sweep_")
    os.makedirs(work, exist_ok=True)

    # Probe every flag value once on a tiny render: rejected values are skipped.
    notes = []
    probe_png = os.path.join(work, "probe.png")

    def probe(flags):
        ok, _, why = rast.run(["render", "builtin:default", "--size", "16x16", "-o", probe_png] + flags)
        return ok, why

    aa_flags = {}  # mode -> flags, or None when unsupported
    for m in aa_modes:
        ok, why = probe(["--aa", m])
        if ok:
            aa_flags[m] = ["--aa", m]
        elif m == "none":
            aa_flags[m] = []
            notes.append(f"note: --aa none rejected ({why}); aa=none runs without --aa")
        else:
            aa_flags[m] = None
            notes.append(f"note: skipping aa={m}: {why}")
    filter_ok = {}
    for f in filters:
        ok, why = probe(filter_flags(f))
        filter_ok[f] = ok
        if not ok:
            notes.append(f"note: skipping filter={f}: {why}")
    ref_args = shlex.split(a.reference_args)
    ref_ok, ref_why = probe(ref_args)
    if not ref_ok:
        if a.allow_fake_reference:
            notes.append(f"note: `{a.reference_args}` rejected ({ref_why}); using the bilinear no-AA render as a "
                         f"FAKE reference (rows say {FAKE_LABEL})")
        else:
            notes.append(f"note: `{a.reference_args}` rejected ({ref_why}); no reference, error columns left empty "
                         "(--allow-fake-reference substitutes the bilinear no-AA render)")
    for n in notes:
        print(n, flush=True)

    rows, skipped = [], 0
    base = ["--size", a.size]
    progress = Progress("quality_sweep: render", len(scenes) * len(aa_modes) * len(filters) * len(methods))
    for label, scene, cam in scenes:
        print(f"== {label} {' '.join(cam)}", flush=True)
        tag = "".join(c if c.isalnum() else "_" for c in label)
        sflags = [scene] + cam + base
        # Primitive ids of the reference view (pixel centres, no AA): the edge mask.
        ids = os.path.join(work, f"{tag}_ids.bin")
        ok, _, why = rast.run(["render"] + sflags + ["-o", os.path.join(work, f"{tag}_plain.png"),
                                                    "--aov", f"primid={ids}"])
        if not ok:
            print(f"  note: skipping scene {label}: {why}", flush=True)
            skipped += 1
            continue
        ref_png, ref_label = os.path.join(work, f"{tag}_reference.png"), None
        if ref_ok:
            ok, _, why = rast.run(["render"] + sflags + ref_args + ["-o", ref_png])
            if ok:
                ref_label = "reference"
            else:
                print(f"  note: reference render failed: {why}", flush=True)
        if ref_label is None and a.allow_fake_reference:
            ok, _, why = rast.run(["render"] + sflags + ["--filter", "bilinear", "-o", ref_png])
            if ok:
                ref_label = FAKE_LABEL
                print(f"  note: FAKE reference (bilinear, no AA) for {label}", flush=True)
            else:
                print(f"  note: fake reference render failed: {why}", flush=True)

        for aa in aa_modes:
            for flt in filters:
                for meth in methods:
                    name = f"aa={aa} filter={flt} method={meth}"
                    progress.step(f"{label} {name}")
                    if aa_flags[aa] is None or not filter_ok[flt]:
                        skipped += 1
                        continue  # noted once above
                    cfg = aa_flags[aa] + filter_flags(flt) + ["--raster", meth]
                    ctag = f"{tag}_{aa}_{flt}_{meth}"
                    png = os.path.join(work, ctag + ".png")
                    ok, _, why = rast.run(["render"] + sflags + cfg + ["-o", png])
                    if not ok:
                        print(f"  note: skipping {name}: render: {why}", flush=True)
                        skipped += 1
                        continue
                    bj = os.path.join(work, ctag + "_bench.json")
                    ok, _, why = rast.run(["bench"] + sflags + cfg + ["--frames", str(a.frames), "--warmup",
                                                                      str(a.warmup), "--json", bj])
                    if not ok:
                        print(f"  note: skipping {name}: bench: {why}", flush=True)
                        skipped += 1
                        continue
                    b = read_json(bj)[0]
                    row = {"scene": label, "aa": aa, "filter": flt, "method": meth, "ms": b["total_median_ms"],
                           "reference": ref_label or "", "resolved_method": b.get("method", ""), "size": a.size,
                           "ms_min": b.get("total_min_ms")}
                    if ref_label:
                        cj = os.path.join(work, ctag + "_compare.json")
                        ok, _, why = rast.run(["compare", ref_png, png, "--ids", ids, "--json", cj])
                        if not ok:
                            print(f"  note: {name}: compare failed: {why}", flush=True)
                        else:
                            c = read_json(cj)
                            psnr = c["psnr_linear_db"]
                            row.update(rmse_linear=c["rmse_linear"], psnr=math.inf if psnr is None else psnr,
                                       ssim=c["ssim"], frac_gt1=c["frac_gt1"], frac_gt8=c["frac_gt8"],
                                       edge_rmse=c["edge_rmse_linear"])
                    rows.append(row)
                    print(f"  {aa:6s} {flt:9s} {meth:9s} {b['total_median_ms']:9.3f} ms"
                          + (f"  rmse {fmt(row.get('rmse_linear'))}  ssim {fmt(row.get('ssim'))}"
                             f"  edge_rmse {fmt(row.get('edge_rmse'))}" if "ssim" in row else "  (no reference)")
                          + (f"  [{ref_label}]" if ref_label == FAKE_LABEL else ""), flush=True)

    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    progress.close()
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow({k: fmt(r.get(k)) for k in FIELDS})
    print(f"quality_sweep: wrote {a.out}: {len(rows)} configurations measured, {skipped} skipped"
          + (f"; images in {work}" if a.keep else ""))
    if not a.keep:
        for n in os.listdir(work):
            os.remove(os.path.join(work, n))
        os.rmdir(work)
    return 0


if __name__ == "__main__":
    sys.exit(main())
