#!/usr/bin/env bash
# Computing time of the default `cellsurf ripple` run (the recipe for mature current ripples,
# until equilibrium) at d50 = 0.1 / 0.2 / 0.4 mm, seeds 1-3, one run at a time: `elapsed_s`
# from the JSON, the flow simulated and where it stopped. With BASE=path/to/another/cellsurf
# the two binaries run alternately in the same script, each first in every other pair (ratios
# like for like on a shared machine), and their volumes are compared byte for byte.
#   bash bench/ripple_default.sh                 (BASE=... optional; GRAINS="0.2" SEEDS="2")
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin="${CARGO_TARGET_DIR:-target}/release/cellsurf"
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); load average $(cut -d' ' -f1-3 /proc/loadavg)"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
python3 - "$out" "$bin" "${BASE:-}" "${GRAINS:-0.1 0.2 0.4}" "${SEEDS:-1 2 3}" <<'PY'
import filecmp, json, subprocess, sys
out, this, base = sys.argv[1], sys.argv[2], sys.argv[3]
grains, seeds = sys.argv[4].split(), sys.argv[5].split()
bins = {"this": this}
if base:
    bins["base"] = base
total = {k: 0.0 for k in bins}
worst = {k: 0.0 for k in bins}
pair = 0
for d in grains:
    for s in seeds:
        files, result = {}, {}
        order = list(bins) if pair % 2 == 0 else list(reversed(bins))
        pair += 1
        for k in order:
            files[k] = f"{out}/{k}.nc"
            r = subprocess.run([bins[k], "ripple", "--d50", d, "--seed", s, "--json",
                                "--out", files[k]], check=True, capture_output=True, text=True)
            j = json.loads(r.stdout)
            total[k] += j["elapsed_s"]
            worst[k] = max(worst[k], j["elapsed_s"])
            result[k] = (f"{k} {j['elapsed_s']:6.1f} s (stopped at {j['simulated_time_s']:7.0f} s "
                         f"of flow, {100 * j['wavelength_m']:.1f} cm)")
        row = [result[k] for k in bins]
        if base:
            same = filecmp.cmp(files["this"], files["base"], shallow=False)
            row.append("same bytes" if same else "DIFFERENT bytes")
        print(f"d50 {d} mm seed {s}: " + "; ".join(row), flush=True)
for k in bins:
    print(f"{k}: {total[k]:.1f} s in all, slowest run {worst[k]:.1f} s")
if base:
    print(f"ratio base / this: {total['base'] / total['this']:.2f}")
PY
