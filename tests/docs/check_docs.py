#!/usr/bin/env python3
"""The docs test (docs/testing.md, "The docs test"): the commands that README.md and docs/*.md show
must run as written.

It reads every fenced code block of README.md and docs/*.md and every inline code span that
starts with `nearfield `, and does one thing with each command it finds:

  run        a complete command (no placeholders): run against the build, in a temporary
             folder, made fast by the default overrides below and the block's `docs-test`
             directives; it must exit 0.
  synopsis   a usage line with placeholders (SCENE, OUT.exr, [--opt ...], a|b, ...): the
             subcommand must exist and every option it names must be in
             `nearfield SUBCOMMAND --help` (or the global options).
  exists     a `scripts/` or `bench/` program in a block marked `skip`: it must exist and be
             executable; the block is not run, for the reason its directive gives.
  skip       a block marked `skip REASON` (the reason is printed), or one marked
             `needs PATH` whose PATH (relative to the repository) is absent.

Directives are HTML comments (invisible in rendered Markdown) on the lines right above a
fence, one per comment:

  <!-- docs-test: skip REASON -->         do not run the block; say why
  <!-- docs-test: needs PATH -->          skip (printed) unless PATH exists, e.g. ../shared/data
  <!-- docs-test: replace OLD NEW -->     replace text OLD by NEW in the block before running it
                                          (shell words: quote with '...' to include spaces)
  <!-- docs-test: args ARGS -->           add ARGS to every `nearfield` command of the block
  <!-- docs-test: timeout SECONDS -->     time limit of the block (default 60)

Default overrides, for every run `nearfield` command (documented in docs/testing.md): `render`
and `reference` get --width 64 --height 36 (replacing the values written; 64 x 64 when the
command writes a square --width N --height N, which a fisheye camera needs), --spp at most 2 and
--frames at most 1; `view` gets --window 160x90. A command that a directive cannot make fast
enough must be marked `skip` with its reason: an unmarked block that fails, fails the test.

Commands run with the working directory in a temporary folder that holds copies of the
repository's scenes/ and luminaires/ and links to scripts/ and bench/, with ../shared linked to
the repository's ../shared when it exists, and `nearfield` first on PATH. Outputs land there.

Exit status 0 when every command passed (skips included), 1 otherwise; a table of every
command found and what was done with it is printed either way.
"""
import argparse
import glob
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

SHELL_LANGS = {"", "sh", "bash", "shell", "console"}
PROGRAM_PREFIXES = ("nearfield", "scripts/", "bench/", "./scripts/", "./bench/", "build/")
DIRECTIVE = re.compile(r"^\s*<!--\s*docs-test:\s*(\w+)\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)(```+|~~~+)\s*([\w+-]*)")
INLINE = re.compile(r"(?<!`)`(nearfield [^`]+)`(?!`)")
# Placeholders: SCENE, OUT.exr, LF.json, DIR, [--opt], a|b, ..., NAME=VALUE
# (an upper-case word alone, or of two letters or more before an extension: S.json is a file name)
PLACEHOLDER = re.compile(r"^(\[|[A-Z][A-Z0-9_]*\]?$|[A-Z][A-Z0-9_]+[.:=][\w.]*\]?$)|\||\.\.\.")


class Command:
    def __init__(self, where, text, kind):
        self.where = where  # "file:line"
        self.text = text  # as written (one line, continuations joined)
        self.kind = kind  # run | synopsis | exists | skip
        self.status = "?"  # ok | FAIL | skipped
        self.note = ""


def words_after_prefixes(line):
    """The words of a shell line with env assignments, chrt, xvfb-run and time stripped."""
    try:
        w = shlex.split(line, comments=True)
    except ValueError:
        w = line.split()
    i = 0
    while i < len(w):
        if re.match(r"^[A-Za-z_][A-Za-z0-9_]*=", w[i]) or w[i] == "time":
            i += 1
        elif w[i] == "chrt":
            i += 1
            while i < len(w) and (w[i].startswith("-") or w[i].isdigit()):
                i += 1
        elif w[i] == "xvfb-run":
            i += 1
            while i < len(w) and w[i].startswith("-"):
                i += 2 if w[i] in ("-s", "--server-args", "-n", "--server-num", "-e", "--error-file") else 1
        else:
            break
    return w[i:]


def logical_lines(body):
    """Join backslash continuations; keep here-documents as part of the line that opens them."""
    out, cur, heredoc = [], "", None
    for raw in body:
        if heredoc is not None:
            cur += "\n" + raw
            if raw.strip() == heredoc:
                out.append(cur)
                cur, heredoc = "", None
            continue
        cur = raw if not cur else cur + "\n" + raw
        if raw.rstrip().endswith("\\"):
            continue
        m = re.search(r"<<-?\s*'?\"?(\w+)'?\"?", raw)
        if m:
            heredoc = m.group(1)
            continue
        out.append(cur)
        cur = ""
    if cur:
        out.append(cur)
    return out


def first_line_words(line):
    return words_after_prefixes(line.replace("\\\n", " ").split("\n")[0])


def is_program_line(line):
    w = first_line_words(line)
    return bool(w) and (w[0] == "nearfield" or w[0].startswith(PROGRAM_PREFIXES[1:]))


def has_placeholder(words):
    return any(PLACEHOLDER.search(x) for x in words)


# ------------------------------------------------------------------ nearfield help -----------


class Help:
    def __init__(self, binary):
        self.binary = binary
        self.cache = {}

    def text(self, path):
        key = tuple(path)
        if key not in self.cache:
            p = subprocess.run([self.binary, *path, "--help"], capture_output=True, text=True, timeout=60)
            self.cache[key] = (p.returncode, p.stdout + p.stderr)
        return self.cache[key]

    def prefetch(self):
        """Every subcommand's help, in parallel (each start of the binary takes ~0.5 s)."""
        from concurrent.futures import ThreadPoolExecutor
        level = [[]]
        with ThreadPoolExecutor(max_workers=4) as pool:
            while level:
                list(pool.map(self.text, level))
                level = [p + [s] for p in level for s in sorted(self.subcommands(p))]

    def subcommands(self, path):
        rc, out = self.text(path)
        if rc != 0 or "Subcommands:" not in out:
            return set()
        names = set()
        for line in out.split("Subcommands:", 1)[1].splitlines():
            m = re.match(r"^  (\S+)\s", line + " ")
            if m:
                names.add(m.group(1))
        return names

    def check(self, words):
        """words: after `nearfield`. Returns an error string or ''."""
        path = []
        rest = list(words)
        while rest and rest[0] in self.subcommands(path):
            path.append(rest.pop(0))
        if not path and rest and has_placeholder(rest[:1]):
            return ""  # `nearfield SUBCOMMAND --help`: any subcommand
        if not path:
            return f"no subcommand '{rest[0] if rest else ''}' (nearfield --help)"
        rc, help_text = self.text(path)
        if rc != 0:
            return f"`nearfield {' '.join(path)} --help` exits {rc}"
        if self.subcommands(path):
            return f"`nearfield {' '.join(path)}` needs a subcommand: {', '.join(sorted(self.subcommands(path)))}"
        _, global_text = self.text([])
        missing = []
        for w in rest:
            for opt in re.findall(r"(?<![\w-])(--?[A-Za-z][\w-]*)", w):
                if opt.startswith("--") or re.match(r"^-[A-Za-z]$", opt):
                    pat = re.compile(r"(?<![\w-])" + re.escape(opt) + r"(?![\w-])")
                    if not pat.search(help_text) and not pat.search(global_text) and opt not in missing:
                        missing.append(opt)
        if missing:
            return f"`nearfield {' '.join(path)}` has no option {', '.join(missing)}"
        return ""


# ------------------------------------------------------------------ collecting ---------------


def read_blocks(path, rel):
    """Yield (line_no, lang, body_lines, directives) for each fenced block."""
    lines = open(path, encoding="utf-8").read().split("\n")
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        fence, lang = m.group(2), m.group(3).lower()
        directives = []
        k = i - 1
        while k >= 0 and DIRECTIVE.match(lines[k]):
            d = DIRECTIVE.match(lines[k])
            directives.insert(0, (d.group(1), d.group(2)))
            k -= 1
        j = i + 1
        while j < len(lines) and not lines[j].strip().startswith(fence):
            j += 1
        yield i + 1, lang, lines[i + 1:j], directives
        i = j + 1


def inline_spans(path):
    """Yield (line_no, text, directives) of inline `nearfield ...` spans outside fences; the
    directives above a paragraph apply to the spans in it."""
    in_fence = None
    directives = []
    for n, line in enumerate(open(path, encoding="utf-8").read().split("\n"), 1):
        m = FENCE.match(line)
        if m:
            in_fence = None if in_fence == m.group(2) else (in_fence or m.group(2))
            directives = []
            continue
        if in_fence:
            continue
        d = DIRECTIVE.match(line)
        if d:
            directives.append((d.group(1), d.group(2)))
            continue
        if not line.strip():
            directives = []
            continue
        for s in INLINE.finditer(line):
            yield n, s.group(1), directives


def synopsis_entries(body):
    """Usage blocks: an entry starts at a line beginning with `nearfield`; indented lines that
    start with [ or - continue it; a run of 2+ spaces starts the description column."""
    entries, cur = [], None
    for line in body:
        if line.startswith("nearfield "):
            if cur:
                entries.append(cur)
            cur = re.split(r"\s{2,}", line.strip())[0]
        elif cur is not None and re.match(r"^\s+[\[-]", line):
            cur += " " + re.split(r"\s{2,}", line.strip())[0]
        elif cur is not None and line.strip():
            pass  # description text
    if cur:
        entries.append(cur)
    return entries


# ------------------------------------------------------------------ running ------------------

FAST = {
    "render": [("--width", "64"), ("--height", "36"), ("--spp", "2"), ("--frames", "1")],
    "reference": [("--width", "64"), ("--height", "36"), ("--spp", "2")],
    "view": [("--window", "160x90")],
}


def fast_overrides(line, extra_args):
    """Apply the default overrides (and `args`) to every nearfield command in a shell line."""
    def fix(cmd):
        w = first_line_words(cmd)
        if not w or w[0] != "nearfield":
            return cmd
        sub = w[1] if len(w) > 1 else ""
        # A square image stays square (a fisheye camera refuses others): --width N --height N
        # written as equal values get 64 x 64.
        mw = re.search(r"(?<![\w-])--width[ =](\d+)", cmd)
        mh = re.search(r"(?<![\w-])--height[ =](\d+)", cmd)
        square = mw and mh and mw.group(1) == mh.group(1)
        for opt, val in FAST.get(sub, []):
            if square and opt == "--height":
                val = "64"

            m = re.search(r"(?<![\w-])" + re.escape(opt) + r"[ =](\S+)", cmd)
            if m:
                cur = m.group(1)
                if opt in ("--spp", "--frames") and cur.isdigit() and int(cur) <= int(val):
                    continue
                cmd = cmd[:m.start(1)] + val + cmd[m.end(1):]
            else:
                cmd = add_args(cmd, f"{opt} {val}")
        if extra_args:
            cmd = add_args(cmd, extra_args)
        return cmd
    return fix(line)


def add_args(cmd, args):
    first, sep, rest = cmd.partition("\n")  # a here-document stays after the first line
    # before a trailing comment or redirection
    m = re.search(r"\s(#.*|[12]?>.*)$", first)
    if m:
        first = first[:m.start()] + " " + args + first[m.start():]
    else:
        first = first.rstrip() + " " + args
    return first + sep + rest


def make_workdir(source, root):
    work = os.path.join(root, "repo")
    os.makedirs(work)
    for d in ("scenes", "luminaires"):
        if os.path.isdir(os.path.join(source, d)):
            shutil.copytree(os.path.join(source, d), os.path.join(work, d), symlinks=True)
    for d in ("scripts", "bench"):
        if os.path.isdir(os.path.join(source, d)):
            os.symlink(os.path.join(source, d), os.path.join(work, d))
    shared = os.path.normpath(os.path.join(source, "..", "shared"))
    if os.path.isdir(shared):
        os.symlink(shared, os.path.join(root, "shared"))
    return work


def run_block(script, work, env, timeout):
    t = time.monotonic()
    try:
        p = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", script], cwd=work, env=env,
                           capture_output=True, text=True, timeout=timeout)
        rc, out = p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired as e:
        rc, out = 124, f"timed out after {timeout} s\n" + ((e.stdout or b"").decode(errors="replace") if
                                                            isinstance(e.stdout, bytes) else (e.stdout or ""))
    return rc, out, time.monotonic() - t


# ------------------------------------------------------------------ main ---------------------


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--nearfield", required=True, help="the nearfield binary")
    ap.add_argument("--source", required=True, help="the repository root")
    ap.add_argument("--keep", action="store_true", help="keep the temporary folder")
    ap.add_argument("--only", default="", help="only files whose path contains this")
    ap.add_argument("--no-run", action="store_true", help="check synopses only, run nothing")
    a = ap.parse_args()
    source = os.path.abspath(a.source)
    binary = os.path.abspath(a.nearfield)
    helps = Help(binary)
    helps.prefetch()
    files = ["README.md"] + sorted(os.path.relpath(p, source) for p in glob.glob(os.path.join(source, "docs", "*.md")))
    files = [f for f in files if a.only in f]

    root = tempfile.mkdtemp(prefix="nf-docs-")
    work = make_workdir(source, root)
    bindir = os.path.join(root, "bin")
    os.makedirs(bindir)
    os.symlink(binary, os.path.join(bindir, "nearfield"))
    env = dict(os.environ)
    env["PATH"] = bindir + os.pathsep + env.get("PATH", "")
    env["NEARFIELD_BIN"] = binary  # scripts/*.sh that run nearfield take it from here

    commands, other_blocks = [], []
    t0 = time.monotonic()
    for rel in files:
        path = os.path.join(source, rel)
        for line_no, lang, body, directives in read_blocks(path, rel):
            where = f"{rel}:{line_no}"
            lines = logical_lines(body)
            program_lines = [l for l in lines if is_program_line(l)]
            if lang not in SHELL_LANGS or not program_lines:
                other_blocks.append(f"{where} ({lang or 'text'})")
                continue
            d = {}
            replaces = []
            for key, val in directives:
                if key == "replace":
                    parts = shlex.split(val)
                    if len(parts) != 2:
                        sys.exit(f"{where}: docs-test replace needs OLD NEW, got {val!r}")
                    replaces.append(parts)
                elif key in ("skip", "needs", "args", "timeout"):
                    d[key] = val
                else:
                    sys.exit(f"{where}: unknown docs-test directive '{key}'")
            # Synopsis: placeholders in a nearfield line.
            nf_lines = [l for l in program_lines if first_line_words(l)[0] == "nearfield"]
            if any(has_placeholder(first_line_words(l)) for l in nf_lines):
                for entry in synopsis_entries(body):
                    c = Command(where, entry, "synopsis")
                    err = helps.check(entry.split()[1:])
                    c.status, c.note = ("FAIL", err) if err else ("ok", "subcommand and options exist")
                    commands.append(c)
                continue
            shown = "; ".join(l.replace("\\\n", " ").split("\n")[0] for l in program_lines)
            if "skip" in d or ("needs" in d and not os.path.exists(os.path.join(source, d["needs"]))):
                reason = d.get("skip") or f"needs {d['needs']} (absent)"
                for l in program_lines:
                    w = first_line_words(l)
                    if w[0] != "nearfield":
                        c = Command(where, re.sub(r"\s+#.*", "", l.split("\n")[0]), "exists")
                        prog = os.path.join(source, w[0])
                        ok = os.path.isfile(prog) and os.access(prog, os.X_OK)
                        c.status = "ok" if ok else "FAIL"
                        c.note = f"exists and is executable; not run: {reason}" if ok else f"{w[0]}: missing or not executable"
                    else:
                        c = Command(where, l.split("\n")[0], "skip")
                        c.status = "skipped"
                        c.note = reason
                        err = helps.check(w[1:])
                        if err:
                            c.status, c.note = "FAIL", err
                    commands.append(c)
                continue
            # Run the block.
            script = "\n".join(body)
            for old, new in replaces:
                if old not in script:
                    sys.exit(f"{where}: docs-test replace: '{old}' is not in the block")
                script = script.replace(old, new)
            script = "\n".join(fast_overrides(l, d.get("args", "")) if is_program_line(l) else l
                               for l in logical_lines(script.split("\n")))
            for l in program_lines:
                w = first_line_words(l)
                if w[0] == "nearfield":
                    err = helps.check([x for x in w[1:] if not has_placeholder([x])])
                    if err:
                        c = Command(where, shown, "run")
                        c.status, c.note = "FAIL", err
                        commands.append(c)
                        break
            else:
                c = Command(where, shown, "run")
                no_display = not env.get("DISPLAY") and not env.get("WAYLAND_DISPLAY")
                if "xvfb-run" in script and not shutil.which("xvfb-run"):
                    c.status, c.note = "skipped", "xvfb-run is not installed"
                    c.kind = "skip"
                    commands.append(c)
                    continue
                if no_display and "xvfb-run" not in script and re.search(r"\bnearfield\s+view\b", script):
                    c.status, c.note = "skipped", "nearfield view needs a display (DISPLAY is unset; run_tests.sh provides Xvfb)"
                    c.kind = "skip"
                    commands.append(c)
                    continue
                if a.no_run:
                    c.status, c.note = "skipped", "--no-run"
                    commands.append(c)
                    continue
                rc, out, secs = run_block(script, work, env, float(d.get("timeout", 60)))
                c.status = "ok" if rc == 0 else "FAIL"
                c.note = f"exit {rc}, {secs:.1f} s" + ("" if rc == 0 else "\n" + indent(script, "    $ ") +
                                                         "\n" + indent(out[-3000:], "    | "))
                commands.append(c)

        # Inline code spans: complete commands run (render/reference/probe/luminaire/settings/info
        # with every input present), the rest are checked like synopses.
        for line_no, text, directives in inline_spans(path):
            where = f"{rel}:{line_no}"
            words = text.split()
            if len(words) < 2:
                continue
            d = dict(directives)
            c = Command(where, text, "synopsis")
            err = helps.check([w for w in words[1:]])
            c.status, c.note = ("FAIL", err) if err else ("ok", "subcommand and options exist")
            complete = not has_placeholder(words) and words[1] in ("render", "reference") and \
                any(w.endswith(".json") for w in words[2:])
            if not err and complete and ("skip" in d or ("needs" in d and not os.path.exists(os.path.join(source, d["needs"])))):
                c.kind, c.status = "skip", "skipped"
                c.note = (d.get("skip") or f"needs {d['needs']} (absent)") + "; options exist"
            elif not err and complete and not a.no_run:
                c.kind = "run"
                script = fast_overrides(text, d.get("args", ""))
                rc, out, secs = run_block(script, work, env, 60.0)
                c.status = "ok" if rc == 0 else "FAIL"
                c.note = f"exit {rc}, {secs:.1f} s" + ("" if rc == 0 else "\n" + indent(script, "    $ ") +
                                                         "\n" + indent(out[-2000:], "    | "))
            commands.append(c)

    # The table.
    width = max((len(c.where) for c in commands), default=10)
    print(f"{'where'.ljust(width)}  {'kind':8}  {'result':7}  command: note")
    for c in commands:
        text = c.text if len(c.text) <= 100 else c.text[:97] + "..."
        print(f"{c.where.ljust(width)}  {c.kind:8}  {c.status:7}  {text}: {c.note}")
    print(f"\nblocks without nearfield/scripts commands (not shell, or text): {len(other_blocks)}: "
          + ", ".join(other_blocks))
    counts = {}
    for c in commands:
        counts[(c.kind, c.status)] = counts.get((c.kind, c.status), 0) + 1
    print("summary: " + ", ".join(f"{k} {s}: {n}" for (k, s), n in sorted(counts.items())) +
          f"; {time.monotonic() - t0:.1f} s")
    failed = [c for c in commands if c.status == "FAIL"]
    if a.keep:
        print(f"kept {root}")
    else:
        shutil.rmtree(root, ignore_errors=True)
    if failed:
        print(f"\n{len(failed)} doc command(s) failed:", file=sys.stderr)
        for c in failed:
            print(f"  {c.where}: {c.text}", file=sys.stderr)
        return 1
    return 0


def indent(text, prefix):
    return "\n".join(prefix + l for l in text.rstrip().split("\n"))


if __name__ == "__main__":
    sys.exit(main())
