#!/usr/bin/env bash
# The CLI against the engine on the same configuration, in one run: the exact sampler on the
# 2048 x 2048 hexagonal flame (torus, side-20 square start), 1,000,000 accepted events, at
# n = 0, 2, 8, 50. The engine's rate is the divan benchmark `exact_flame_2048` (median); the
# CLI's is `accepted_per_s` of `cellsurf flame --events 1e6 --json` (sampling time: set-up and
# observables excluded), median of REPEATS runs.
#   bash bench/cli_vs_engine.sh [REPEATS]
set -euo pipefail
cd "$(dirname "$0")/.."
REPEATS=${1:-5}
cargo build --release --quiet
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); load average $(cut -d' ' -f1-3 /proc/loadavg)"
bench=$(cargo bench --quiet --bench growth -- exact_flame_2048 2>/dev/null)
python3 - "$REPEATS" "$bench" <<'PY'
import json, re, statistics, subprocess, sys
repeats, bench = int(sys.argv[1]), sys.argv[2]
# divan rows: "├─ 0   fastest │ slowest │ median │ mean" then a line of Mitem/s in the same columns.
rates, arg = {}, None
for line in bench.splitlines():
    m = re.match(r"\s*[│ ]*[├╰]─ (\S+)\s", line)
    if m:
        arg = m.group(1)
        continue
    if arg is not None and "item/s" in line:
        cols = [c.strip() for c in line.split("│")]
        med = cols[2]
        v, unit = re.match(r"([0-9.]+) (\w)?item/s", med).groups()
        rates[arg] = float(v) * {"M": 1e6, "K": 1e3, "G": 1e9}.get(unit, 1.0)
        arg = None
for n in ["0", "2", "8", "50"]:
    cli = []
    for _ in range(repeats):
        r = subprocess.run(["target/release/cellsurf", "flame", "--size", "2048x2048", "--start", "20",
                            "--n", n, "--events", "1e6", "--json"], check=True, capture_output=True, text=True)
        cli.append(json.loads(r.stdout)["accepted_per_s"])
    c, b = statistics.median(cli), rates.get(n, float("nan"))
    # The engine's own goal: 15 M events/s at n = 0 and 2, 20 M at n = 50 (none at n = 8).
    goal = {"0": 15e6, "2": 15e6, "50": 20e6}.get(n)
    engine = "" if goal is None else f"; engine goal >= {goal / 1e6:.0f} M/s: {'met' if b >= goal else 'not met'}"
    print(f"n = {n:>2}: engine {b / 1e6:6.2f} M events/s ({1e9 / b:.0f} ns per event), CLI {c / 1e6:6.2f} M events/s, "
          f"CLI/engine {c / b:.2f} (goal >= 0.85: {'met' if c / b >= 0.85 else 'not met'}){engine}")
PY
