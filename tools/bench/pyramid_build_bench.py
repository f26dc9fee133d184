#!/usr/bin/env python3
"""Pyramid build benchmark: terrain-build against GDAL's COG build on the same inputs.

For every real DEM in ../shared/data, two 8-bit grey PNGs without georeference made from
them (gdal_translate -ot Byte -scale -outsize 1200 1200 -of PNG), and a 16,385² float32
procedural DEM written as a tiled GeoTIFF, runs (one at a time, same machine, same thread count)
  terrain-build INPUT -o PYRAMID --threads 2                         (zstd level 3)
  terrain-build INPUT -o PYRAMID --threads 2 --compression-level 0   (the same, uncompressed)
  terrain-build INPUT -o PYRAMID --threads 2 --max-error-m 1  (lossy, Yusov §4's quantizer)
  terrain-inspect PYRAMID --verify --source INPUT --json      (its bounds against the source)
  gdal_translate -of COG -co COMPRESS=DEFLATE -co PREDICTOR=YES -co NUM_THREADS=2 INPUT OUT.tif
  gdal_translate -of COG -co COMPRESS=LERC -co MAX_Z_ERROR=1 -co NUM_THREADS=2 INPUT OUT.tif
(the COG driver adds overviews, OVERVIEWS=AUTO, to a raster larger than its 512² blocks; the
predictor is 2 for integer and 3 for float samples), records wall seconds and peak RSS of
each (os.wait4) and their sizes, the lossy pyramid's ratio to the raw float32 raster (and to
16-bit samples, Yusov's reference) and whether its bounds held, then writes
OUT_DIR/pyramid-build-bench.json and .md. Rerun with:
  tools/bench/pyramid_build_bench.py --build build --out out/bench
"""
import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
from pathlib import Path

from measured_run import run  # (wall s, CPU s, peak RSS bytes, stdout)

REPO = Path(__file__).resolve().parents[2]

REAL_DEMS = [
    # (file, extra terrain-build flags)
    ("puget_sound_1k.png", ["--vertical-scale", "0.1", "--spacing", "160"]),
    ("puget_sound_4k_8bit.jpg", ["--vertical-scale", "25.7", "--spacing", "40"]),
    ("srtm3_n46w122_rainier.tif", []),
    ("srtm/N57E011.hgt", []),
    ("kilauea_utm5n_30m.nc", []),
    ("etopo20_global.nc", []),
    ("luxembourg_elev_30s.tif", []),
]

# 8-bit grey PNGs without georeference made from real DEMs (issue 52: such a DEM's pyramid was
# larger than its COG), as a user's `gdal_translate -ot Byte -scale -of PNG` makes them:
# (name, source in the shared data, side).
GREY_DEMS = [
    ("rainier_8bit_1200.png", "srtm3_n46w122_rainier.tif", 1200),
    ("N57E011_8bit_1200.png", "srtm/N57E011.hgt", 1200),
]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=str(REPO / "build"), help="build folder")
    parser.add_argument("--out", default=str(REPO / "out" / "bench"), help="results folder")
    parser.add_argument("--shared", default=str(REPO.parent / "shared" / "data"), help="real DEMs")
    parser.add_argument("--size", type=int, default=16385, help="procedural DEM side")
    parser.add_argument("--scratch", default="/tmp/terrain-bench", help="big temporary files")
    parser.add_argument("--max-error-m", type=float, default=1.0,
                        help="δ of the lossy build and LERC's MAX_Z_ERROR")
    parser.add_argument("--compression-level", type=int, default=3,
                        help="terrain-build --compression-level of the compressed and lossy "
                             "builds")
    parser.add_argument("--no-procedural", action="store_true",
                        help="the shared DEMs only, without the procedural DEM")
    parser.add_argument("--no-verify", action="store_true",
                        help="skip terrain-inspect --verify --source of the lossy pyramids")
    args = parser.parse_args()

    build = Path(args.build)
    terrain_build = build / "tools" / "terrain-build" / "terrain-build"
    terrain_generate = build / "tools" / "terrain-generate" / "terrain-generate"
    terrain_inspect = build / "tools" / "terrain-inspect" / "terrain-inspect"
    if shutil.which("gdal_translate") is None:
        sys.exit("gdal_translate not found: scripts/setup.sh installs gdal-bin")
    out, scratch = Path(args.out), Path(args.scratch)
    out.mkdir(parents=True, exist_ok=True)
    scratch.mkdir(parents=True, exist_ok=True)

    inputs = [(Path(args.shared) / name, flags) for name, flags in REAL_DEMS]
    for name, source, side in GREY_DEMS:
        grey = scratch / name
        if not grey.exists():
            # No .aux.xml beside it: the PNG carries no georeference and no no-data value.
            run(["gdal_translate", "-q", "--config", "GDAL_PAM_ENABLED", "NO", "-ot", "Byte",
                 "-scale", "-a_nodata", "none", "-outsize", str(side), str(side), "-of", "PNG",
                 Path(args.shared) / source, grey], scratch / "gdal.log")
        inputs.append((grey, []))
    big = scratch / f"procedural-{args.size}.tif"
    if not args.no_procedural and not big.exists():
        print(f"writing {big} (float32, tiled 256², uncompressed) ...", flush=True)
        run([terrain_generate, "--size", str(args.size), "--compression", "none", "-o", big],
            scratch / "generate.log")
    if not args.no_procedural:
        inputs.append((big, []))
    level = ["--compression-level", str(args.compression_level)]

    rows = []
    for path, flags in inputs:
        pyramid = scratch / (path.stem + ".pyramid")
        cog = scratch / (path.stem + ".cog.tif")
        shutil.rmtree(pyramid, ignore_errors=True)
        ours_s, _, ours_rss, ours_json = run(
            [terrain_build, path, "-o", pyramid, "--threads", "2", *level, "--json", "--quiet",
             *flags],
            scratch / "terrain-build.log")
        summary = json.loads(ours_json)
        shutil.rmtree(pyramid, ignore_errors=True)
        raw_s, _, _, raw_json = run(
            [terrain_build, path, "-o", pyramid, "--threads", "2", "--compression-level", "0", "--json",
             "--quiet", *flags], scratch / "terrain-build.log")
        raw_bytes = json.loads(raw_json)["bytes"]
        shutil.rmtree(pyramid, ignore_errors=True)
        delta = str(args.max_error_m)
        lossy_s, _, _, lossy_json = run(
            [terrain_build, path, "-o", pyramid, "--threads", "2", "--max-error-m", delta,
             *level, "--json", "--quiet", *flags], scratch / "terrain-build.log")
        lossy = json.loads(lossy_json)
        check = None
        if not args.no_verify:
            # terrain-inspect exits 1 when it finds a problem: recorded, not fatal here.
            with open(scratch / "terrain-inspect.log", "w") as err:
                inspected = subprocess.run(
                    [terrain_inspect, pyramid, "--verify", "--source", path, "--json", *flags],
                    stdout=subprocess.PIPE, stderr=err, text=True)
            report = json.loads(inspected.stdout)
            source = report.get("sourceCheck") or {}
            check = {"ok": report.get("ok"), "violations": source.get("violations"),
                     "storedViolations": source.get("storedViolations"),
                     "largestStoredDifferencePerLevelM": source.get("largestStoredDifferencePerLevelM")}
        shutil.rmtree(pyramid, ignore_errors=True)
        gdal_s, _, gdal_rss, _ = run(
            ["gdal_translate", "-q", "-of", "COG", "-co", "COMPRESS=DEFLATE", "-co", "PREDICTOR=YES",
             "-co", "NUM_THREADS=2", path, cog], scratch / "gdal.log")
        cog_bytes = cog.stat().st_size
        cog.unlink(missing_ok=True)
        lerc_s, _, _, _ = run(
            ["gdal_translate", "-q", "-of", "COG", "-co", "COMPRESS=LERC", "-co", f"MAX_Z_ERROR={args.max_error_m:g}",
             "-co", "NUM_THREADS=2", path, cog], scratch / "gdal.log")
        lerc_bytes = cog.stat().st_size
        samples = summary["raster"]["width"] * summary["raster"]["height"]
        rows.append({
            "input": path.name, "width": summary["raster"]["width"], "height": summary["raster"]["height"],
            "levels": summary["levels"], "patches": summary["patches"],
            "terrainBuildSeconds": round(ours_s, 3), "terrainBuildPeakRssMiB": round(ours_rss / 2**20, 1),
            "pyramidMiB": round(summary["bytes"] / 2**20, 2),
            "uncompressedBuildSeconds": round(raw_s, 3), "uncompressedPyramidMiB": round(raw_bytes / 2**20, 2),
            "gdalCogSeconds": round(gdal_s, 3), "gdalCogPeakRssMiB": round(gdal_rss / 2**20, 1),
            "cogMiB": round(cog_bytes / 2**20, 2),
            "lercCogSeconds": round(lerc_s, 3), "lercCogMiB": round(lerc_bytes / 2**20, 2),
            "pyramidToCog": round(summary["bytes"] / cog_bytes, 2),
            "maxErrorM": args.max_error_m,
            "lossyBuildSeconds": round(lossy_s, 3), "lossyPyramidMiB": round(lossy["bytes"] / 2**20, 2),
            "lossyToLerc": round(lossy["bytes"] / lerc_bytes, 2),
            "float32ToLossy": round(4 * samples / lossy["bytes"], 1),
            "int16ToLossy": round(2 * samples / lossy["bytes"], 1),
            "lossyCheck": check,
        })
        print(json.dumps(rows[-1]), flush=True)
        cog.unlink(missing_ok=True)

    result = {"machine": {"cpus": os.cpu_count(), "platform": platform.platform()},
              "command": " ".join(sys.argv), "rows": rows}
    (out / "pyramid-build-bench.json").write_text(json.dumps(result, indent=2) + "\n")
    lines = ["| input | size | levels | patches | terrain-build s | RSS MiB | pyramid MiB | "
             "uncompressed s | MiB | gdal COG s | RSS MiB | COG MiB | pyramid / COG | LERC s | MiB | "
             "lossy s | MiB | lossy / LERC | float32 / lossy | bounds held |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['input']} | {r['width']}×{r['height']} | {r['levels']} | {r['patches']} | "
                     f"{r['terrainBuildSeconds']} | {r['terrainBuildPeakRssMiB']} | {r['pyramidMiB']} | "
                     f"{r['uncompressedBuildSeconds']} | {r['uncompressedPyramidMiB']} | "
                     f"{r['gdalCogSeconds']} | {r['gdalCogPeakRssMiB']} | {r['cogMiB']} | "
                     f"{r['pyramidToCog']} | {r['lercCogSeconds']} | {r['lercCogMiB']} | "
                     f"{r['lossyBuildSeconds']} | "
                     f"{r['lossyPyramidMiB']} | {r['lossyToLerc']} | {r['float32ToLossy']} | "
                     f"{'not checked' if r['lossyCheck'] is None else 'yes' if r['lossyCheck']['ok'] else 'NO'} |")
    (out / "pyramid-build-bench.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
