#!/usr/bin/env bash
# Prepares what scenes/led.json reads (docs/photometry.md, "The LED scene"): the OSRAM LED ray
# file, which is third-party data and not part of the repository, imported into scenes/led/
# (git-ignored) as a light field (osram.json + osram.exr), and that light field's far field
# written as IES LM-63 (osram.ies). Rerun it after upgrading: an osram.ies written before the
# type C orientation change (docs/photometry.md, "Change for existing scenes") is mirrored. Usage:
#   scripts/make_led_scene.sh [RAYFILE]     (default: ../shared/data/raysets/osram_LERTDUW_S2WP_green_100k.TM25RAY)
# Environment: NEARFIELD_BIN (default build/nearfield).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
nf="${NEARFIELD_BIN:-$here/build/nearfield}"
rays="${1:-$here/../shared/data/raysets/osram_LERTDUW_S2WP_green_100k.TM25RAY}"
if [[ ! -x "$nf" ]]; then
  echo "make_led_scene.sh: $nf not found: build first (docs/building.md) or set NEARFIELD_BIN" >&2
  exit 1
fi
if [[ ! -f "$rays" ]]; then
  echo "make_led_scene.sh: ray file not found: $rays (give the OSRAM TM-25 file as the first argument)" >&2
  exit 1
fi
out="$here/scenes/led"
mkdir -p "$out"
"$nf" luminaire import "$rays" -o "$out" --name osram --force
"$nf" luminaire farfield "$out/osram.json" -o "$out/osram.ies"
echo "scenes/led/: osram.json, osram.exr (light field) and osram.ies (its far field); render with"
echo "  $nf render $here/scenes/led.json -o out/led.exr --png out/led.png --stats out/led_stats.json"
