#!/usr/bin/env bash
# Side by side with the notebook's numpy code (../shared/peers/wind_ripples_numpy.py, variant
# `reference`: the notebook verbatim), in one run on one machine: default parameters (524,288
# particles, 256 x 256 bins, L = 1/64, kappa = 4.5, D = 8e-4 annealed) and 128 steps.
#
# Times: the peer's TIME line (its loop, perf_counter, imports excluded) against cellsurf's
# `elapsed_s` (its steps, particle set-up excluded), median over cellsurf's runs, all cores.
# Statistics: mean height (1), height standard deviation and the two wavelengths of the final
# height field, the peer's (seed 1998) against the spread of cellsurf's seeds; the peer's
# wavelengths are computed here with numpy's FFT from its --out file, with the same definitions
# as cellsurf (src/windripples.rs), and the same numpy code checks cellsurf's own numbers.
#
#   bash bench/peer_windripples.sh [STEPS] [SEEDS]
set -euo pipefail
cd "$(dirname "$0")/.."
STEPS=${1:-128}
SEEDS=${2:-6}
PEER=${PEER:-../shared/peers/wind_ripples_numpy.py}
if ! python3 -c "import numpy" 2>/dev/null; then
  echo "numpy is missing: pip install numpy" >&2
  python3 -m pip install --quiet numpy
fi
cargo build --release --quiet
bin=target/release/cellsurf
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "python $(python3 -c 'import sys; print(sys.version.split()[0])'), numpy $(python3 -c 'import numpy; print(numpy.__version__)'), $($bin --version)"

# Each command's CPU time (user + sys, whole process) goes to a .cpu file.
TIMEFORMAT='%U %S'
# cellsurf, seed 1998 (the peer's), with the height field, before and after the peer so that a
# change of load on a shared machine hits both sides.
{ time $bin wind-ripples --steps "$STEPS" --json --npy "$tmp/ours.npy" >"$tmp/ours_1998_a.json"; } 2>"$tmp/ours_1998_a.cpu"
{ time python3 "$PEER" "$STEPS" --out "$tmp/peer.npy" >"$tmp/peer.out"; } 2>"$tmp/peer.cpu"
peer=$(grep '^TIME' "$tmp/peer.out")
echo "$peer"
{ time $bin wind-ripples --steps "$STEPS" --json >"$tmp/ours_1998_b.json"; } 2>"$tmp/ours_1998_b.cpu"
for s in $(seq 1 "$SEEDS"); do
  { time $bin wind-ripples --steps "$STEPS" --seed "$s" --json >"$tmp/ours_seed_$s.json"; } 2>"$tmp/ours_seed_$s.cpu"
done
echo "load average after the runs: $(cut -d' ' -f1-3 /proc/loadavg)"

python3 - "$tmp" "$peer" "$STEPS" "$SEEDS" <<'EOF'
import glob, json, re, sys
import numpy as np

tmp, peer_line, steps, seeds = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])

def spectrum(h):
    """P(k) = sum over columns ix of |DFT along y of h[ix, :] - 1|^2, k = 0..bins/2."""
    n = h.shape[0]
    return (np.abs(np.fft.fft(h - 1.0, axis=1)) ** 2).sum(axis=0)[: n // 2 + 1]

def peak_wavelength(p, n):
    w, top = max(1, n // 64), len(p) - 1
    win = lambda j: (max(1, j - w), min(top, j + w))
    s = [p[win(j)[0]: win(j)[1] + 1].mean() for j in range(1, top + 1)]
    lo, hi = win(int(np.argmax(s)) + 1)
    k = np.arange(lo, hi + 1)
    return n / ((k * p[lo: hi + 1]).sum() / p[lo: hi + 1].sum())

def mean_wavelength(p, n):
    k = np.arange(1, len(p))
    return ((n / k) * p[1:]).sum() / p[1:].sum()

def stats(h):
    p = spectrum(h)
    n = h.shape[0]
    return {"height_mean": h.mean(), "height_std": h.std(),
            "wavelength_bins": peak_wavelength(p, n), "mean_wavelength_bins": mean_wavelength(p, n)}

keys = ["height_mean", "height_std", "wavelength_bins", "mean_wavelength_bins"]
peer = stats(np.load(f"{tmp}/peer.npy"))
ours_npy = stats(np.load(f"{tmp}/ours.npy"))
a = json.load(open(f"{tmp}/ours_1998_a.json"))
b = json.load(open(f"{tmp}/ours_1998_b.json"))
runs = [json.load(open(f)) for f in sorted(glob.glob(f"{tmp}/ours_seed_*.json"))]

# cellsurf's numbers against the numpy re-computation from its own .npy.
for k in keys:
    assert abs(a[k] - ours_npy[k]) <= 1e-9 * max(1.0, abs(a[k])), (k, a[k], ours_npy[k])
print("check: cellsurf's statistics equal numpy's re-computation from its .npy (to 1e-9)")

peer_s = float(re.search(r"seconds=([0-9.]+)", peer_line).group(1))
times = sorted([a["elapsed_s"], b["elapsed_s"]] + [r["elapsed_s"] for r in runs])
med = float(np.median(times))
print(f"peer numpy-reference: {peer_s:.3f} s for {steps} steps")
print(f"cellsurf: median {med:.3f} s over {len(times)} runs (min {times[0]:.3f}, max {times[-1]:.3f}), "
      f"{a['threads']} threads, {a['particles'] * steps / med:.3g} particle-steps/s")
print(f"speed-up: x{peer_s / med:.1f} (median), x{peer_s / times[0]:.1f} (fastest run)   goal: >= 20")
cpu = lambda f: sum(float(v) for v in open(f).read().split()[-2:])
peer_cpu = cpu(f"{tmp}/peer.cpu")
ours_cpu = float(np.median([cpu(f) for f in glob.glob(f"{tmp}/ours_*.cpu")]))
print(f"CPU time (user + sys, whole process): peer {peer_cpu:.2f} s, cellsurf median {ours_cpu:.2f} s "
      f"(all its threads): x{peer_cpu / ours_cpu:.1f}")
print()
print(f"{'statistic':22} {'peer seed 1998':>15} {'ours seed 1998':>15} {'ours seeds 1..%d: mean +- sd' % seeds:>30} {'z':>6}  verdict")
ok = True
for k in keys:
    v = np.array([r[k] for r in runs], dtype=float)
    m, sd = v.mean(), v.std(ddof=1)
    if k == "height_mean":
        good = abs(peer[k] - 1) < 1e-12 and abs(a[k] - 1) < 1e-12
        z, verdict = float("nan"), "both 1" if good else "NOT 1"
    else:
        z = (peer[k] - m) / sd if sd > 0 else float("inf")
        good = abs(z) <= 3
        verdict = "within the spread (|z| <= 3)" if good else "OUTSIDE the spread"
    ok &= good
    print(f"{k:22} {peer[k]:15.4f} {a[k]:15.4f} {m:17.4f} +- {sd:<10.4f} {z:6.2f}  {verdict}")
print()
print("statistics agree" if ok else "statistics DISAGREE")
EOF
