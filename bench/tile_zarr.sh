#!/usr/bin/env bash
# Zarr store against the NetCDF stream, in one run on one machine: throughput per process
# (float32 values per second, the uncompressed size, as the NetCDF figure), two parts at once
# against one part alone (one rayon thread each), and peak RSS at two mosaic sizes.
# Usage: bench/tile_zarr.sh [EXTENT_M (default 40)] [SCRATCH (default /tmp)]
set -euo pipefail
B="${CARGO_TARGET_DIR:-target}/release/cellsurf"
E="${1:-40}"
D="${2:-/tmp}/cellsurf-bench-zarr-$$"
mkdir -p "$D"
trap 'rm -rf "$D"' EXIT
T=(tile --generate --nx 64 --ny 32 --layers 20 --steps 1500 --activity 0.004 --seeds 1,2,3
   --choose patches --blend 12 --json)
mbs() { python3 -c 'import json,sys; d=json.load(sys.stdin); print(round(d["bytes"]/1e6/d["elapsed_s"],1), round(d["elapsed_s"],2))'; }
rss() { grep "Maximum resident" "$1" | awk '{print $6/1024 " MB"}'; }
echo "machine: $(nproc) cores, $(uname -m); extent ${E} x ${E} m at 5 mm"
for ext in "$E" "$((E / 2))"; do
  /usr/bin/time -v "$B" "${T[@]}" --extent "${ext}x${ext}" --out "$D/m.nc" 2>"$D/t1" | { printf "netcdf  %3s m: MB/s, s = " "$ext"; mbs; }
  echo "  peak RSS $(rss "$D/t1")"
  /usr/bin/time -v "$B" "${T[@]}" --extent "${ext}x${ext}" --out "$D/m.zarr" 2>"$D/t2" | { printf "zarr    %3s m: MB/s, s = " "$ext"; mbs; }
  echo "  peak RSS $(rss "$D/t2"), store $(du -sm "$D/m.zarr" | cut -f1) MB on disk"
  rm -rf "$D/m.nc" "$D/m.zarr"
done
# one part of two alone, one thread, then both parts at once, one thread each; wall and CPU
# seconds (the cores are shared with other work: CPU seconds show whether the parts slow each
# other down, wall seconds whether the machine had the second core free)
tv() { /usr/bin/time -f "%e %U %S" -o "$1" "${@:2}"; }
RAYON_NUM_THREADS=1 tv "$D/t0" "$B" "${T[@]}" --extent "${E}x${E}" --out "$D/p.zarr" --part 0/2 >"$D/one"
rm -rf "$D/p.zarr"
RAYON_NUM_THREADS=1 tv "$D/ta" "$B" "${T[@]}" --extent "${E}x${E}" --out "$D/p.zarr" --part 0/2 >"$D/a" &
RAYON_NUM_THREADS=1 tv "$D/tb" "$B" "${T[@]}" --extent "${E}x${E}" --out "$D/p.zarr" --part 1/2 >"$D/b" &
wait
python3 - "$D" <<'P'
import json, sys
d = sys.argv[1]
def load(n, t):
    j = json.load(open(f"{d}/{n}"))
    wall, user, sys_ = map(float, open(f"{d}/{t}").read().split()[-3:])
    return j, wall, user + sys_
one, w1, c1 = load("one", "t0")
a, wa, ca = load("a", "ta")
b, wb, cb = load("b", "tb")
r1 = one["bytes"] / 1e6 / one["elapsed_s"]
both = (a["bytes"] + b["bytes"]) / 1e6 / max(a["elapsed_s"], b["elapsed_s"])
print(f"part 0/2 alone, 1 thread: {r1:.1f} MB/s ({one['elapsed_s']:.2f} s writing; process {w1:.2f} s wall, {c1:.2f} s CPU)")
print(f"parts 0/2 and 1/2 at once, 1 thread each: {both:.1f} MB/s together = {both / r1:.2f} x one part alone (ideal 2)")
print(f"  processes {wa:.2f} and {wb:.2f} s wall, {ca:.2f} and {cb:.2f} s CPU: CPU per part {max(ca, cb) / c1:.2f} x alone")
P
"$B" tile --check "$D/p.zarr"
uptime
