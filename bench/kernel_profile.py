#!/usr/bin/env python3
"""Per-source-line profile of an OpenCL kernel run by PoCL on the CPU (bench/README.md "Kernel profile").

PoCL compiles a kernel twice into its cache's .so: the work-item function `_pocl_kernel_NAME`, which
carries the line table when the program is built with -g (NEARFIELD_CL_EXTRA_OPTIONS=-g), and the
work-group function `_pocl_kernel_NAME_workgroup` that actually runs, a copy with the work-item loop
around it and no line table. This script aligns the two functions' instruction streams (opcodes and
registers, addresses blanked), maps every `perf` sample in the work-group copy to its counterpart in
the work-item function, and reads the source line (with the chain of inlined calls) from there.

    NEARFIELD_CL_EXTRA_OPTIONS=-g perf record -e cpu-clock -F 1000 -o perf.data \\
        build/bench/bench_frame --res 320x180 --spp 16 --still 20 --moving 0
    bench/kernel_profile.py perf.data lf_fused [--top 40] [--csv out.csv]

Reports the share of the kernel's samples by function (inclusive: a sample counts for every function
on its inline chain), by source line (inclusive), by innermost line and by the kernel body's line.
Needs perf, objdump, nm and addr2line (binutils).
"""
import argparse
import collections
import csv
import difflib
import re
import subprocess
import sys


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True, check=True).stdout


def samples(data, kernel):
    """perf samples in KERNEL's .so: Counter of (symbol, offset), the .so's path, all samples."""
    out = run(["perf", "script", "--no-demangle", "-i", data, "-F", "ip,sym,symoff,dso"])
    pat = re.compile(r"(\S+)\+0x([0-9a-f]+) \((\S+/%s\.so)\)" % re.escape(kernel))
    per_so = collections.defaultdict(collections.Counter)
    total = 0
    for line in out.splitlines():
        total += 1
        m = pat.search(line)
        if m:
            per_so[m.group(3)][(m.group(1), int(m.group(2), 16))] += 1
    if not per_so:
        sys.exit(f"kernel_profile: no samples in {kernel}.so in {data} (was the kernel run under perf?)")
    so = max(per_so, key=lambda k: sum(per_so[k].values()))  # the build that ran most
    return per_so[so], so, total


def symbols(so):
    syms = {}
    for line in run(["nm", "-S", so]).splitlines():
        p = line.split()
        if len(p) == 4:
            syms[p[3]] = (int(p[0], 16), int(p[1], 16))
    return syms


def disassemble(so, start, size):
    """[(address, instruction text with addresses and immediates blanked)]"""
    text = run(["objdump", "-d", "--no-show-raw-insn", f"--start-address={start}", f"--stop-address={start + size}", so])
    out = []
    for line in text.splitlines():
        m = re.match(r"\s+([0-9a-f]+):\s+(.*)", line)
        if m:
            ins = re.sub(r"0x[0-9a-f]+|\b[0-9a-f]{4,}\b|<[^>]*>|#.*", "", m.group(2)).strip()
            out.append((int(m.group(1), 16), ins))
    return out


def align(wg, wi):
    """work-group address -> work-item address: matched instructions, unmatched ones take the last match."""
    sm = difflib.SequenceMatcher(None, [t for _, t in wg], [t for _, t in wi], autojunk=False)
    direct = {}
    for blk in sm.get_matching_blocks():
        for k in range(blk.size):
            direct[wg[blk.a + k][0]] = wi[blk.b + k][0]
    mapping, last = {}, None
    for a, _ in wg:
        last = direct.get(a, last)
        mapping[a] = last
    return mapping, len(direct)


def kernel_path(where):
    """'/tmp/common/sat_box.h:50' -> 'common/sat_box.h:50' (the names the loader's #line directives give)"""
    m = re.search(r"((?:common|shared)/[^/]+)$", where.rsplit(":", 1)[0])
    name = m.group(1) if m else where.rsplit(":", 1)[0].split("/")[-1]
    return f"{name}:{where.rsplit(':', 1)[-1]}" if ":" in where else where


def inline_chains(so, addrs):
    """address -> [(function, file:line)], innermost first (addr2line -i)."""
    lines = run(["addr2line", "-a", "-i", "-f", "-e", so] + [hex(a) for a in addrs]).splitlines()
    chains, cur, i = {}, None, 0
    while i < len(lines):
        if lines[i].startswith("0x"):
            cur = int(lines[i], 16)
            chains[cur] = []
            i += 1
            continue
        where = lines[i + 1].split(" (")[0]
        chains[cur].append((lines[i], kernel_path(where)))
        i += 2
    return chains


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("data", help="perf.data")
    ap.add_argument("kernel", help="kernel name, e.g. lf_fused")
    ap.add_argument("--top", type=int, default=40)
    ap.add_argument("--csv", help="also write view,key,share_percent rows here")
    a = ap.parse_args()
    counts, so, total = samples(a.data, a.kernel)
    syms = symbols(so)
    wi_name = "_pocl_kernel_" + a.kernel
    wg_name = wi_name + "_workgroup"
    if wi_name not in syms or wg_name not in syms:
        sys.exit(f"kernel_profile: {so} has no {wi_name} and {wg_name}")
    wg = disassemble(so, *syms[wg_name])
    wi = disassemble(so, *syms[wi_name])
    mapping, matched = align(wg, wi)
    ksum = sum(counts.values())
    mapped = collections.Counter()
    other = 0
    for (sym, off), c in counts.items():
        target = mapping.get(syms[wg_name][0] + off) if sym == wg_name else None
        if target is None:
            other += c
        else:
            mapped[target] += c
    chains = inline_chains(so, sorted(mapped))
    views = {k: collections.Counter() for k in ("function", "line", "innermost line", "kernel body line")}
    for addr, c in mapped.items():
        ch = chains.get(addr) or [("?", "?:?")]
        for f in {f for f, _ in ch}:
            views["function"][f] += c
        for w in {w for _, w in ch}:
            views["line"][w] += c
        views["innermost line"][ch[0][1]] += c
        views["kernel body line"][ch[-1][1]] += c
    print(f"# {a.kernel}: {ksum} samples in the kernel of {total} ({100 * ksum / max(total, 1):.1f} %); "
          f"{matched} of {len(wg)} work-group instructions aligned; {other} samples outside the work-group copy")
    print(f"# {so}")
    rows = []
    for view, counter in views.items():
        print(f"\n## by {view} (inclusive)" if view in ("function", "line") else f"\n## by {view}")
        for key, c in counter.most_common(a.top):
            share = 100.0 * c / ksum
            print(f"{share:6.2f} %  {key}")
            rows.append((view, key, f"{share:.2f}"))
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["view", "key", "share_percent"])
            w.writerows(rows)


if __name__ == "__main__":
    main()
