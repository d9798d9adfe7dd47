#!/usr/bin/env bash
# Ripple shape with the paper's rules in its Fig. 3 situation (`--recipe paper`) and its variants, seeds 1-3:
# wavelength, height, ripple index, lee/stoss slopes, symmetry index, crest normal and the
# crest/trough d50, against Soulsby & Whitehouse (2005). Prints one line per run (JSON keys of
# `cellsurf ripple --json`). Usage: bash bench/ripple_shape.sh [extra cellsurf ripple flags]
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin=target/release/cellsurf
keys='wavelength_m height_m ripple_index lee_slope_deg stoss_slope_deg symmetry_index crest_normal_deg d50_crest_mm d50_trough_mm mass_change elapsed_s'
run() {
  local label="$1"; shift
  "$bin" ripple --recipe paper --json --quiet "$@" | python3 -c "
import json, sys
d = json.load(sys.stdin)
print('$label'.ljust(34), ' '.join(f'{k}={d[k]:.4g}' if isinstance(d[k], float) else f'{k}={d[k]}' for k in '$keys'.split()))
"
}
for seed in 1 2 3; do
  run "slices seed $seed" --seed "$seed" "$@"
  run "shadow seed $seed" --seed "$seed" --abstraction shadow "$@"
  run "slices sorting 1 seed $seed" --seed "$seed" --sorting 1 "$@"
done
run "slices current 45 deg" --current-angle 45 --nx 96 --ny 96 "$@"
run "slices current 90 deg" --current-angle 90 --nx 64 --ny 128 "$@"
run "pure wave (0.5 m/s, 8 s)" --current-speed 0 --wave-velocity 0.5 --wave-period 8s "$@"
run "bin 2.5 mm (256 x 128)" --bin-size 0.0025 --nx 256 --ny 128 "$@"
run "bin 10 mm (64 x 32)" --bin-size 0.01 --nx 64 --ny 32 --layer-thickness 0.001 --layers 30 "$@"
run "d50 0.4 mm" --d50 0.4 "$@"
