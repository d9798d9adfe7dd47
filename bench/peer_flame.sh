#!/usr/bin/env bash
# Whole-run comparison with the naive plain-Python flame (the peer flame_python.py, a
# rejection-sampling Eden/flame growth in the standard library only), side by side in one run
# on one machine: hex torus L x L, side-20 square start, n = 2, 5,000,000 timesteps.
# The peer's time is its run loop (set-up excluded, its own TIME line); cellsurf's is the
# whole process (start-up, lattice construction, the run, the JSON summary), measured from
# outside with perf_counter, best of REPEATS. Both samplers.
#   bash bench/peer_flame.sh [L] [STEPS] [REPEATS]
#   PEER=path/to/flame_python.py bash bench/peer_flame.sh
set -euo pipefail
cd "$(dirname "$0")/.."
L=${1:-1000}
STEPS=${2:-5000000}
REPEATS=${3:-5}
PEER=${PEER:-../shared/peers/flame_python.py}
cargo build --release --quiet
bin=target/release/cellsurf
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); load average $(cut -d' ' -f1-3 /proc/loadavg)"
py=$(python3 "$PEER" --L "$L" --steps "$STEPS" --repeats 3 | grep '^TIME')
echo "peer: $py"
python3 - "$bin" "$L" "$STEPS" "$REPEATS" "$py" <<'PY'
import json, re, subprocess, sys, time
bin, L, steps, repeats, py = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), sys.argv[5]
peer_s = float(re.search(r"median_run_s=([0-9.]+)", py).group(1))
peer_burnt = re.search(r"final_burnt=([0-9]+)", py).group(1)
for sampler in ["rejection", "exact"]:
    cmd = [bin, "grow", "--lattice", "hex", "--size", f"{L}x{L}", "--boundary", "torus",
           "--shape", "square", "--start", "20", "--n", "2", "--steps", steps,
           "--sampler", sampler, "--json"]
    best, out = None, None
    for _ in range(repeats):
        t = time.perf_counter()
        r = subprocess.run(cmd, check=True, capture_output=True, text=True)
        dt = time.perf_counter() - t
        if best is None or dt < best:
            best, out = dt, json.loads(r.stdout)
    print(f"cellsurf {sampler}: whole process best {best:.4f} s (run {out['elapsed_s']:.4f} s, "
          f"set-up {out['setup_s']:.4f} s), burnt {out['occupied']} (peer {peer_burnt}), "
          f"x{peer_s / best:.0f} the peer's run loop ({peer_s:.2f} s); goal x50: "
          f"{'met' if peer_s / best >= 50 else 'not met'}")
PY
