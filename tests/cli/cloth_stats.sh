#!/usr/bin/env bash
# stats.jsonl's cloth figures: a quick cloth drape carries stretch_p99, stretch_max, folds_45 and
# folds_90 in every frame, finite and in range (the flat sheet at frame 0: every stretch exactly 1
# and no fold; draped over the ball: a stretch near 1), and its progress line shows them; a scene
# without cloth (the torus) has none of them.
#   cloth_stats.sh INVFEM SOURCE_DIR WORKDIR
set -uo pipefail
invfem="$1" src="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
command -v python3 >/dev/null || { echo "skipped: no python3"; exit 0; }

if ! "$invfem" run "$src/apps/scenes/cloth_drape.json" --quick --set frames=20 --threads 2 \
      --out "$work/drape" > "$work/drape.log" 2>&1; then
  echo "FAIL: the cloth drape did not run:"; cat "$work/drape.log"; exit 1
fi
grep -q "stretch p99 [0-9.]*, folds past 90 deg [0-9.]*%" "$work/drape.log" ||
  { echo "FAIL: the progress line shows no stretch and folds:"; tail -3 "$work/drape.log"; fail=1; }
python3 - "$work/drape/stats.jsonl" <<'PY' || fail=1
import json, math, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
assert len(rows) == 21, "%d stats lines, want 21" % len(rows)
for r in rows:
    f = r["frame"]
    p99, top, f45, f90 = (r[k] for k in ("stretch_p99", "stretch_max", "folds_45", "folds_90"))
    assert all(isinstance(v, float) or isinstance(v, int) for v in (p99, top, f45, f90)), r
    assert all(math.isfinite(v) for v in (p99, top, f45, f90)), r
    assert 0 < p99 <= top, "frame %d: stretch p99 %g, max %g" % (f, p99, top)
    assert 0 <= f90 <= f45 <= 1, "frame %d: folds_45 %g, folds_90 %g" % (f, f45, f90)
    # A membrane of E = 2e5 Pa under its own weight and a fall of half a metre: never half again
    # as long as its rest shape.
    assert p99 < 1.5, "frame %d: stretch p99 %g" % (f, p99)
# Frame 0 is the flat sheet at rest: every stretch exactly 1 and no fold.
first = rows[0]
assert abs(first["stretch_p99"] - 1) < 1e-12 and abs(first["stretch_max"] - 1) < 1e-12, first
assert first["folds_45"] == 0 and first["folds_90"] == 0, first
# Frame 20: draped over the ball and settling; the stiff membrane holds it near its rest size.
assert 0.98 <= rows[-1]["stretch_p99"] <= 1.08, "frame 20: stretch p99 %g, not near 1" % rows[-1]["stretch_p99"]
print("drape: last frame stretch p99 %g max %g folds_45 %g folds_90 %g" %
      tuple(rows[-1][k] for k in ("stretch_p99", "stretch_max", "folds_45", "folds_90")))
PY

if ! "$invfem" run "$src/apps/scenes/torus_puddle.json" --quick --set frames=1 --threads 2 --quiet \
      --out "$work/torus" > "$work/torus.log" 2>&1; then
  echo "FAIL: the torus did not run:"; cat "$work/torus.log"; exit 1
fi
if grep -q '"stretch_\|"folds_' "$work/torus/stats.jsonl"; then
  echo "FAIL: a scene without cloth has cloth figures:"; head -1 "$work/torus/stats.jsonl"; fail=1
fi
exit $fail
