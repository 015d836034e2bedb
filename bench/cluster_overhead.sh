#!/usr/bin/env bash
# The cost of splitting a reference into parts (docs/cluster.md, "Measured"): the CPU time of
# `nearfield reference` at once (1 thread) against the same image in N bands of rows, each part
# in a process of its own (`--part`, as nearfield-cluster --process-per-part runs them) and all
# parts in one `nearfield serve` process (as one Ray worker runs them), and the whole image as one
# part in `serve` (the same code path without a split). Checks that the merges are the
# one-machine image bit for bit. CPU time (user + system) is the figure to compare on a
# shared machine; wall times are printed too.
#
#   bench/cluster_overhead.sh [--bin BUILD/nearfield] [--spp 256] [--parts 8] [--size 320x180] [--out CSV]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="$here/build/nearfield" spp=256 parts=8 size=320x180 out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --bin) bin="$2"; shift ;;
    --spp) spp="$2"; shift ;;
    --parts) parts="$2"; shift ;;
    --size) size="$2"; shift ;;
    --out) out="$2"; shift ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *) echo "cluster_overhead.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
  shift
done
w=${size%x*} h=${size#*x}
scene="$here/scenes/default.json"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
common=(-q reference "$scene" --width "$w" --height "$h" --spp "$spp" --threads 1)
cpu() {  # user + system seconds and wall seconds of a command
  /usr/bin/time -f "%U %S %e" -o "$tmp/time" "$@" > /dev/null
  awk '{ printf "%.2f %.2f\n", $1 + $2, $3 }' "$tmp/time"
}
read -r one_cpu one_wall < <(cpu "$bin" "${common[@]}" -o "$tmp/one.exr")
requests="$tmp/requests"
: > "$requests"
proc_cpu=0 proc_wall=0 files=() sfiles=()
for ((i = 0; i < parts; i++)); do
  a=$((h * i / parts)) b=$((h * (i + 1) / parts))
  read -r c wl < <(cpu "$bin" "${common[@]}" --tile "0,$a,$w,$((b - a))" --part "$tmp/p$i.nfpart")
  proc_cpu=$(awk -v x="$proc_cpu" -v y="$c" 'BEGIN { print x + y }')
  proc_wall=$(awk -v x="$proc_wall" -v y="$wl" 'BEGIN { print x + y }')
  files+=("$tmp/p$i.nfpart") sfiles+=("$tmp/s$i.nfpart")
  printf '["-q", "reference", "%s", "--width", "%s", "--height", "%s", "--spp", "%s", "--threads", "1", "--tile", "0,%s,%s,%s", "--part", "%s"]\n' \
    "$scene" "$w" "$h" "$spp" "$a" "$w" "$((b - a))" "$tmp/s$i.nfpart" >> "$requests"
done
read -r serve_cpu serve_wall < <(cpu "$bin" serve < "$requests")
printf '["-q", "reference", "%s", "--width", "%s", "--height", "%s", "--spp", "%s", "--threads", "1", "--part", "%s"]\n' \
  "$scene" "$w" "$h" "$spp" "$tmp/whole.nfpart" > "$tmp/whole-request"
read -r whole_cpu whole_wall < <(cpu "$bin" serve < "$tmp/whole-request")
"$bin" -q merge "$tmp/whole.nfpart" -o "$tmp/whole.exr"
"$bin" -q merge "${files[@]}" -o "$tmp/processes.exr"
"$bin" -q merge "${sfiles[@]}" -o "$tmp/serve.exr"
same() {  # the pixel data of two EXRs (nearfield writes equal pixels as equal bytes)
  python3 - "$1" "$2" <<'PY'
import struct, sys
def px(p):
    d = open(p, "rb").read(); pos = 8
    while d[pos] != 0:
        pos = d.index(b"\0", pos) + 1; pos = d.index(b"\0", pos) + 1; pos += 4 + struct.unpack_from("<i", d, pos)[0]
    return d[struct.unpack_from("<Q", d, pos + 1)[0]:]
print("yes" if px(sys.argv[1]) == px(sys.argv[2]) else "NO")
PY
}
p_same=$(same "$tmp/one.exr" "$tmp/processes.exr") s_same=$(same "$tmp/one.exr" "$tmp/serve.exr")
w_same=$(same "$tmp/one.exr" "$tmp/whole.exr")
load=$(cut -d' ' -f1-3 /proc/loadavg)
pct() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%+.1f", 100 * (a - b) / b }'; }
table="run,parts,cpu_s,wall_s,overhead_cpu_pct,bit_identical
one machine (1 thread),1,$one_cpu,$one_wall,0,yes
a process per part,$parts,$proc_cpu,$proc_wall,$(pct "$proc_cpu" "$one_cpu"),$p_same
one nearfield serve,$parts,$serve_cpu,$serve_wall,$(pct "$serve_cpu" "$one_cpu"),$s_same
the whole image as one part in serve,1,$whole_cpu,$whole_wall,$(pct "$whole_cpu" "$one_cpu"),$w_same"
echo "# ${w}x${h}, $spp spp, default scene; $(nproc) CPUs, load average $load; $(date -u +%FT%TZ)"
echo "$table"
if [ -n "$out" ]; then
  { echo "# ${w}x${h}, $spp spp, default scene; $(nproc) CPUs, load average $load; $(date -u +%FT%TZ)"; echo "$table"; } > "$out"
fi
