#!/usr/bin/env bash
# Wind ripples against the numpy peer with np.bincount (variant `fast`), and 1 against 2
# threads, in one run on one machine: the notebook's defaults (524,288 particles, 256 x 256
# bins), 128 steps. The peer's time is its loop (its TIME line); cellsurf's is the whole
# process (wall, best of REPEATS) with --threads 1 and --threads 2, whose height fields must be
# the same bytes.
#   bash bench/windripples_threads.sh [STEPS] [REPEATS]
#   PEER=path/to/wind_ripples_numpy.py bash bench/windripples_threads.sh
set -euo pipefail
cd "$(dirname "$0")/.."
STEPS=${1:-128}
REPEATS=${2:-3}
PEER=${PEER:-../shared/peers/wind_ripples_numpy.py}
python3 -c "import numpy" 2>/dev/null || python3 -m pip install --quiet numpy
cargo build --release --quiet
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); load average $(cut -d' ' -f1-3 /proc/loadavg)"
peer=$(python3 "$PEER" "$STEPS" --variant fast | grep '^TIME')
echo "peer (numpy, bincount): $peer"
python3 - target/release/cellsurf "$STEPS" "$REPEATS" "$peer" "$tmp" <<'PY'
import re, subprocess, sys, time
bin, steps, repeats, peer, tmp = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5]
peer_s = float(re.search(r"seconds=([0-9.]+)", peer).group(1))
best, data = {}, {}
for _ in range(repeats):
    for t in (1, 2):
        out = f"{tmp}/h{t}.npy"
        t0 = time.perf_counter()
        subprocess.run([bin, "wind-ripples", "--steps", steps, "--threads", str(t), "--quiet",
                        "--npy", out], check=True)
        dt = time.perf_counter() - t0
        best[t] = min(best.get(t, dt), dt)
        data[t] = open(out, "rb").read()
same = data[1] == data[2]
print(f"cellsurf, whole process, best of {repeats}: 1 thread {best[1]:.3f} s, 2 threads {best[2]:.3f} s")
print(f"  vs the peer's loop {peer_s:.3f} s: x{peer_s / best[1]:.1f} (1 thread), x{peer_s / best[2]:.1f} (2 threads); goal x10: "
      f"{'met' if peer_s / best[2] >= 10 else 'not met'}")
print(f"  2 threads against 1: x{best[1] / best[2]:.2f}; goal x1.6: {'met' if best[1] / best[2] >= 1.6 else 'not met'}")
print(f"  height fields of 1 and 2 threads: {'the same bytes' if same else 'DIFFERENT'}")
PY
