#!/usr/bin/env bash
# Whole-run comparison with the naive plain-Python flame (../shared/peers/flame_python.py),
# side by side in one run on one machine: hex torus L x L, side-20 square start, n = 2,
# 5,000,000 timesteps. Times exclude set-up on both sides (the peer reports it separately;
# cellsurf's elapsed_s excludes lattice construction).
#   bash bench/peer_flame.sh [L] [STEPS] [REPEATS]
set -euo pipefail
cd "$(dirname "$0")/.."
L=${1:-1000}
STEPS=${2:-5000000}
REPEATS=${3:-3}
PEER=${PEER:-../shared/peers/flame_python.py}
cargo build --release --quiet
bin=target/release/cellsurf
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
py=$(python3 "$PEER" --L "$L" --steps "$STEPS" --repeats "$REPEATS" | grep '^TIME')
echo "$py"
py_s=$(sed -E 's/.*median_run_s=([0-9.]+).*/\1/' <<<"$py")
py_burnt=$(sed -E 's/.*final_burnt=([0-9]+).*/\1/' <<<"$py")
for sampler in rejection exact; do
  best=""
  for _ in $(seq "$REPEATS"); do
    out=$($bin grow --lattice hex --size "${L}x${L}" --boundary torus --shape square --start 20 \
      --n 2 --steps "$STEPS" --sampler "$sampler" --series 1 --snapshots "$STEPS" --json)
    s=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["elapsed_s"])' "$out")
    occ=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["occupied"])' "$out")
    if [ -z "$best" ] || python3 -c "import sys; sys.exit(0 if $s < $best else 1)"; then best=$s; fi
  done
  ratio=$(python3 -c "print(f'{$py_s / $best:.0f}')")
  echo "cellsurf $sampler: best run ${best}s, burnt $occ (peer $py_burnt), speed-up x$ratio over the peer"
done
