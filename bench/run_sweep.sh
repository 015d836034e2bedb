#!/usr/bin/env bash
# The speed/accuracy sweep in one command (bench/README.md): builds what is missing, runs
# bench_sweep (CSV tables), bench_micro (Google Benchmark JSON) and bench/plot_report.py (plots and
# report.md).
#
#   bench/run_sweep.sh [--quick] [--out DIR] [--build-dir DIR] [--no-build] [--no-micro] [--check]
#                      [-- extra bench_sweep options]
#
# Full mode writes bench/results/ (the committed report); --quick (< 1 min, the ctest smoke test)
# writes bench/results/cache/quick/ unless --out says otherwise, so it never replaces the full
# report. References are cached in <out>/cache/. --check validates the outputs' form afterwards.
# Full mode adds a close-up of the measured OSRAM LED ray set when ../shared/data/raysets holds it
# (imported with `nearfield luminaire import` into <out>/cache/imported/; $NEARFIELD_RAYSETS
# overrides the folder), and says why when it does not.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${NEARFIELD_BUILD_DIR:-$here/build}"
quick=0 out="" do_build=1 micro=1 check=0 extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --out) out="$2"; shift ;;
    --build-dir) build="$2"; shift ;;
    --no-build) do_build=0 ;;
    --no-micro) micro=0 ;;
    --check) check=1 ;;
    --) shift; extra=("$@"); break ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "run_sweep.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
if [ -z "$out" ]; then
  if [ $quick = 1 ]; then out="$here/bench/results/cache/quick"; else out="$here/bench/results"; fi
fi

python=""
for p in /usr/bin/python3 python3; do
  if command -v "$p" >/dev/null && "$p" -c 'import matplotlib, numpy' 2>/dev/null; then python="$p"; break; fi
done
if [ -z "$python" ]; then
  echo "run_sweep.sh: no Python 3 with matplotlib and numpy (apt-get install python3-matplotlib python3-numpy)" >&2
  exit 1
fi

start=$(date +%s)
if [ $do_build = 1 ]; then
  [ -f "$build/CMakeCache.txt" ] || cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
  cmake --build "$build" --target bench_sweep bench_micro nearfield --parallel "$(nproc)"
fi
for exe in bench_sweep bench_micro; do
  [ -x "$build/bench/$exe" ] || { echo "run_sweep.sh: $build/bench/$exe is missing (build it, or drop --no-build)" >&2; exit 1; }
done
mkdir -p "$out"

args=(--out "$out")
[ $quick = 1 ] && args+=(--quick)

# The measured close-up (full mode, default luminaires only): the OSRAM LED imported as it is.
if [ $quick = 0 ] && [[ " ${extra[*]-} " != *" --luminaires "* ]]; then
  rays_dir="${NEARFIELD_RAYSETS:-$here/../shared/data/raysets}"
  rays="$rays_dir/osram_LERTDUW_S2WP_green_100k.TM25RAY"
  if [ ! -f "$rays" ]; then
    echo "run_sweep.sh: skipping closeup-osram-led: $rays is absent (the shared data is not here)"
  elif [ ! -x "$build/nearfield" ]; then
    echo "run_sweep.sh: skipping closeup-osram-led: $build/nearfield is missing (build it, or drop --no-build)"
  else
    imported="$out/cache/imported"
    mkdir -p "$imported"
    if [ ! -f "$imported/osram-led.json" ] || [ "$rays" -nt "$imported/osram-led.json" ]; then
      "$build/nearfield" luminaire import "$rays" -o "$imported" --name osram-led
    fi
    args+=(--luminaires "bike,car1,car2,led-rgb,$imported/osram-led.json")
  fi
fi
"$build/bench/bench_sweep" "${args[@]}" "${extra[@]}"

if [ $micro = 1 ]; then
  margs=(--benchmark_out="$out/micro.json" --benchmark_out_format=json)
  # quick: one kernel and one precomputation, briefly (checks that the program runs)
  [ $quick = 1 ] && margs+=(--benchmark_filter='^(StepA/led-rgb|Precompute/car1)/' --benchmark_min_time=0.05)
  "$build/bench/bench_micro" "${margs[@]}"
fi

"$python" "$here/bench/plot_report.py" "$out"
[ $check = 1 ] && "$python" "$here/bench/check_sweep_outputs.py" "$out"
echo "run_sweep.sh: done in $(( $(date +%s) - start )) s; report: $out/report.md"
