#!/bin/sh
# Regenerates the measured columns of tests/studies/verification_matrix.tsv (order, order_tol, bound, and
# the reason's TODO marks) from the rows' own studies, run by the test binary in measuring mode:
#
#   scripts/verification_matrix.sh [BUILD_DIR] [CATCH_TEST_SPEC]
#
# BUILD_DIR defaults to build (it must hold a built kiln_tests). CATCH_TEST_SPEC selects which
# case tests to re-measure (default "[rows]": every row, about ten minutes of one core; e.g.
# "2/7 stick*" for that case's rows only); rows not selected keep their values. One process at a
# time, one thread each.
#
# Per measured row: order = the fitted least-squares order (2 decimals), or `fails` when a level
# failed or crashed; order_tol = 0.15 when the per-halving orders of the fitted levels agree within
# 0.3, else 0.5 (erratic); bound = 2 x the finest error (2 significant digits, rounded up). A row
# whose order is now below nominal - 0.2 keeps its reason, or gets "TODO: say why"; if its order
# moved beyond its old tolerance the reason becomes "TODO: check (order was X): <old reason>" (the
# integrity test fails on TODO, so stale reasons get reviewed); a row back at its nominal order
# loses its reason. The changes are printed; review them (git diff) before committing.
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
spec=${2:-[rows]}
case $build in /*) ;; *) build="$here/$build" ;; esac
table="$here/tests/studies/verification_matrix.tsv"
measured=$(mktemp)
trap 'rm -f "$measured"' EXIT
KILN_MATRIX_MEASURE="$measured" "$build/kiln_tests" "$spec" >/dev/null 2>&1 || true
if [ ! -s "$measured" ]; then
  echo "nothing measured: is $build/kiln_tests built, and does '$spec' select matrix case tests?" >&2
  exit 1
fi
/usr/bin/python3 - "$table" "$measured" <<'PY'
import math, sys
table, measured = sys.argv[1], sys.argv[2]
results = {}
for line in open(measured):
    f = line.rstrip('\n').split('\t')
    key = tuple(f[0:6])  # scene, sets, events, integrator, quantity, t_end
    results[key] = f
lines = open(table).read().split('\n')
if lines and lines[-1] == '':
    lines.pop()
header = None
out, changes, todo = [], [], 0

def round_up(x):
    if not (x > 0) or math.isinf(x):
        return x
    e = math.floor(math.log10(x)) - 1
    return math.ceil(x / 10 ** e * (1 - 1e-12)) * 10 ** e

for text in lines:
    if text.startswith('#') or not text.strip():
        out.append(text)
        continue
    f = text.split('\t')
    if header is None:
        header = f
        out.append(text)
        continue
    row = dict(zip(header, f))
    key = (row['scene'], row['sets'], row['events'], row['integrator'], row['quantity'], row['t_end'])
    if key not in results:
        out.append(text)
        continue
    m = results[key]
    fitted, finest, orders, failure = m[6], m[7], m[8], m[9]
    old = dict(row)
    nominal = int(row['nominal'])
    if failure != '-':
        row['order'], row['order_tol'] = 'fails', '0.5'
        drops = True
    else:
        fitted, finest = float(fitted), float(finest)
        ks = [float(x) for x in orders.split(',')] if orders != '-' else []
        count = int(row['levels'])
        start = max(0, min(count - 3, count // 2))
        fit = [o for o in ks[start:] if not math.isnan(o)]
        spread = max(fit) - min(fit) if fit else float('inf')
        if row['order'] != '-':
            row['order'] = '%.2f' % fitted
            row['order_tol'] = '0.15' if spread <= 0.3 else '0.5'
        row['bound'] = '%.2g' % round_up(2 * finest)
        drops = row['order'] != '-' and fitted < nominal - 0.2
    moved = row['order'] != old['order'] and (
        'fails' in (row['order'], old['order']) or
        (old['order'] != '-' and abs(float(row['order']) - float(old['order'])) > float(old['order_tol'])))
    if drops and row['reason'] in ('-', ''):
        row['reason'] = 'TODO: say why'
    elif drops and moved and not row['reason'].startswith('TODO'):
        row['reason'] = 'TODO: check (order was %s): %s' % (old['order'], row['reason'])
    if not drops and row['reason'] != '-':
        row['reason'] = '-'
    if row['reason'].startswith('TODO'):
        todo += 1
    if row != old:
        changes.append('%s %s events %s %s: order %s -> %s, bound %s -> %s%s' % (
            row['scene'], '' if row['sets'] == '-' else row['sets'], row['events'], row['integrator'],
            old['order'], row['order'], old['bound'], row['bound'],
            '' if row['reason'] == old['reason'] else ', reason now "%s"' % row['reason']))
    out.append('\t'.join(row[h] for h in header))
open(table, 'w').write('\n'.join(out) + '\n')
print('%d rows measured, %d changed' % (len(results), len(changes)))
for c in changes:
    print('  ' + c)
if todo:
    print('%d rows need a reason (TODO): write it in the table' % todo)
PY
