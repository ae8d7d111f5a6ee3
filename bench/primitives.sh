#!/usr/bin/env bash
# The per-ray cost of each primitive beside the sphere's: renders bench/scenes/{sphere, cylinder,
# cone, torus, disc}.wsd (the same framing, light and material: a 10×10 grid of one primitive on
# a plane) on one thread, the scenes alternating, and prints each one's median render time, its
# ray queries (camera and shadow rays) and its time per query relative to the sphere scene's.
#
# Usage: bench/primitives.sh [BUILD_DIR] [RUNS]   (defaults build/ and 5)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
runs=${2:-5}
[[ -x $build/wsd ]] || { echo "primitives: $build/wsd not found; build first (./setup.sh)" >&2; exit 3; }
kinds=(sphere cylinder cone torus disc)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for ((r = 0; r < runs; r++)); do
  for k in "${kinds[@]}"; do
    "$build/wsd" render "bench/scenes/$k.wsd" -o "$tmp/$k.pfm" --threads 1 -q --stats-json "$tmp/$k.$r.json" >/dev/null
  done
done
python3 - "$tmp" "$runs" "${kinds[@]}" <<'PY'
import json, statistics, sys
tmp, runs, kinds = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
def load(k, r):
    return json.load(open(f"{tmp}/{k}.{r}.json"))
def find(d, *names):
    for n in names:
        if n in d: return d[n]
    for v in d.values():
        if isinstance(v, dict):
            x = find(v, *names)
            if x is not None: return x
    return None
rows = []
for k in kinds:
    times = [find(load(k, r), "render_seconds", "render_time") for r in range(runs)]
    queries = find(load(k, 0), "ray_queries", "total_ray_queries")
    rows.append((k, statistics.median(times), queries))
base = rows[0][1] / rows[0][2]
print("| scene | median render (s) | ray queries | time per query vs sphere |")
print("|---|---|---|---|")
for k, t, q in rows:
    print(f"| {k} | {t:.3f} | {q:,} | {t / q / base:.2f} |")
PY
