#!/usr/bin/env bash
# Rippled-dune mosaic streaming rate: the 20 m x 20 m surface at 5 mm (4032 x 4000 bins, fBm
# dunes H = 0.6) written as .npy, `rows_per_s` x width, median of REPEATS runs, wall time and
# peak RSS from /usr/bin/time. With BASE=path/to/another/cellsurf the two binaries run
# alternately in the same script (ratios like for like on a shared machine).
#   bash bench/rippled_dunes.sh [REPEATS]        (BASE=... optional)
# The 1 km x 1 km surface at 1 cm (40 GB on disk):
#   /usr/bin/time -v target/release/cellsurf tile --generate --nx 100 --ny 100 --bin-size 0.01 \
#     --extent 1000x1000 --dunes --out km --format npy --json
set -euo pipefail
cd "$(dirname "$0")/.."
REPEATS=${1:-3}
cargo build --release --quiet
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); load average $(cut -d' ' -f1-3 /proc/loadavg)"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
python3 - "$REPEATS" "$out" "${BASE:-}" <<'PY'
import json, statistics, subprocess, sys
repeats, out, base = int(sys.argv[1]), sys.argv[2], sys.argv[3]
bins = {"this": "target/release/cellsurf"}
if base:
    bins["base"] = base
cmd = ["tile", "--generate", "--nx", "64", "--ny", "32", "--layers", "20", "--steps", "1500",
       "--activity", "0.004", "--extent", "20x20", "--dunes", "--hurst", "0.6",
       "--out", f"{out}/d", "--format", "npy", "--json"]
runs = {k: [] for k in bins}
for _ in range(repeats):
    for k, b in bins.items():
        r = subprocess.run(["/usr/bin/time", "-f", "%e %M", b] + cmd, check=True,
                           capture_output=True, text=True)
        d = json.loads(r.stdout)
        wall, rss = r.stderr.split()[-2:]
        runs[k].append((d["rows_per_s"] * d["width"] / 1e6, float(wall), int(rss) / 1024))
med = {k: statistics.median(v[0] for v in r) for k, r in runs.items()}
for k, r in runs.items():
    print(f"{k}: {med[k]:.2f} Mbins/s (median), wall {statistics.median(v[1] for v in r):.2f} s, "
          f"peak RSS {max(v[2] for v in r):.1f} MB")
if base:
    print(f"ratio this/base: {med['this'] / med['base']:.2f}")
print(f"goal >= 15 Mbins/s: {'met' if med['this'] >= 15 else 'not met'}")
PY
