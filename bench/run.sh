#!/usr/bin/env bash
# bench/run.sh [--quick | --smoke [--record]] [--build-dir DIR]: kiln against LAMMPS and LIGGGHTS
# on the pile of shared/BENCH.md, every code on the same settled pile, in one run on this machine.
#
#   bench/run.sh           the full run (about an hour on 2 cores): 1,000, 10,000 and 100,000 discs
#                          resting, 10,000 flowing, heat (LIGGGHTS' fix heat/gran/conduction),
#                          ARKODE, 2 threads on 100,000, 100,000 numbered at random (mixed);
#                          5 alternating pairs (3 at 100,000)
#   bench/run.sh --quick   the same figures from fewer steps and repeats, in under 10 minutes
#   bench/run.sh --smoke   the guard against a regression, under a minute after the build: the
#                          1,000-disc pile, kiln and LAMMPS alternately (9 pairs of 10,000 steps), and the ratio
#                          kiln/LAMMPS against the one recorded in bench/baseline.json at the last
#                          release. One line; exit 1 when it is below 0.9 of the baseline's.
#   --record               with --smoke: write the measured ratio to bench/baseline.json (a release)
#   --kiln BINARY          time this kiln binary instead of building one (an earlier release's;
#                          BENCH_COMMIT=<commit> names it in a recorded baseline)
#   --build-dir DIR        kiln's build directory (default build, or $KILN_BUILD_DIR): configured
#                          and built as Release here if needed
#
# It installs the peers from Debian if they are missing (lammps, liggghts, and time for
# /usr/bin/time -v), builds kiln, builds the piles once into bench/out/piles/ (kiln settles the
# 1,000 and 10,000 piles, `kiln bench --write-pile`; LAMMPS replicates the 10,000 pile ten times
# in x, bench/in.replicate; delete the directory to settle them again), then runs kiln and the
# peers alternately, one after the other, repeat by repeat (bench/in.lammps, bench/in.liggghts),
# with OMP_NUM_THREADS=1 except kiln's 2-thread runs. It prints a table of every
# (code, model, N), the goal ratios (each from runs of this invocation, pair by pair), and as its
# last line `ratio kiln/LAMMPS particle-steps/s: X.XX at N=10000`. Raw numbers of every run:
# bench/out/runs-<time>.csv; every run's output: bench/out/logs-<time>/.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
quick=0
smoke=0
record=0
kiln_given=""
build=${KILN_BUILD_DIR:-$root/build}
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    --smoke) smoke=1 ;;
    --record) record=1 ;;
    --kiln) [ $# -ge 2 ] || { echo "--kiln needs a binary" >&2; exit 2; }; kiln_given=$2; shift ;;
    --build-dir) [ $# -ge 2 ] || { echo "--build-dir needs a directory" >&2; exit 2; }; build=$2; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "unknown argument '$1'; usage: bench/run.sh [--quick | --smoke [--record]] [--build-dir DIR | --kiln BINARY]" >&2; exit 2 ;;
  esac
  shift
done
case $build in /*) ;; *) build=$root/$build ;; esac
[ $record = 0 ] || [ $smoke = 1 ] || { echo "--record goes with --smoke" >&2; exit 2; }
if [ -n "$kiln_given" ]; then
  [ -x "$kiln_given" ] && [ -f "$kiln_given" ] || { echo "error: --kiln $kiln_given is not an executable file" >&2; exit 2; }
  [ "$build" = "${KILN_BUILD_DIR:-$root/build}" ] || { echo "--kiln and --build-dir are two ways to name kiln: choose one" >&2; exit 2; }
fi
if [ $smoke = 1 ] && [ $record = 0 ] && [ ! -s "$here/baseline.json" ]; then
  echo "error: no $here/baseline.json to compare with: record one with --smoke --record (a release's figure)" >&2
  exit 2
fi
[ $quick = 0 ] || [ $smoke = 0 ] || { echo "--quick and --smoke are different runs: choose one" >&2; exit 2; }

started=$(date +%s)
stamp=$(date +%Y%m%d-%H%M%S)
out=$here/out
piles=$out/piles
logs=$out/logs-$stamp
csv=$out/runs-$stamp.csv
mkdir -p "$piles" "$logs"

# ---- the peers and /usr/bin/time, from Debian if missing ----
missing=()
command -v lmp >/dev/null || missing+=(lammps)
command -v liggghts >/dev/null || missing+=(liggghts)
[ -x /usr/bin/time ] || missing+=(time)
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing from Debian: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null ||
    echo "warning: could not install ${missing[*]}" >&2
fi
command -v lmp >/dev/null || { echo "error: LAMMPS (lmp) is needed: apt-get install lammps" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "error: /usr/bin/time is needed: apt-get install time" >&2; exit 1; }
have_liggghts=0
command -v liggghts >/dev/null && have_liggghts=1
[ $have_liggghts = 1 ] || echo "warning: no LIGGGHTS: its rows and ratios are left out" >&2

# ---- kiln, a Release build (or the binary given) ----
if [ -n "$kiln_given" ]; then
  kiln=$(cd "$(dirname "$kiln_given")" && pwd)/$(basename "$kiln_given")
else
  if [ ! -f "$build/CMakeCache.txt" ]; then
    echo "configuring kiln in $build (Release)"
    cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  fi
  grep -q '^CMAKE_BUILD_TYPE:STRING=Release$' "$build/CMakeCache.txt" ||
    { echo "error: $build is not a Release build: timings of it would mean nothing (use --build-dir)" >&2; exit 1; }
  if grep -q '^KILN_SANITIZE:BOOL=ON$' "$build/CMakeCache.txt"; then
    echo "error: $build is built with the sanitizers (use --build-dir)" >&2; exit 1
  fi
  echo "building kiln in $build"
  cmake --build "$build" --target kiln >"$logs/build.log" 2>&1 ||
    { tail -n 30 "$logs/build.log"; echo "error: kiln did not build: see $logs/build.log" >&2; exit 1; }
  kiln=$build/kiln
fi

# ---- the piles, once ----
pile() {  # pile COLUMNS FILE: kiln settles 50 rows x COLUMNS and writes the pile
  if [ -s "$2" ]; then echo "pile: reusing $2"; return; fi
  echo "pile: settling 50 x $1 discs with kiln (0.24 s of simulated time, not timed)"
  OMP_NUM_THREADS=1 "$kiln" bench --write-pile "$2" --columns "$1"
}
pile 20 "$piles/pile_1k.data"
if [ $smoke = 1 ]; then
  smoke_started=$(date +%s)
  # What the recorded figure is of: this tree's commit, or for --kiln what BENCH_COMMIT says.
  commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)
  [ -z "$kiln_given" ] || commit=${BENCH_COMMIT:-"binary $(basename "$kiln_given")"}
  echo "repeat,kiln_rate,lammps_rate" >"$csv"
  for repeat in $(seq 9); do
    OMP_NUM_THREADS=1 "$kiln" bench --pile "$piles/pile_1k.data" --steps 10000 --warmup 500 >"$logs/kiln-$repeat.log" 2>&1 ||
      { tail -n 15 "$logs/kiln-$repeat.log"; exit 1; }
    OMP_NUM_THREADS=1 lmp -in "$here/in.lammps" -var pile "$piles/pile_1k.data" -var warmup 500 -var steps 10000 \
      -var gx 0 -var gy -1 -log none >"$logs/lammps-$repeat.log" 2>&1 || { tail -n 15 "$logs/lammps-$repeat.log"; exit 1; }
    k=$(sed -n 's/^kiln-bench: .* particle_steps_per_s=\([^ ]*\).*/\1/p' "$logs/kiln-$repeat.log")
    l=$(awk '/^Loop time of/ && $9 == 10000 { printf "%.6g\n", $12 * 10000 / $4 }' "$logs/lammps-$repeat.log")
    [ -n "$k" ] && [ -n "$l" ] || { echo "error: no particle-steps/s in $logs/kiln-$repeat.log or $logs/lammps-$repeat.log" >&2; exit 1; }
    echo "$repeat,$k,$l" >>"$csv"
  done
  python3 - "$csv" "$here/baseline.json" "$record" "$commit" \
    "$(($(date +%s) - smoke_started))" <<'PY'
import csv, datetime, json, os, platform, statistics, sys
runs, baseline_path, record, commit, seconds = sys.argv[1], sys.argv[2], sys.argv[3] == "1", sys.argv[4], sys.argv[5]
rows = list(csv.DictReader(open(runs)))
ratios = [float(r["kiln_rate"]) / float(r["lammps_rate"]) for r in rows]
ratio = statistics.median(ratios)
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), platform.machine())
if record:
    json.dump({"kiln_per_lammps_1000": round(ratio, 3), "pairs": len(ratios), "pair_range": [round(min(ratios), 3), round(max(ratios), 3)],
               "commit": commit, "date": datetime.date.today().isoformat(), "machine": f"{cpu}, {os.cpu_count()} cores"},
              open(baseline_path + ".tmp", "w"), indent=2)
    os.replace(baseline_path + ".tmp", baseline_path)
base = json.load(open(baseline_path))
against = ratio / base["kiln_per_lammps_1000"]
print(f"smoke: kiln/LAMMPS particle-steps/s {ratio:.2f} at N=1000 (median of {len(ratios)} alternating pairs, "
      f"{min(ratios):.2f}-{max(ratios):.2f}, {seconds} s); baseline {base['kiln_per_lammps_1000']:.2f} "
      f"(kiln {base['commit']}, {base['date']}): {against:.2f}x the baseline" + (" (recorded now)" if record else ""))
sys.exit(0 if against >= 0.9 else 1)
PY
  exit $?
fi
pile 200 "$piles/pile_10k.data"
if [ -s "$piles/pile_100k.data" ]; then
  echo "pile: reusing $piles/pile_100k.data"
else
  echo "pile: ten periodic copies in x of the 10,000 pile, by LAMMPS (replicate 10 1 1, write_data)"
  OMP_NUM_THREADS=1 lmp -in "$here/in.replicate" -var pile "$piles/pile_10k.data" -var copies 10 \
    -var out "$piles/pile_100k.data" -log none >"$logs/replicate.log" 2>&1 ||
    { echo "error: LAMMPS could not replicate the pile: see $logs/replicate.log" >&2; exit 1; }
fi
# LIGGGHTS in 2D takes a disc's mass as rho pi r^2: a density of rho 4/3 r gives the sphere's mass
# 4/3 pi r^3 rho (column 3 of an Atoms line is the diameter, column 4 the density).
liggghts_pile() {
  awk '/^Atoms/ { atoms = 1; print; next } /^Velocities/ { atoms = 0 }
       atoms && NF >= 7 { $4 = sprintf("%.17g", $4 * 2 / 3 * $3) } { print }' "$1" >"$2"
}
# The 100,000 pile numbered at random: a pile whose particles have mixed after flowing a while.
[ -s "$piles/pile_100k_mixed.data" ] || python3 "$here/shuffle_pile.py" "$piles/pile_100k.data" "$piles/pile_100k_mixed.data" 1
if [ $have_liggghts = 1 ]; then liggghts_pile "$piles/pile_10k.data" "$piles/pile_10k_liggghts.data"; fi
middle_x() { awk '/xlo xhi/ { printf "%.17g\n", ($1 + $2) / 2; exit }' "$1"; }

# ---- runs ----
echo "group,repeat,code,model,integrator,n,steps,warmup,threads,loop_s,rhs_evals,peak_rss_mb,run_rss_mb,contacts_per_disc,rebuild_ns_per_disc,log" >"$csv"
count=0
group=""
repeat=0

# record CODE MODEL INTEGRATOR N STEPS WARMUP THREADS -- COMMAND...: runs it under /usr/bin/time -v
# and appends its figures to the CSV.
record() {
  local code=$1 model=$2 integrator=$3 n=$4 steps=$5 warmup=$6 threads=$7
  shift 8
  count=$((count + 1))
  local name=$code-$model
  [ "$integrator" = velocity-verlet ] || name=$name-$integrator
  [ "$threads" = 1 ] || name=$name-${threads}threads
  local log=$logs/$(printf '%03d' $count)-$name-$n.log
  printf '  %-8s %-8s %-8s N=%-6s %6s steps, %s thread(s): ' "$code" "$model" "$integrator" "$n" "$steps" "$threads"
  if ! OMP_NUM_THREADS=$threads /usr/bin/time -v -o "$log.time" "$@" >"$log" 2>&1; then
    echo "failed; the end of $log:"
    tail -n 15 "$log"
    exit 1
  fi
  local loop rhs contacts rebuild rss run_rss=""
  # Peak RSS: /usr/bin/time's, except kiln's own figures: kiln bench starts the resident
  # high-water mark again after its stability estimate (to read the run's own peak apart), which
  # starts what /usr/bin/time sees again too; its peak_rss_mb is the larger of the two parts'.
  rss=$(awk -F': ' '/Maximum resident set size/ { printf "%.2f", $2 / 1024 }' "$log.time")
  if [ "$code" = kiln ]; then
    rss=$(sed -n 's/^kiln-bench: .* peak_rss_mb=\([^ ]*\).*/\1/p' "$log")
    run_rss=$(sed -n 's/^kiln-bench: .* run_rss_mb=\([^ ]*\).*/\1/p' "$log")
    loop=$(sed -n 's/^kiln-bench: .* loop_s=\([^ ]*\).*/\1/p' "$log")
    rhs=$(sed -n 's/^kiln-bench: .* rhs_evals=\([^ ]*\).*/\1/p' "$log")
    contacts=$(sed -n 's/^kiln-bench: .* contacts_per_disc=\([^ ]*\).*/\1/p' "$log")
    rebuild=$(sed -n 's/^kiln-bench: .* rebuild_ns_per_disc=\([^ ]*\).*/\1/p' "$log")
  else
    # "Loop time of X on 1 procs for N steps ...": the timed run is the last one.
    loop=$(awk -v steps="$steps" '/^Loop time of/ && $9 == steps { t = $4 } END { print t }' "$log")
    rhs=$steps
    contacts=$(sed -n 's/^lammps-contacts-per-disc: *//p' "$log")
    # A build's cost per disc: the timed run's "Neigh | T" over its "Neighbor list builds = B".
    rebuild=$(awk -v n="$n" '/^Neigh +\|/ { t = $3 } /^Neighbor list builds =/ { b = $5 }
                             END { if (b > 0) printf "%.1f\n", 1e9 * t / b / n }' "$log")
  fi
  [ -n "$loop" ] || { echo "no loop time for $steps steps in $log"; exit 1; }
  echo "$group,$repeat,$code,$model,$integrator,$n,$steps,$warmup,$threads,$loop,$rhs,$rss,$run_rss,$contacts,$rebuild,$log" >>"$csv"
  awk -v l="$loop" -v n="$n" -v s="$steps" -v r="$rss" \
    'BEGIN { printf "%.2f s, %.3g particle-steps/s, %.0f MB\n", l, n * s / l, r }'
}

kiln_run() {  # kiln_run MODEL N PILE STEPS WARMUP THREADS [OPTIONS...]
  local model=$1 n=$2 file=$3 steps=$4 warmup=$5 threads=$6
  shift 6
  local integrator=velocity-verlet
  [ "${1:-}" = --integrator ] && integrator=$2
  record kiln "$model" "$integrator" "$n" "$steps" "$warmup" "$threads" -- \
    "$kiln" bench --pile "$file" --steps "$steps" --warmup "$warmup" "$@"
}
lammps_run() {  # lammps_run MODEL N PILE STEPS WARMUP GX GY
  record LAMMPS "$1" velocity-verlet "$2" "$4" "$5" 1 -- \
    lmp -in "$here/in.lammps" -var pile "$3" -var warmup "$5" -var steps "$4" -var gx "$6" -var gy "$7" -log none
}
liggghts_run() {  # liggghts_run MODEL N PILE STEPS WARMUP THERMAL(0/1)
  [ $have_liggghts = 1 ] || return 0
  # stdbuf: LIGGGHTS' output reaches the log even when MPI aborts it.
  record LIGGGHTS "$1" velocity-verlet "$2" "$4" "$5" 1 -- \
    stdbuf -oL liggghts -in "$here/in.liggghts" -var pile "$3" -var warmup "$5" -var steps "$4" \
    -var gx 0 -var gy -1 -var thermal "$6" -var xmid "$(middle_x "$3")" -log none
}

start_group() {  # start_group NAME DESCRIPTION
  group=$1
  echo
  echo "== $2"
}

if [ $quick = 1 ]; then
  pairs_small=3 steps_small=10000 warm_small=2000
  pairs_10k=3 steps_10k=8000 warm_10k=2000
  pairs_flow=1 steps_flow=5000 warm_flow=1000
  pairs_cost=2 steps_cost=4000 warm_cost=1000 steps_erk=1000 warm_erk=500
  pairs_100k=1 steps_100k=1000 warm_100k=500
else
  pairs_small=5 steps_small=20000 warm_small=5000
  pairs_10k=5 steps_10k=20000 warm_10k=5000
  pairs_flow=5 steps_flow=20000 warm_flow=5000
  pairs_cost=3 steps_cost=20000 warm_cost=5000 steps_erk=5000 warm_erk=1000
  pairs_100k=3 steps_100k=5000 warm_100k=5000
fi
p1k=$piles/pile_1k.data p10k=$piles/pile_10k.data p100k=$piles/pile_100k.data
p10k_lig=$piles/pile_10k_liggghts.data
cos30=0.8660254037844386

start_group small "1,000 discs, resting: kiln and LAMMPS alternately"
for repeat in $(seq "$pairs_small"); do
  kiln_run resting 1000 "$p1k" "$steps_small" "$warm_small" 1
  lammps_run resting 1000 "$p1k" "$steps_small" "$warm_small" 0 -1
done

start_group resting "10,000 discs, resting: kiln, LAMMPS and LIGGGHTS alternately"
for repeat in $(seq "$pairs_10k"); do
  kiln_run resting 10000 "$p10k" "$steps_10k" "$warm_10k" 1
  lammps_run resting 10000 "$p10k" "$steps_10k" "$warm_10k" 0 -1
  liggghts_run resting 10000 "$p10k_lig" "$steps_10k" "$warm_10k" 0
done

start_group flowing "10,000 discs, flowing (gravity tilted 30 degrees toward +x)"
for repeat in $(seq "$pairs_flow"); do
  kiln_run flowing 10000 "$p10k" "$steps_flow" "$warm_flow" 1 --flowing
  lammps_run flowing 10000 "$p10k" "$steps_flow" "$warm_flow" 0.5 -$cos30
done

start_group cost "10,000 discs: what heat and an ARKODE right-hand side cost"
for repeat in $(seq "$pairs_cost"); do
  kiln_run resting 10000 "$p10k" "$steps_cost" "$warm_cost" 1
  kiln_run thermal 10000 "$p10k" "$steps_cost" "$warm_cost" 1 --thermal
  kiln_run resting 10000 "$p10k" "$steps_erk" "$warm_erk" 1 --integrator erk2
  liggghts_run resting 10000 "$p10k_lig" "$steps_cost" "$warm_cost" 0
  liggghts_run thermal 10000 "$p10k_lig" "$steps_cost" "$warm_cost" 1
done

start_group large "100,000 discs, resting: kiln on 1 thread, LAMMPS, kiln on 2 threads"
for repeat in $(seq "$pairs_100k"); do
  kiln_run resting 100000 "$p100k" "$steps_100k" "$warm_100k" 1
  lammps_run resting 100000 "$p100k" "$steps_100k" "$warm_100k" 0 -1
  kiln_run resting 100000 "$p100k" "$steps_100k" "$warm_100k" 2
done

start_group mixed "100,000 discs, resting, numbered at random (as after flowing a while): kiln, LAMMPS"
for repeat in $(seq "$pairs_100k"); do
  kiln_run mixed 100000 "$piles/pile_100k_mixed.data" "$steps_100k" "$warm_100k" 1
  lammps_run mixed 100000 "$piles/pile_100k_mixed.data" "$steps_100k" "$warm_100k" 0 -1
done

echo
echo "raw figures: $csv"
echo "total time: $(($(date +%s) - started)) s"
echo
python3 "$here/report.py" "$csv"
