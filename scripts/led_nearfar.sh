#!/usr/bin/env bash
# Near field against far field for the OSRAM LED (docs/measured-data.md, "Where the far field
# fails"): for each distance d, the illuminance grid (`nearfield probe --grid`) on the plane
# z = d across the LED's axis (a 2d x 2d square centred on the axis, 10 x 10 points, so up to
# 55 degrees off axis) under the imported light field (--reference: the double-precision
# quadrature of the light field) and under its own far field (scenes/led/osram.ies, closed form).
# Prints per d: the mean of each grid, the ratio of the means and the largest per-point
# |E_near / E_far - 1|. Needs scripts/make_led_scene.sh first. Usage:
#   scripts/led_nearfar.sh [d_mm ...]      (default: 2 3 5 7 10 15 20 30 50 100)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
nf="${NEARFIELD_BIN:-$here/build/nearfield}"
lf="$here/scenes/led/osram.json"
ies="$here/scenes/led/osram.ies"
for f in "$lf" "$ies"; do
  if [[ ! -f "$f" ]]; then
    echo "led_nearfar.sh: $f not found: run scripts/make_led_scene.sh first" >&2
    exit 1
  fi
done
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
distances=("$@")
[[ ${#distances[@]} -gt 0 ]] || distances=(2 3 5 7 10 15 20 30 50 100)
printf "%8s %14s %14s %10s %12s\n" "d_mm" "E_near_mean_lx" "E_far_mean_lx" "near/far" "max|dev|"
for mm in "${distances[@]}"; do
  read -r d two step < <(python3 -c "d=$mm/1000; print(d, 2*d, 2*d/10)")
  grid="-$d,-$d,$d;0,$two,0;$two,0,0"
  "$nf" probe "$lf" --grid "$grid" --spacing "$step" --reference --csv "$tmp/near.csv" > /dev/null 2>&1
  "$nf" probe "$ies" --grid "$grid" --spacing "$step" --csv "$tmp/far.csv" > /dev/null
  python3 - "$mm" "$tmp/near.csv" "$tmp/far.csv" <<'PY'
import csv, sys
mm, near, far = sys.argv[1], sys.argv[2], sys.argv[3]
def read(f):
    with open(f) as h:
        return [float(r["E_lx"]) for r in csv.DictReader(h)]
a, b = read(near), read(far)
dev = max(abs(x / y - 1.0) for x, y in zip(a, b) if y > 0)
ma, mb = sum(a) / len(a), sum(b) / len(b)
print(f"{float(mm):8.4g} {ma:14.6g} {mb:14.6g} {ma / mb:10.4f} {dev:12.4f}")
PY
done
