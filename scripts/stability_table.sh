#!/bin/sh
# Measures where each integrator goes unstable on a set of scenes and sets it beside the limit
# `kiln check` prints: the README's stability table, written to docs/stability_table.md.
#
#   scripts/stability_table.sh [BUILD_DIR] [INTEGRATORS] [ROWS]
#
# BUILD_DIR defaults to build. INTEGRATORS is a comma list (default: one of each family of the
# verification matrix: the three Verlet schemes, erk2 (Heun-Euler), erk3 (Bogacki-Shampine), erk4
# (Zonneveld), erk5 (Dormand-Prince), erk6 (Verner), imex3 and imex4 (ARK324L2SA, ARK436L2SA)).
# ROWS is a comma list of the row names below (default all).
#
# Per row: the limit `kiln check --json` prints for the integrator (the smaller of the contacts'
# and conduction's, and the mode that binds) sets the range of `kiln sweep`, 0.25x to 2x (a
# settled network can bind at half the start's), seven log-spaced steps, whose bisection between the largest stable and the smallest unstable step
# gives the measured boundary (to 1e-3 relative). A run is unstable when its guard stops it
# (energy balance, dissipation, travel, a non-finite state). The printed limit is the sweep's: the
# start's joined with the limit on its finest run's end state (a settled column's network), and
# where a tangential-rotational or rolling mode binds, the blow-up limit of the normal modes
# beside it. One process at a time.
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build="$here/$build" ;; esac
integrators=${2:-verlet,velocity-verlet,velocity-verlet-predicted,erk2,erk3,erk4,erk5,erk6,imex3,imex4}
selected=${3:-}
slope="$here/../shared/handed-cases/rolling_incline_rest.yaml"
# row name | scene file | sets (';' separated) | t_end (empty: the scene's)
rows="slope-constant-rolling|$slope||0.3
slope-epsd-rolling|$slope|rolling_model=epsd|0.3
slope-no-tangential-dashpot|$slope|contacts=[{between: [copper, plate], tangential_damping_ratio: 0}]|0.3
t1-damped|$here/cases/t1_free_fall_damped.yaml||0.3
harmonic-pair|$here/cases/harmonic_contact_pair.yaml||1
deep-pair|$here/scripts/stability_deep_pair.yaml||1
f1-chain|$here/cases/f1_chain_slab.yaml||
settled-column|$here/scripts/stability_column.yaml||
light-lid|$here/scripts/stability_lid.yaml||
drum|$here/cases/t6_drum.yaml||0.3"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out="$here/docs/stability_table.md"
part="$out.part"
{
  echo "| scene | integrator | printed limit (s) | binding mode | blow-up limit (s) | measured boundary (s) | measured / printed | measured / blow-up |"
  echo "|---|---|---:|---|---:|---:|---:|---:|"
} >"$part"
echo "$rows" | while IFS='|' read -r name file sets t_end; do
  if [ -n "$selected" ] && ! echo ",$selected," | grep -q ",$name,"; then continue; fi
  for integrator in $(echo "$integrators" | tr ',' ' '); do
    set -- --set "integrator=$integrator"
    if [ -n "$sets" ]; then
      old_ifs=$IFS
      IFS=';'
      for s in $sets; do set -- "$@" --set "$s"; done
      IFS=$old_ifs
    fi
    "$build/kiln" check "$file" "$@" --json >"$work/check.json" 2>/dev/null || true
    /usr/bin/python3 - "$work/check.json" >"$work/limit" 2>/dev/null <<'PY' || echo "0 -" >"$work/limit"
import json, sys
e = json.load(open(sys.argv[1]))['estimate']
best = (e.get('dt_limit') or float('inf'), e.get('binding_mode') or '-')
if (e.get('conduction_dt_limit') or float('inf')) < best[0]:
    best = (e['conduction_dt_limit'], 'conduction')
print(best[0] if best[0] != float('inf') else 0, best[1])
PY
    read -r limit mode <"$work/limit"
    if [ "$limit" = 0 ]; then
      echo "| $name | $integrator | none | $mode | - | - | - | - |" >>"$part"
      continue
    fi
    lo=$(/usr/bin/python3 -c "print(0.25 * $limit)")
    hi=$(/usr/bin/python3 -c "print(2.0 * $limit)")
    [ -n "$t_end" ] && set -- "$@" --t-end "$t_end"
    "$build/kiln" sweep "$file" --integrator "$integrator" "$@" --dt-min "$lo" --dt-max "$hi" --points 7 \
      --quiet --out "$work/sweep" >/dev/null 2>&1 || true
    /usr/bin/python3 - "$work/sweep/sweep.json" "$name" "$integrator" "$limit" "$mode" >>"$part" <<'PY'
import json, math, sys
path, name, integrator, limit, mode = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]), sys.argv[5]
try:
    d = json.load(open(path))
except (OSError, ValueError):
    print(f"| {name} | {integrator} | {limit:.4g} | {mode} | - | sweep failed | - | - |")
    sys.exit()
e = d["estimate"]
if mode != "conduction":  # the sweep's: the start's joined with its finest run's end state
    limit, mode = e["dt_limit"], e["binding_mode"]
    if e["dt_limit"] < 0.999 * d["estimate_at_start"]["dt_limit"]:
        mode += " (end state)"
blow_up = e.get("blow_up_dt_limit") if mode != "conduction" else None
capped = blow_up and blow_up > limit
b = f"{blow_up:.4g}" if capped else "-"
s, u = d.get("largest_stable_dt"), d.get("smallest_unstable_dt")
if s and u:
    m = math.sqrt(s * u)
    ratio_b = f"{m / blow_up:.3f}" if capped else "-"
    print(f"| {name} | {integrator} | {limit:.4g} | {mode} | {b} | {m:.4g} | {m / limit:.3f} | {ratio_b} |")
elif s:
    print(f"| {name} | {integrator} | {limit:.4g} | {mode} | {b} | > {s:.4g} | > {s / limit:.2f} | - |")
else:
    print(f"| {name} | {integrator} | {limit:.4g} | {mode} | {b} | < {u:.4g} | < {u / limit:.2f} | - |")
PY
    rm -rf "$work/sweep"
  done
done
mv "$part" "$out"
cat "$out"
