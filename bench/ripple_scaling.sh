#!/usr/bin/env bash
# Steps per second and memory of `cellsurf ripple --recipe paper` at 4 sizes up to the paper's 5,000,000
# automata (30 automata per column, activity 0.1 %: about 5,000 activations per step at 5 M).
# Usage: bench/ripple_scaling.sh   (after `cargo build --release`)
set -euo pipefail
bin=${BIN:-target/release/cellsurf}
for size in "128 64" "256 128" "512 256" "576 288"; do
  set -- $size
  for ab in slices shadow; do
    /usr/bin/time -f "maxrss_kb=%M" "$bin" ripple --recipe paper --json --nx "$1" --ny "$2" --layers 30 \
      --steps 300 --abstraction "$ab" 2>&1 | python3 -c "
import sys, json
lines = sys.stdin.read().splitlines()
d = json.loads(lines[0]); rss = int(lines[-1].split('=')[1])
print(f\"{'$1'}x{'$2'} {'$ab':7s} automata={d['automata']} act/step={d['activations']//d['steps']} \"
      f\"steps/s={d['steps_per_s']:.1f} setup_s={d['setup_s']:.2f} \"
      f\"volume_B/automaton={d['bytes_per_automaton']:.2f} maxrss_B/automaton={rss*1024/d['automata']:.2f}\")"
  done
done
