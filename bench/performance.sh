#!/usr/bin/env bash
# Measures wsd and writes docs/performance.md from what it measured: the machine and the date at
# the top, then one table per benchmark, each with the command that regenerates it. It runs the
# programs of an existing build directory (default build/, made by ./setup.sh). The Cornell box
# is compared with POV-Ray when `povray` is installed (Debian's povray package); otherwise that
# section says so. The same holds for the side-by-side tables
# against Embree 3: bench_embree is built when CMake finds Debian's libembree-dev.
#
# Usage: bench/performance.sh [--quick] [--baseline WSD] [--only NAMES] [-o OUT] [BUILD_DIR]
#   --quick         small sizes and one run of each, for checking the script (about a minute); the
#                   `wsd bench` output then goes to a temporary directory instead of docs/bench/
#   --baseline WSD  an older wsd executable: every example is rendered by both, alternating, and
#                   the page says whether the images are byte-identical and how the times compare
#   --only NAMES    measure only these sections (comma-separated: cornell, honesty, targeted, …; see
#                   `sections` below) and replace them in the existing page, each stamped with its
#                   own date and load; the rest of the page stays as its run measured it
#   -o OUT          the page to write (default docs/performance.md)
# A full run takes about 15 CPU-minutes, mostly on one thread: 30 minutes of wall time on a busy
# 2-core machine, and up to 10 more the first time, for the Cornell box's converged reference
# (cached under BUILD_DIR/bench-cache).
set -euo pipefail
cd "$(dirname "$0")/.."

quick=0; out=docs/performance.md; build=build; baseline=; baseline_shown=; only=
while (($#)); do
  case $1 in
    --quick) quick=1 ;;
    --baseline) baseline_shown=${2:?--baseline needs an executable}; baseline=$(realpath "$2"); shift ;;
    --only) only=${2:?--only needs section names}; shift ;;
    -o) out=${2:?-o needs a file}; shift ;;
    -h|--help) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "performance: unknown option $1" >&2; exit 2 ;;
    *) build=$1 ;;
  esac
  shift
done
for program in wsd bench_mesh bench_obj bench_parse bench_csg; do
  [[ -x $build/$program ]] || { echo "performance: $build/$program not found; build first (./setup.sh)" >&2; exit 3; }
done
wsd=$(realpath "$build/wsd")
export WSD=$wsd
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
TIMEFORMAT='%R %U %S'
start=$(date +%s)

if ((quick)); then
  runs=1; cornell=200; adaptive=200; bench_size=32; threads_size=150; pairs=1
  parse_args=(20000); mesh_args=(100 51); bench_dir=$tmp/bench
  inst_grid=(4 5); inst_sphere=(100 52); inst_size=(256 192)
else
  runs=3; cornell=1200; adaptive=1200; bench_size=200; threads_size=600; pairs=3
  parse_args=(); mesh_args=(); bench_dir=docs/bench
  inst_grid=(40 25); inst_sphere=(1000 502); inst_size=(1024 768)
fi

log() { echo "performance: $*" >&2; }
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) exit 1; print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
range() { sort -g | awk 'NR == 1 { lo = $1 } { hi = $1 } END { print lo "–" hi }'; }
# field FILE REGEX N: the Nth whitespace-separated field of the first line matching REGEX.
field() { awk -v n="$3" "/$2/ { print \$n; exit }" "$1"; }
fmt() { awk -v x="$1" -v d="${2:-2}" 'BEGIN { printf "%.*f", d, x }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }
commas() { printf "%d" "$1" | sed ':a; s/\B[0-9]\{3\}\>/,&/; ta'; }
loadavg() { cut -d' ' -f1-3 /proc/loadavg; }
cpu_model() { lscpu | sed -n 's/^Model name: *//p' | head -1; }

page=$tmp/page.md
section() {
  printf '\n## %s\n\n' "$1" >>"$page"
  # A section measured later may come from another machine than the page's header names.
  [[ -z $only ]] || printf '_Measured on its own by `bench/performance.sh --only %s` on %s, on %s, %s cores (load average before: %s)._\n\n' \
    "$current" "$(date -u '+%Y-%m-%d %H:%M UTC')" "$(cpu_model)" "$(nproc)" "$(loadavg)" >>"$page"
}
para() { printf '%s\n' "$@" >>"$page"; }

load_before=$(loadavg)
# The commit measured; "with local changes" only for changes outside the files this run writes.
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
if [[ -n $(git status --porcelain 2>/dev/null | grep -vE " (docs/performance\.md|docs/bench/.*|$out)$" || true) ]]; then
  commit+=" with local changes"
fi

# ---------------------------------------------------------------- the Cornell box against POV-Ray
cornell_table() {
  section "The Cornell box against POV-Ray"
  if ! command -v povray >/dev/null; then
    para "POV-Ray is not installed on this machine (\`apt-get install povray\`), so this comparison was" \
         "not made."
    return
  fi
  local args=("$cornell" 1) pov_version
  pov_version=$(povray --version 2>&1 | awk '/^POV-Ray/ { print $2; exit }')
  log "Cornell box against POV-Ray at ${cornell}x${cornell}"
  bench/cornell_vs_povray.sh "${args[@]}" >"$tmp/cvp.txt"
  log "the same with adaptive area lights"
  bench/cornell_vs_povray.sh "${args[@]}" --adaptive >"$tmp/cvp-adaptive.txt"

  para "\`bench/cornell_vs_povray.sh $cornell 1\` and \`bench/cornell_vs_povray.sh $cornell 1 --adaptive\`:" \
       "examples/cornell.wsd and its POV-Ray ${pov_version:-3.7} port bench/scenes/cornell.pov at" \
       "${cornell}×${cornell}, 4 camera rays a pixel, a 10×10 area light, depth 5, one thread, the two" \
       "renderers one after the other (one run each). CPU-s is user + system time of the whole process" \
       "(parse, build, render, write). A ray query is one camera, shadow, reflection or refraction ray;" \
       "\"shaft-answered\" shadow rays were decided by their shaft without a traversal ([robustness.md](robustness.md))." \
       "With \`--adaptive\`, POV-Ray's area light has \`adaptive 1\` and wsd renders with \`--adaptive-lights\`." \
       "" \
       "| area light | renderer | CPU-s | ray queries | M ray queries per CPU-s | shaft-answered shadow rays | CPU time, POV-Ray ÷ wsd |" \
       "|---|---|---:|---:|---:|---:|---:|"
  local f label w_cpu w_rays p_cpu p_rays shaft
  for f in cvp cvp-adaptive; do
    [[ $f == cvp ]] && label="full 10×10" || label="adaptive"
    w_cpu=$(field "$tmp/$f.txt" '^wsd +[0-9]' 2); w_rays=$(field "$tmp/$f.txt" '^wsd +[0-9]' 3)
    p_cpu=$(field "$tmp/$f.txt" '^povray +[0-9]' 2); p_rays=$(field "$tmp/$f.txt" '^povray +[0-9]' 3)
    shaft=$(field "$tmp/$f.txt" '^wsd: ' 2)
    para "| $label | wsd | $(fmt "$w_cpu") | $(commas "$w_rays") | $(fmt "$(awk "BEGIN{print $w_rays/$w_cpu/1e6}")" 1) | $(commas "$shaft") | **$(ratio "$p_cpu" "$w_cpu")×** |" \
         "| | POV-Ray $pov_version | $(fmt "$p_cpu") | $(commas "$p_rays") | $(fmt "$(awk "BEGIN{print $p_rays/$p_cpu/1e6}")" 1) | — | |"
  done
  para "" \
       "Not measured here: the report “Recursive Backwards Ray Tracing” publishes 286 s for this scene" \
       "with its BVH and 540 s without, on its author's machine (its own published figures, for scale" \
       "only)."
}

# ---------------------------------------------------------------- caustics against POV-Ray's photons
caustics_table() {
  section "Caustics against POV-Ray's photons"
  if ! command -v povray >/dev/null; then
    para "POV-Ray is not installed on this machine (\`apt-get install povray\`), so this comparison was" \
         "not made."
    return
  fi
  local size=300 counts="25000 100000 400000"
  ((quick)) && size=96 counts="10000 40000"
  log "caustics against POV-Ray's photons at ${size}x${size}"
  bench/caustics_vs_povray.sh "$size" 1 "$counts" >"$tmp/caustics.txt"
  para "\`bench/caustics_vs_povray.sh $size 1 \"$counts\"\`: examples/cornell-caustics.wsd and its POV-Ray" \
       "port bench/scenes/cornell-caustics.pov (\`photons { count N }\`) at ${size}×${size}, 4 camera rays a" \
       "pixel, one thread, each photon count for both renderers, every image compared with wsd's" \
       "converged reference (32 times the largest count, 16 rays a pixel) by \`wsd diff\` on display" \
       "values. CPU-s is user + system time of the whole process (photons included)." \
       "" \
       "| renderer | photons | CPU-s | RMSE | PSNR (dB) |" \
       "|---|---:|---:|---:|---:|"
  awk '$1 == "wsd" || $1 == "povray" { printf "| %s | %s | %s | %s | %s |\n", ($1 == "wsd" ? "wsd" : "POV-Ray"), $2, $3, $4, $5 }' \
    "$tmp/caustics.txt" >>"$page"
  para "" \
       "POV-Ray's photons follow its own conventions (its photon spacing and gather), so its error includes" \
       "any difference of model between the two renderers, not only noise."
}

# ---------------------------------------------------------------- adaptive sampling
adaptive_table() {
  section "Adaptive sampling against full sampling"
  log "adaptive options against full sampling at ${adaptive}x${adaptive}"
  bench/adaptive_vs_full.sh "$adaptive" 1 >"$tmp/avf.txt"
  para "\`bench/adaptive_vs_full.sh $adaptive 1\`: the Cornell box at ${adaptive}×${adaptive}, one thread, one run" \
       "of each. \"Full\" is the scene with \`bailout 0\` and nothing adaptive: every camera ray, every light" \
       "cell, every reflected and refracted ray. Same seed everywhere; PSNR and SSIM are \`wsd diff\`" \
       "against the full image." \
       "" \
       "| setting | CPU-s | speed-up | ray queries | shadow rays | fewer shadow rays | PSNR vs full (dB) | SSIM |" \
       "|---|---:|---:|---:|---:|---:|---:|---:|"
  # Rows: a 36-character label, then CPU-s, speed-up, queries, shadow rays, shadow ratio,
  # adaptive pixels, PSNR, SSIM.
  sed -n '2,7p' "$tmp/avf.txt" | while IFS= read -r line; do
    local label cpu speed rq sh shr psnr ssim
    label=$(awk '{ for (i = 1; i <= NF - 8; i++) printf "%s%s", $i, (i < NF - 8 ? " " : "") }' <<<"$line")
    read -r cpu speed rq sh shr _ psnr ssim < <(awk '{ for (i = NF - 7; i <= NF; i++) printf "%s ", $i; print "" }' <<<"$line")
    if [[ $psnr == inf ]]; then psnr="—"; else psnr=$(fmt "$psnr"); fi
    para "| $label | $(fmt "$cpu") | ${speed%x}× | $(commas "$rq") | $(commas "$sh") | ${shr%x}× | $psnr | $ssim |"
  done
}

# ---------------------------------------------------------------- wsd bench
bench_table() {
  section "What accuracy costs: \`wsd bench\`"
  local args=(examples/cornell.wsd -o "$bench_dir" --width "$bench_size" --height "$bench_size" --threads 1 --quiet)
  ((quick)) && args+=(--quick)
  log "wsd bench ${args[*]}"
  local t
  t=$( { time "$wsd" bench "${args[@]}" >"$tmp/bench.txt"; } 2>&1 )
  local shown_args=("${args[@]}")
  ((quick)) && shown_args[2]=DIR
  para "\`build/wsd bench ${shown_args[*]}\` ($(fmt "$(cut -d' ' -f1 <<<"$t")" 0) s in all): the Cornell box at" \
       "${bench_size}×${bench_size}, one thread; each knob is varied alone from the scene's settings (4 camera" \
       "rays a pixel, a 10×10 light, depth 5, bailout 1/512), and the error is against a reference with" \
       "256 camera rays a pixel, a 16×16 light, depth 10, bailout 0 and another seed. Times are the" \
       "median of $( ((quick)) && echo "1 run" || echo "3 runs"). \`*\`: on the Pareto front of error against time."
  if ((!quick)); then
    para "Every column, with wall times and ray counts: [bench/bench.md](bench/bench.md); the data:" \
         "[bench/bench.csv](bench/bench.csv)." "" '<img src="bench/bench.svg" width="720">'
  fi
  para "" "| knob | value | CPU-s | shadow rays | RMSE | PSNR (dB) | SSIM | Pareto |" \
       "|---|---:|---:|---:|---:|---:|---:|:---:|"
  # bench.csv: knob,value,wall_seconds,cpu_seconds,camera_rays,shadow_rays,reflection_rays,
  # refraction_rays,ray_queries,rmse,psnr,max_abs_error,ssim,pareto
  awk -F, 'function commas(n) { while (n ~ /[0-9][0-9][0-9][0-9]/) sub(/[0-9][0-9][0-9]($|,)/, ",&", n); return n }
           NR > 1 { printf "| %s | %s | %.2f | %s | %.6f | %.2f | %.5f | %s |\n",
                    $1, $2, $4, commas($6), $10, $11, $13, ($14 == 1 ? "*" : "") }' "$bench_dir/bench.csv" >>"$page"
}

# ---------------------------------------------------------------- how honest the error estimate is
honesty_table() {
  section "How honest \`--target-error\`'s estimate is"
  local args=(80 60 "0.02 0.01" 0.0025)
  ((quick)) && args=(24 18 "0.04" 0.01)
  log "bench/target_error_honesty.sh ${args[*]}"
  bench/target_error_honesty.sh "${args[@]}" >"$tmp/honesty.txt"
  para "\`bench/target_error_honesty.sh ${args[0]} ${args[1]} \"${args[2]}\" ${args[3]}\`: every example scene and the" \
       "three scenes of bench/scenes/honesty-*.wsd (a textured floor at grazing angles, a glass sphere" \
       "over a checker, a room lit by an emissive sphere through indirect light) at ${args[0]}×${args[1]}," \
       "rendered with \`--target-error\` at each target and compared by \`wsd diff\` with a reference" \
       "(\`--target-error ${args[3]}\`, another seed, at most 8 s). Estimated: the render's \`estimated_rmse\`;" \
       "measured: the RMSE against the reference; raw = measured ÷ estimated. The reference keeps some" \
       "error of its own (its estimate: pixels stop at 1024 samples, slow scenes at 8 s), which adds in quadrature: an honest estimate" \
       "predicts sqrt(estimated² + reference²), and ratio = measured ÷ predicted. Within: the ratio" \
       "lies within 1.5× either way." \
       "" \
       "| scene | target | estimated | measured | raw | reference | predicted | ratio | within 1.5× |" \
       "|---|---:|---:|---:|---:|---:|---:|---:|:---:|"
  awk 'NF >= 9 && $2 ~ /^[0-9.]+$/ { printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9 }' \
    "$tmp/honesty.txt" >>"$page"
  para "" "$(awk '/^within 1.5x:/ { printf "Within 1.5× by ratio: %s of %s renders; by raw: %s of %s.", $3, $5, $8, $10 }' "$tmp/honesty.txt")"
}

# ---------------------------------------------------------------- the Cornell box at equal error
targeted_table() {
  section "The Cornell box at equal error: targeted rendering against POV-Ray"
  if ! command -v povray >/dev/null; then
    para "POV-Ray is not installed on this machine (\`apt-get install povray\`), so this comparison was" \
         "not made."
    return
  fi
  local size=$cornell
  log "bench/cornell_targeted.sh $size 1"
  CACHE="$build/bench-cache" bench/cornell_targeted.sh "$size" 1 >"$tmp/targeted.txt"
  local ref_est verdict
  ref_est=$(awk '/^reference / { print $NF; exit }' "$tmp/targeted.txt")
  verdict=$(awk '/^verdict / { $1 = ""; print; exit }' "$tmp/targeted.txt")
  para "\`bench/cornell_targeted.sh $size 1\`: the Cornell box at ${size}×${size}, one thread, one run of each," \
       "one after the other. RMSE is \`wsd diff\` against wsd's converged reference at the same size" \
       "(\`--target-error 0.002\` with \`exact_area_lights on\`, another seed, at most 600 s, cached under" \
       "build/bench-cache; its own estimated RMSE $(fmt "$ref_est" 6), which adds in quadrature: net is" \
       "sqrt(RMSE² − reference²), the row's own error). POV-Ray has \`adaptive 1\` on its area light; its RMSE also holds the" \
       "differences between the two renderers' models. \"Exact\" is \`--adaptive-lights\` with" \
       "\`exact_area_lights on\`; \"targeted\" adds \`--target-error E\`. The target bounds each pixel's own" \
       "estimated error, so the image's error ends well below it. CPU-s is user + system time of the whole process." \
       "" \
       "| renderer and settings | CPU-s | RMSE | net | estimated RMSE | samples a pixel (min/median/max) | CPU time, POV-Ray ÷ this |" \
       "|---|---:|---:|---:|---:|---:|---:|"
  awk '$2 !~ /^[0-9.]+$/ { next } $1 == "povray" { l = "POV-Ray, adaptive 1" } $1 == "default" { l = "wsd, the scene'"'"'s settings" }
       $1 == "exact" { l = "wsd, exact" } $1 == "targeted" { l = "wsd, targeted, E = " $7 }
       l != "" { printf "| %s | %.2f | %s | %s | %s | %s | %s× |\n", l, $2, $3, $4, $5 == "-" ? "—" : $5, $8 == "" ? "—" : $8, $6; l = "" }' \
    "$tmp/targeted.txt" >>"$page"
  set -- $verdict
  if [[ ${4:-none} == none ]]; then
    para "" "No target tried reached the default settings' net error ($(fmt "$2" 6))."
  else
    para "" "The largest target whose image is at least as accurate as the default settings' (net $(fmt "$2" 6)):" \
         "E = $4, **$(fmt "$5" 2) CPU-s**, net error $(fmt "$6" 6), **$7× less CPU time than POV-Ray's adaptive light**."
  fi
}

# ---------------------------------------------------------------- indirect light against POV-Ray radiosity
indirect_table() {
  section "Indirect light: error against time, and POV-Ray's radiosity"
  local size=96 ref=256
  ((quick)) && size=32 ref=16
  log "bench/indirect_vs_povray.sh $size $ref"
  WSD=$wsd bench/indirect_vs_povray.sh "$size" "$ref" >"$tmp/indirect.txt"
  para "\`bench/indirect_vs_povray.sh $size $ref\`: examples/cornell-indirect.wsd at ${size}×${size}, 4 camera" \
       "rays a pixel, one thread, with 1 … 32 indirect paths a camera sample, and its POV-Ray port" \
       "(bench/scenes/cornell-indirect.pov: the same walls, light and glowing panel) with radiosity at" \
       "rising \`count\` (3 bounces, error_bound 0.5), rendered in the same run. The error of each is" \
       "against wsd's converged reference ($ref paths a camera sample, the same 3 bounces, another seed), as" \
       "\`wsd diff\` measures it on display values." "" \
       "| renderer | setting | CPU-s | RMSE | PSNR (dB) |" "|---|---|---:|---:|---:|"
  awk 'NR > 1 && NF >= 5 { s = $2; for (i = 3; i <= NF - 3; i++) s = s " " $i
                           printf "| %s | %s | %s | %s | %s |\n", $1, s, $(NF - 2), $(NF - 1), $NF }' \
      "$tmp/indirect.txt" >>"$page"
}

# ---------------------------------------------------------------- threads
threads_table() {
  section "Threads"
  local cmd=("$wsd" render examples/cornell.wsd --width "$threads_size" --height "$threads_size" --quiet)
  log "thread scaling at ${threads_size}x${threads_size}, $pairs pairs"
  local load_here
  load_here=$(loadavg)
  local i n t
  for ((i = 0; i < pairs; i++)); do
    for n in 1 2; do
      t=$( { time "${cmd[@]}" --threads "$n" -o "$tmp/threads-$n.png" >/dev/null; } 2>&1 )
      echo "$t" >>"$tmp/threads-$n.txt"
    done
    cmp -s "$tmp/threads-1.png" "$tmp/threads-2.png" || { echo "performance: 1 and 2 threads differ" >&2; exit 1; }
  done
  local w1 w2 c1 c2
  w1=$(cut -d' ' -f1 "$tmp/threads-1.txt" | median); w2=$(cut -d' ' -f1 "$tmp/threads-2.txt" | median)
  c1=$(awk '{ print $2 + $3 }' "$tmp/threads-1.txt" | median); c2=$(awk '{ print $2 + $3 }' "$tmp/threads-2.txt" | median)
  para "\`build/wsd render examples/cornell.wsd --width $threads_size --height $threads_size --threads N\`, N = 1 and 2" \
       "alternating, $pairs $( ((pairs == 1)) && echo pair || echo pairs); medians. The two images are byte-identical (checked). Two threads" \
       "get two cores only when nothing else runs: the load average (1, 5, 15 min) was $load_here" \
       "when this step began, on $(nproc) cores." \
       "" \
       "| threads | wall s (median) | wall s (all runs) | CPU-s (median) | speed-up (wall) |" \
       "|---:|---:|---:|---:|---:|" \
       "| 1 | $(fmt "$w1") | $(cut -d' ' -f1 "$tmp/threads-1.txt" | range) | $(fmt "$c1") | 1.00× |" \
       "| 2 | $(fmt "$w2") | $(cut -d' ' -f1 "$tmp/threads-2.txt" | range) | $(fmt "$c2") | $(ratio "$w1" "$w2")× |"
}

# ---------------------------------------------------------------- BVH and ray queries
mesh_table() {
  section "BVH: build and ray queries"
  log "bench_mesh ${mesh_args[*]}"
  "$build/bench_mesh" "${mesh_args[@]}" >"$tmp/mesh.txt"
  local f=$tmp/mesh.txt tris
  # after LINE-REGEX WORD: the number that follows WORD on the matching line.
  after() { awk -v w="$2" "/^$1/ { for (i = 1; i < NF; i++) if (\$i == w) { v = \$(i + 1); gsub(/[,)]/, \"\", v); print v; exit } }" "$f"; }
  tris=$(field "$f" '^mesh:' 2)
  para "\`$build/bench_mesh${mesh_args:+ ${mesh_args[*]}}\`: a closed UV sphere of $(commas "$tris") triangles, and the Cornell box's 28" \
       "primitives. Ray rates are per CPU-second on one thread, each the median of 5 passes taken in turn" \
       "with the others; camera rays one at a time and as packets (the renderer traces one-ray-a-pixel" \
       "images in 4×4-pixel packets and a pixel's supersamples together). Build times are wall times." \
       "" \
       "| figure | measured |" "|---|---:|" \
       "| BVH build (validation, world vertices, BVH), 1 thread | $(awk '/1 thread:/ { print $(NF-2); exit }' "$f") s |" \
       "| the same, 2 threads | $(awk '/2 threads:/ { print $(NF-2); exit }' "$f") s |" \
       "| memory per triangle, geometry + BVH (+ the mesh data itself) | $(field "$f" '^memory:' 2) (+ $(awk '/^memory:/ { sub(/\)/, "", $NF); print $NF }' "$f")) bytes |" \
       "| peak memory per triangle while building on 2 threads, above that before the build | $(field "$f" '^build peak:' 3) bytes |" \
       "| mesh camera rays, one at a time | $(field "$f" '^mesh primary rays:' 4) M/CPU-s |" \
       "| mesh camera rays, 2×2-pixel packets | $(field "$f" 'in packets:' 8) M/CPU-s |" \
       "| mesh camera rays, 4×4-pixel packets | $(awk '/in packets:/ { print $(NF-1); exit }' "$f") M/CPU-s |" \
       "| mesh shadow rays | $(field "$f" '^mesh shadow rays:' 4) M/CPU-s |" \
       "| Cornell box camera rays, BVH, one at a time / packets of 4 / of 16 | $(after cornell.BVH primary) / $(after cornell.BVH 4:) / $(after cornell.BVH 16:) M/CPU-s |" \
       "| Cornell box shadow rays, BVH | $(after cornell.BVH shadow) M/CPU-s |" \
       "| Cornell box camera / shadow rays, no BVH (every primitive) | $(after cornell.brute primary) / $(after cornell.brute shadow) M/CPU-s |"
}

# ---------------------------------------------------------------- the same rays through Embree
embree_table() {
  section "The same rays through Embree"
  if [[ ! -x $build/bench_embree ]]; then
    para "Not measured: \`bench_embree\` is built only when CMake finds Embree 3 (Debian's \`libembree-dev\`)."
    return 0
  fi
  local args=(); ((quick)) && args=(--quick)
  # A first run after the machine idled measured both sides about a quarter slower (a VM's CPU
  # takes seconds to come up to speed): a short run first, not recorded.
  "$build/bench_embree" --quick mesh1m >/dev/null
  log "bench_embree ${args[*]}"
  "$build/bench_embree" "${args[@]}" >"$tmp/embree.txt"
  # The million-triangle mesh again with Embree in its robust mode (no cracks at shared edges).
  log "bench_embree ${args[*]} --robust mesh1m"
  "$build/bench_embree" "${args[@]}" --robust mesh1m >>"$tmp/embree.txt"
  local f=$tmp/embree.txt
  para "\`$build/bench_embree${args:+ ${args[*]}}\`: wsd's geometry and $(awk '/^Embree/ { sub(/,$/, "", $2); print $1, $2; exit }' "$f") (Debian's" \
       "\`libembree-dev\`, default build quality; \"Embree robust\": in its robust mode," \
       "\`RTC_SCENE_FLAG_ROBUST\`) on the same scenes and the same pre-generated rays, one tracing" \
       "thread, one after the other in one run. The Cornell box's 17" \
       "shapes are 28 primitives for Embree (its sphere primitive for the spheres, the box as 12" \
       "triangles); the meshes are closed UV spheres whose vertices Perlin noise pushes along the radius," \
       "in a closed room of 12 triangles. Primary rays go through a pinhole camera one a pixel, in" \
       "4×4-pixel blocks (traced one by one, and as one 16-ray packet a block: wsd's" \
       "\`intersect_packet\`, Embree's \`rtcIntersect16\`); shadow rays from each primary hit to a random" \
       "point of a square area light; diffuse rays from each primary hit in a cosine-distributed" \
       "direction about the surface normal (incoherent). Both trace the same float values; secondary" \
       "origins are wsd's error-bounded offsets. Rates are rays per CPU-second, the median of 5 passes" \
       "(3 on the largest mesh) taken in turn." \
       "" "Builds of the meshes. Wall times on a busy machine include waiting for a core, and every build" \
       "includes faulting in its memory (wsd maps its large arrays in 2 MiB pages where the kernel" \
       "allows: render/huge_pages.h); on a VM, a build that is the first to touch memory also waits for" \
       "the host to back it:" \
       "" "| scene | triangles | wsd build, 2 threads: wall (CPU) | wsd bytes/triangle (+ mesh data) | Embree build, 2 threads: wall |" \
       "|---|---:|---:|---:|---:|"
  awk -F'|' '$1 == "build" && $2 != "cornell" { printf "| %s | %d | %.2f s (%.2f s) | %s (+ %s) | %.2f s |\n", $2, $3, $4, $5, $6, $7, $8 }' "$f" >>"$page"
  para "" "| scene | rays | count | wsd M/CPU-s | Embree M/CPU-s | wsd / Embree | wsd per ray: child boxes, triangle tests | rays whose hits differ: why |" \
       "|---|---|---:|---:|---:|---:|---:|---|"
  awk -F'|' '$1 == "row" { printf "| %s | %s | %d | %.2f | %.2f | %s | %s, %s | %d: %s |\n", $2, $3, $7, $4, $5, $6, $11, $12, $8, $9 }' "$f" >>"$page"
  para "" "Child boxes are those of every wide node a ray's walk tests (\`box_tests\`); a packet tests a" \
       "node once for its 16 rays, so its figure is a sixteenth of the packet's."
  embree_baseline_table
  embree_short_of "$f"
  local tol; tol=$(awk '/^Embree/ { for (i = 1; i < NF; i++) if ($i == "tolerance") { v = $(i + 1); sub(/,$/, "", v); print v; exit } }' "$f")
  para "" "A hit agrees when it is on the same primitive (any of a box's triangles counts as the box) at" \
       "distances apart by at most $tol of the scale float arithmetic works at along the ray (the" \
       "distance travelled plus the origin's distance from the world's origin); shadow rays agree when" \
       "both say occluded or both say not. Why they differ: *tie*, two primitives at the same distance" \
       "(a shared edge or vertex); *origin*, one side hits the surface the ray leaves (within 10⁻⁵ of" \
       "the scene's size from its origin); *edge*, the nearer hit lies within $tol of that scale from" \
       "an edge of its triangle or box, which the other side missed; *grazing*, the same for the" \
       "silhouette of a sphere; *t*, the same primitive at distances further apart; *other*, none of" \
       "these. \"Nearer hit\" says whose hit (or occluder) is the nearer or the only one: where it is" \
       "Embree's at the origin, Embree hit the surface the ray leaves; where it is wsd's at an edge," \
       "Embree's ray passed between two triangles that share that edge."
}

# Every row of the default-mode table below 0.8× Embree, named, and what sets the two apart.
embree_short_of() {
  local short robust isa="no AVX-512" walk="baseline x86-64 (this machine has no AVX)" group="two" lanes="SSE2"
  local packet="SSE (4 lanes a group)"
  short=$(awk -F'|' '$1 == "row" && $2 !~ /robust/ && $6 + 0 < 0.8 { printf "%s%s %s (%s)", sep, $2, $3, $6; sep = "; " }' "$1")
  robust=$(awk -F'|' '$1 == "row" && $2 ~ /robust/ { printf "%s%s %s", sep, $3, $6; sep = ", " }' "$1")
  grep -qw avx512f /proc/cpuinfo && isa="AVX-512, which Embree selects at run time (its 16-ray packets then fill one register)"
  if grep -q "wsd's walks: AVX" "$1"; then
    walk="AVX, chosen at run time" group="four" lanes="AVX" packet="AVX too (8 lanes)"
    grep -q "AVX-512 packets" "$1" &&
      packet="AVX too (8 lanes; with AVX-512 a leaf's box against sixteen rays and a triangle against eight at once)"
  fi
  para "" "Below 0.8× Embree in its default mode: ${short:-none}. What sets the two apart on the meshes:" \
       "wsd tests each triangle watertight in double precision ($group triangles a ray, or $group rays a" \
       "triangle, in one $lanes instruction), through a leaf of at most 4 triangles whose vertices are" \
       "shared and looked up by index; Embree's default mode tests four triangles at once in single" \
       "precision, with no watertightness, from leaves that hold each triangle's own vertex data. This" \
       "machine's CPU has $isa. wsd's single-ray walks test a node's eight boxes with $walk;" \
       "its packets test them with $packet and bound the 16 rays by interval arithmetic," \
       "one packet a node, where Embree tests each ray. Each wide node a ray visits costs wsd a" \
       "chain of dependent steps (load the node, test its boxes, choose the lane, load the child's index," \
       "compute its address) whose length wider SIMD does not change. Against Embree's robust mode," \
       "which is watertight too, wsd / Embree on mesh1m is: ${robust:-not measured}."
}

# The million-triangle mesh again, with wsd's walks held to baseline x86-64 tests
# (bench_embree --baseline) where the machine has AVX: what the run-time choice gains.
embree_baseline_table() {
  if ! grep -qw avx /proc/cpuinfo; then
    para "" "wsd's walks test nodes with baseline x86-64 instructions here: this machine has no AVX."
    return 0
  fi
  local args=(); ((quick)) && args=(--quick)
  log "bench_embree ${args[*]} --baseline mesh1m"
  "$build/bench_embree" "${args[@]}" --baseline mesh1m >"$tmp/embree-baseline.txt"
  para "" "The same mesh1m rays with wsd's walks held to baseline x86-64 instructions" \
       "(\`bench_embree --baseline\`: two 4-lane SSE tests a node instead of one 8-lane AVX test," \
       "two triangles (or packet rays) a 2-lane SSE2 test instead of four a 4-lane AVX test;" \
       "the hits are the same), run after the table above:" \
       "" "| scene | rays | count | wsd M/CPU-s | Embree M/CPU-s | wsd / Embree |" "|---|---|---:|---:|---:|---:|"
  awk -F'|' '$1 == "row" { printf "| %s | %s | %d | %.2f | %.2f | %s |\n", $2, $3, $7, $4, $5, $6 }' "$tmp/embree-baseline.txt" >>"$page"
}

# ---------------------------------------------------------------- CSG
csg_table() {
  section "CSG: cost per ray beside the sphere's"
  log "bench_csg"
  "$build/bench_csg" >"$tmp/csg.txt"
  para "\`$build/bench_csg\`: closest-hit queries against one solid filling a 512×512 orthographic grid of" \
       "rays (per CPU-second on one thread), then the grids of bench/scenes/csg_intersection.wsd and" \
       "csg_difference.wsd (100 solids on a plane, one point light) rendered at 400×400 on one thread" \
       "beside the same grid of spheres (CPU time per camera or shadow ray). Each figure is the" \
       "median of 5 passes taken in turn with the others." \
       "" \
       "| solid | closest-hit queries | time per query | × the sphere's |" "|---|---:|---:|---:|"
  awk '/Mrays\/s/ { for (i = 1; i <= NF; i++) if ($i == "Mrays/s") k = i; name = $1;
         for (i = 2; i <= k - 2; i++) name = name " " $i;
         printf "| %s | %s M/CPU-s | %s ns | %s |\n", name, $(k - 1), $(k + 1), $(k + 3) }' "$tmp/csg.txt" >>"$page"
  para "" "| render | time per ray | × the spheres' |" "|---|---:|---:|"
  awk '/ns\/ray .*spheres/ { for (i = 1; i <= NF; i++) if ($i == "ns/ray") k = i; name = $1;
         for (i = 2; i <= k - 2; i++) name = name " " $i;
         printf "| %s | %s ns | %s |\n", name, $(k - 1), $(k + 1) }' "$tmp/csg.txt" >>"$page"
}

# ---------------------------------------------------------------- the new primitives
primitives_table() {
  section "Cylinders, cones, tori and discs: cost per ray beside the sphere's"
  log "bench/primitives.sh $build $runs"
  bench/primitives.sh "$build" "$runs" >"$tmp/primitives.txt"
  para "\`bench/primitives.sh $build $runs\`: bench/scenes/{sphere, cylinder, cone, torus, disc}.wsd — the same" \
       "framing, light and material, a 10×10 grid of one primitive on a plane — rendered on one thread," \
       "the scenes taken in turn; the median render time of $runs $( ((runs == 1)) && echo run || echo runs), the ray queries" \
       "(camera and shadow rays) and the time per query relative to the sphere scene's." ""
  cat "$tmp/primitives.txt" >>"$page"
}

# ---------------------------------------------------------------- instances
instances_table() {
  section "Instances: one mesh stored, a thousand placed"
  local cols=${inst_grid[0]} rows=${inst_grid[1]} slices=${inst_sphere[0]} stacks=${inst_sphere[1]}
  local w=${inst_size[0]} h=${inst_size[1]} n=$((inst_grid[0] * inst_grid[1]))
  local tris=$((2 * slices * (stacks - 2)))
  log "instances: a $tris-triangle mesh, $n instances, ${w}×${h}"
  # A UV sphere of 2·slices·(stacks − 2) triangles: quads split in two, one triangle each at the
  # poles (whose rows of vertices coincide).
  awk -v S="$slices" -v T="$stacks" 'BEGIN {
      pi = atan2(0, -1)
      for (j = 0; j < T; j++) for (i = 0; i < S; i++) {
        th = pi * j / (T - 1); ph = 2 * pi * i / S
        printf "v %.6f %.6f %.6f\n", sin(th) * cos(ph), cos(th), sin(th) * sin(ph) }
      for (j = 0; j < T - 1; j++) for (i = 0; i < S; i++) {
        a = j * S + i + 1; b = j * S + (i + 1) % S + 1; c = a + S; d = b + S
        if (j > 0) printf "f %d %d %d\n", a, c, b
        if (j < T - 2) printf "f %d %d %d\n", b, c, d } }' >"$tmp/ball.obj"
  local head="settings { width $w  height $h }
camera { position <$((cols)), 9, -12>  look_at <$((cols)), 0, $((rows))>  fov 60 }
light point { position <0, 40, -20> }
let skin = material { color <0.8, 0.5, 0.3>  specular 0.4 }"
  printf '%s\nmesh { file "ball.obj"  translate <%d, 0, %d>  material skin }\n' "$head" "$cols" "$rows" >"$tmp/one.wsd"
  printf '%s\nlet ball = mesh { file "ball.obj" }\nfor i in 0 .. %d { for j in 0 .. %d { object ball { translate <2 * i, 0, 2 * j>  material skin } } }\n' \
    "$head" "$cols" "$rows" >"$tmp/many.wsd"
  local k
  for k in one many; do
    "$wsd" check "$tmp/$k.wsd" >"$tmp/$k.check" 2>/dev/null
    /usr/bin/time -f '%e %U %S %M' -o "$tmp/$k.time" "$wsd" render "$tmp/$k.wsd" -o "$tmp/$k.png" -q \
      --stats-json "$tmp/$k.json" >/dev/null 2>&1
  done
  json() { python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))
def find(d, k):
    if isinstance(d, dict):
        if k in d: return d[k]
        for v in d.values():
            x = find(v, k)
            if x is not None: return x
print(find(d, sys.argv[2]))' "$1" "$2"; }
  row() {  # row NAME FILE-STEM
    local t; t=($(cat "$tmp/$2.time"))
    para "| $1 | $(sed 's/^[^—]*— //' "$tmp/$2.check") | $(fmt "${t[0]}") s | $(fmt "$(awk -v u="${t[1]}" -v s="${t[2]}" 'BEGIN { print u + s }')") s | $(fmt "$(json "$tmp/$2.json" render_seconds)") s | $(awk -v k="${t[3]}" 'BEGIN { printf "%.0f", k / 1024 }') MiB |"
  }
  para "A closed mesh of $(commas "$tris") triangles (a UV sphere written as OBJ), rendered once as a" \
       "\`mesh\` and $n times as \`object\` instances of one \`let\` value in a $cols × $rows grid, each at" \
       "${w}×${h}, one camera ray a pixel, one point light, on $(nproc) threads: \`wsd check\`'s counts, the" \
       "whole run's wall and CPU time (loading, BVH builds and rendering) and the render alone, and the" \
       "peak resident memory (\`/usr/bin/time\`). A flat copy of the instanced scene would hold" \
       "$(commas $((n * tris))) triangles (about 80 bytes each with their BVH)." \
       "" "| scene | \`wsd check\` | wall | CPU | render | peak memory |" "|---|---|---:|---:|---:|---:|"
  row "one mesh" one
  row "$n instances" many
}

# ---------------------------------------------------------------- scenes that ask for none of it
baseline_table() {
  [[ -n $baseline ]] || return 0
  section "Scenes without the new features: old and new builds"
  local f name i same=0 total=0 old new
  : >"$tmp/base.txt"
  for f in examples/*.wsd; do
    name=$(basename "$f" .wsd)
    # Only scenes the older build can read: the new examples use what it does not have.
    "$baseline" check "$f" >/dev/null 2>&1 || continue
    total=$((total + 1))
    for ((i = 0; i < runs; i++)); do
      for exe in "$baseline" "$wsd"; do
        local tag=new; [[ $exe == "$baseline" ]] && tag=old
        (cd examples && /usr/bin/time -f '%U %S' -o "$tmp/$name.$tag.$i.time" "$exe" render "$name.wsd" \
          -o "$tmp/$name.$tag.pfm" --width 320 --height 240 --threads 1 -q >/dev/null 2>&1)
      done
    done
    cmp -s "$tmp/$name.old.pfm" "$tmp/$name.new.pfm" && same=$((same + 1))
    old=$(cat "$tmp/$name".old.*.time | awk '{ print $1 + $2 }' | median)
    new=$(cat "$tmp/$name".new.*.time | awk '{ print $1 + $2 }' | median)
    printf '| %s | %s | %s s | %s s | %s |\n' "$name" \
      "$(cmp -s "$tmp/$name.old.pfm" "$tmp/$name.new.pfm" && echo yes || echo NO)" \
      "$(fmt "$old")" "$(fmt "$new")" "$(ratio "$new" "$old")" >>"$tmp/base.txt"
  done
  para "Every example the older build (\`$baseline_shown\`, $("$baseline" --version 2>/dev/null | head -1 || echo "an older build")) can read, rendered by it and by this build" \
       "at 320×240 on one thread, the two taken in turn, $runs $( ((runs == 1)) && echo time || echo times) each: whether the float images (\`.pfm\`) are" \
       "byte-identical ($same of $total are), and the median CPU time of each." \
       "" "| scene | identical | old CPU | new CPU | new / old |" "|---|:---:|---:|---:|---:|"
  cat "$tmp/base.txt" >>"$page"
}

# ---------------------------------------------------------------- parsing and loading
# mesh_row REGEX TITLE: a table row for the bench_obj line matching REGEX (size, wall, CPU, MB/s).
mesh_row() {
  awk -v t="$2" "/$1/"' {
    for (i = 1; i <= NF; i++) { if ($i == "MB") mb = $(i - 1); if ($i == "median") wall = $(i + 1); if ($i == "CPU") cpu = $(i - 2) }
    printf "| %s, %s MB | %s s wall, %s s CPU, %.0f MB/s |\n", t, mb, wall, cpu, mb / cpu; exit }' "$tmp/obj.txt"
}
parse_table() {
  section "Parsing and loading"
  local i
  log "bench_parse ${parse_args[*]}, $runs run(s); bench_obj"
  for ((i = 0; i < runs; i++)); do "$build/bench_parse" "${parse_args[@]}" >"$tmp/parse-$i.txt"; done
  "$build/bench_obj" >"$tmp/obj.txt"
  local mb tris
  mb=$(field "$tmp/parse-0.txt" '^mesh.wsd +lex' 3)
  tris=$(awk '/^mesh.wsd +load_scene/ { for (i = 1; i < NF; i++) if ($(i + 1) == "triangles") print $i; exit }' "$tmp/parse-0.txt")
  # all REGEX N: the Nth field of the matching line of every run.
  all() { cat "$tmp"/parse-*.txt | awk -v n="$2" "/$1/ { print \$n }"; }
  para "\`$build/bench_parse${parse_args:+ ${parse_args[*]}}\` ($runs $( ((runs == 1)) && echo run || echo runs); median and range of one pass each, wall time):" \
       "an inline mesh of $(commas "$tris") triangles ($mb MB of \`.wsd\` text), and a 100,000-sphere \`for\` loop." \
       "\`$build/bench_obj\`: one 1,000,000-triangle grid written as two OBJ and two PLY files, the median of 3 loads" \
       "(MB/s per CPU-second: the file's size over the load's CPU time, one thread)." \
       "" \
       "| figure | measured |" "|---|---:|" \
       "| inline mesh, lex + parse | $(all '^mesh.wsd +lex' 7 | median) MB/s ($(all '^mesh.wsd +lex' 7 | range)) |" \
       "| inline mesh, whole scene load (no BVH) | $(all '^mesh.wsd +load_scene' 7 | median) MB/s ($(all '^mesh.wsd +load_scene' 7 | range)) |" \
       "| peak memory per triangle, source text included (lex + parse / load) | $(all '^mesh.wsd +lex' 10 | median) / $(all '^mesh.wsd +load_scene' 15 | median) bytes |" \
       "| 100,000-sphere \`for\` loop, whole scene load | $(all '^spheres.wsd +load_scene' 5 | median) s ($(all '^spheres.wsd +load_scene' 5 | range)) |" \
       "$(mesh_row '^f v ' 'OBJ `f a b c`')" \
       "$(mesh_row '^f v\/vt' 'OBJ `f a/a/a` with `vt` and `vn`')" \
       "$(mesh_row '^ply ascii' 'PLY, ASCII')" \
       "$(mesh_row '^ply binary' 'PLY, binary little-endian')"
}

lsp_table() {
  section "Language server"
  local lsp_args=(--runs 5) label="about 1,000,000"
  ((quick)) && lsp_args=(--runs 1 --triangles 20000) && label="about 20,000"
  log "bench/lsp_latency.py ${lsp_args[*]}"
  python3 bench/lsp_latency.py "$wsd" "${lsp_args[@]}" >"$tmp/lsp.txt"
  # row NAME: the figures of one scene's line.
  row() {
    awk -v n="$1" '$1 == n { for (i = 1; i < NF; i++) v[$i] = $(i + 1)
      printf "| `%s`%s | %s MB | %s ms | %s ms (%s ms) |\n", n, ($2 == "-" ? "" : ", inline mesh of " $2 " triangles"), $4,
             v["didOpen"], v["median"], v["range"] }' "$tmp/lsp.txt"
  }
  para "\`bench/lsp_latency.py\`: \`wsd lsp\` driven over a pipe; the time from sending \`textDocument/didChange\`" \
       "(the whole text, one comment changed) to receiving that version's \`publishDiagnostics\`, which runs the" \
       "whole check of \`wsd check\` (parse, evaluate, build) on the unsaved text; median and range over" \
       "$(awk '{ for (i = 1; i < NF; i++) if ($i == "runs") { print $(i + 1); exit } }' "$tmp/lsp.txt") change(s)." \
       "The inline mesh ($label triangles) is generated." \
       "" \
       "| scene | text | didOpen to diagnostics | didChange to diagnostics, median (range) |" "|---|---:|---:|---:|" \
       "$(row cornell.wsd)" "$(row mesh.wsd)"
}

# ---------------------------------------------------------------- live preview
preview_table() {
  section "Live preview: from saving a file to new pixels"
  local edits=$( ((quick)) && echo 3 || echo 9)
  log "bench/preview_latency.sh $build/wsd examples/cornell.wsd $edits"
  bench/preview_latency.sh "$build/wsd" examples/cornell.wsd "$edits" >"$tmp/preview.txt"
  para "\`bench/preview_latency.sh $build/wsd examples/cornell.wsd $edits\`: \`wsd preview\` on a copy of the Cornell box;" \
       "$edits saves of the scene file (a colour changed), each while the previous render still refines; the time from" \
       "the write to the save being noticed (the \`loading\` event) and to the first image of the new render" \
       "(the coarse first stage: reload, build, render, PNG) fetched by a client of the page's event stream." \
       "" "| figure | measured |" "|---|---:|" \
       "| save noticed, median | $(awk '/^median:/ { print $3; exit }' "$tmp/preview.txt") s |" \
       "| first new pixels, median (range) | $(awk '/^median:/ { print $8, $9, $10, $11; exit }' "$tmp/preview.txt" | tr -d ')' | sed 's/ s (range / s (/; s/$/)/') |" \
       "| the image first shown | stage $(awk '/^edit 1:/ { print $11, $12; exit }' "$tmp/preview.txt" | tr -d ',' | sed 's/ /, /') pixels |"
}

# ---------------------------------------------------------------- the page
sections=(cornell caustics adaptive bench honesty targeted indirect threads mesh embree primitives csg instances baseline parse lsp preview)
for name in ${only//,/ }; do
  [[ " ${sections[*]} " == *" $name "* ]] || { echo "performance: no section '$name' (${sections[*]})" >&2; exit 2; }
done
for current in "${sections[@]}"; do
  if [[ -z $only || ",$only," == *",$current,"* ]]; then "${current}_table"; fi
done
load_after=$(loadavg)

model=$(cpu_model)
compiler=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt" 2>/dev/null | head -1)
compiler_version=$("${compiler:-c++}" --version 2>/dev/null | head -1 || true)
build_type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$build/CMakeCache.txt" 2>/dev/null | head -1)
os=$(. /etc/os-release 2>/dev/null && echo "${PRETTY_NAME:-}")
memory=$(awk '/^MemTotal:/ { printf "%.1f GiB", $2 / 1048576 }' /proc/meminfo)
elapsed=$(($(date +%s) - start))
# CPU time of this script and everything it ran (the second line of `times`: children).
times >"$tmp/times"  # in this shell: a command substitution would time only its own subshell
cpu=$(awk 'NR == 2 { for (i = 1; i <= 2; i++) { split($i, t, /[ms]/); s += 60 * t[1] + t[2] } printf "%d min %d s", s / 60, s % 60 }' "$tmp/times")
{
  echo "# Performance"
  echo
  echo "Measured by \`bench/performance.sh$( ((quick)) && echo " --quick")\` on $(date -u '+%Y-%m-%d %H:%M UTC') ($((elapsed / 60)) min $((elapsed % 60)) s of wall"
  echo "time, $cpu of CPU time); every figure on this page is what that run printed. To measure"
  echo "again on your machine: \`./setup.sh && bench/performance.sh\` (the page is rewritten)."
  echo
  echo "- Machine: ${model:-unknown processor}, $(nproc) cores (\`nproc\`), $memory memory; ${os:-unknown system}."
  echo "- Build: ${build_type:-unknown} (\`$build/\`), ${compiler_version:-unknown compiler}, commit \`$commit\`."
  echo "- Load average (1, 5, 15 min) before the run: $load_before; after: $load_after. On a shared machine"
  echo "  wall times include waiting for a core: compare CPU-seconds, and ratios measured in the same run."
  cat "$page"
} >"$out.tmp"
if [[ -n $only && -f $out ]]; then
  # Replace the measured sections (by their "## " title) in the existing page; new ones go last.
  python3 - "$out" "$page" >"$out.tmp" <<'PY'
import re, sys
def split(text):
    parts = re.split(r"(?m)^(?=## )", text)
    return parts[0], [(p.split("\n", 1)[0], p) for p in parts[1:]]
head, old = split(open(sys.argv[1]).read())
_, new = split(open(sys.argv[2]).read())
note = ("Sections that begin \"Measured on its own\" were measured later, by `--only`, each at the"
        " date and load it states; the rest by the run above.\n")
if note not in head:
    head = head.rstrip("\n") + "\n\n" + note
head = head.rstrip("\n") + "\n\n"
fresh = dict(new)
bodies = [fresh.pop(title, body) for title, body in old]
bodies += [body for title, body in new if title in fresh]
# Every section ends in one blank line, wherever the page's split left its newlines.
sys.stdout.write(head + "".join(b.rstrip("\n") + "\n\n" for b in bodies).rstrip("\n") + "\n")
PY
fi
mv "$out.tmp" "$out"
log "wrote $out in ${elapsed} s"
