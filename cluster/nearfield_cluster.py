"""nearfield-cluster: `nearfield reference` and `render` split into parts that run as Ray tasks,
and the bench sweep's targets as Ray tasks (docs/cluster.md).

The driver checks the scene and the options with a small part on this machine (a bad scene
fails here, with the scene's own error, before anything is submitted), splits the job into
`--parts` parts (bands of rows or sample ranges of a reference; frame ranges of a render), runs
every part that is not already in the cache as a Ray task (`nearfield reference ... --tile
--samples --part`, `nearfield render ... --frames-range --part`), stores each finished part in the
cache under a content hash, merges them with `nearfield merge` and moves the outputs into place
together. The merged image is bit for bit the one `nearfield reference -o` (or `nearfield render
--exact-sums -o`) writes. `sweep` runs bench_sweep once per target (cluster/sweep.py).
"""

import argparse
import hashlib
import io
import json
import os
import shutil
import socket
import subprocess
import sys
import tarfile
import tempfile
import time

CACHE_FORMAT = 1
# Fault injection for tests (docs/cluster.md, "Tests"): the task of part K exits the worker
# process in the middle of its first attempt (Ray retries it) / fails with an error.
FAULT_KILL = "NEARFIELD_CLUSTER_KILL_PART"
FAULT_FAIL = "NEARFIELD_CLUSTER_FAIL_PART"
FAULT_DIR = "NEARFIELD_CLUSTER_FAULT_DIR"

# Options passed through to `nearfield reference` unchanged: (flag, type, help).
PASSTHROUGH = [
    ("--spp", int, "camera samples per pixel"),
    ("--bounces", int, "0: direct light; 1: plus one bounce"),
    ("--only", str, "all | luminaires | environment | indirect"),
    ("--seed", int, "random seed"),
    ("--width", int, "image width"),
    ("--height", int, "image height"),
    ("--exposure", float, "tone mapping exposure for --png"),
    ("--gamma", float, "tone mapping gamma for --png"),
]


class ClusterError(Exception):
    """An error the user can act on; printed without a traceback."""


def repo_root():
    return os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def find_binary():
    path = os.environ.get("NEARFIELD_BIN") or os.path.join(repo_root(), "build", "nearfield")
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        raise ClusterError(f"{path}: no nearfield binary there (build it, docs/building.md, or set NEARFIELD_BIN)")
    return os.path.abspath(path)


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def reference_args(opts):
    """The `nearfield reference` options that decide the image (scene excluded)."""
    args = []
    for flag, _, _ in PASSTHROUGH:
        value = getattr(opts, flag[2:])
        if value is not None:
            args += [flag, str(value)]
    if opts.jitter:
        args.append("--jitter")
    return args


def read_part_header(path):
    with open(path, "rb") as f:
        return json.loads(f.readline())


def part_command(command, binary, scene, args, tile, samples, out):
    """The `nearfield` command line of a part: a reference's tile and samples, a render's frames."""
    if command == "render":
        return [binary, "-q", "render", scene, *args, "--frames-range", samples, "--part", out]
    return [binary, "-q", "reference", scene, *args, "--tile", tile, "--samples", samples, "--part", out]


def preflight(binary, scene, args, workdir, command="reference"):
    """A small part on this machine (a reference's pixel and sample; a render's first frame):
    checks scene and options, returns the part header."""
    out = os.path.join(workdir, "preflight.nfpart")
    cmd = part_command(command, binary, scene, args, "0,0,1,1", "0,1", out)
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise ClusterError(r.stderr.strip() or f"{binary} exited with {r.returncode}")
    return read_part_header(out)


def split(width, height, spp, parts, mode):
    """(tile, samples) strings of the parts: bands of rows, or sample (render: frame) ranges of the
    whole image."""
    if mode == "rows":
        n = min(parts, height)
        bounds = [height * i // n for i in range(n + 1)]
        return [(f"0,{a},{width},{b - a}", f"0,{spp}") for a, b in zip(bounds, bounds[1:])]
    n = min(parts, spp)
    bounds = [spp * i // n for i in range(n + 1)]
    return [(f"0,0,{width},{height}", f"{a},{b - a}") for a, b in zip(bounds, bounds[1:])]


def part_key(header, binary_hash, args, tile, samples):
    """Content hash of a part: scene files and settings (the binary's content key), tone mapping,
    the binary itself, the options and the part's pixels and samples."""
    text = json.dumps(
        {
            "format": CACHE_FORMAT,
            "content_key": header["content_key"],
            "tonemap": header["tonemap"],
            "binary": binary_hash,
            "args": args,
            "tile": tile,
            "samples": samples,
        },
        sort_keys=True,
    )
    return hashlib.sha256(text.encode()).hexdigest()[:32]


# ---- the task (runs on a worker) ---------------------------------------------------------------


def worker_name():
    return socket.gethostname()


def check_worker_files(binary, scene, inputs):
    """A missing binary or input on a worker names the worker and the file."""
    for path in [binary, scene, *inputs]:
        if not os.path.exists(path):
            raise ClusterError(f"worker {worker_name()}: {path}: no such file (docs/cluster.md, 'Where the files are')")


def maybe_inject_fault(index, proc):
    """Tests: exit this worker process in the middle of the first attempt of part K."""
    kill = os.environ.get(FAULT_KILL)
    if kill is not None and int(kill) == index:
        marker = os.path.join(os.environ.get(FAULT_DIR, tempfile.gettempdir()), f"nearfield-cluster-killed-{index}")
        if not os.path.exists(marker):
            open(marker, "w").close()
            time.sleep(0.2)
            proc.kill()
            os._exit(1)
    fail = os.environ.get(FAULT_FAIL)
    if fail is not None and int(fail) == index:
        proc.kill()
        proc.wait()  # reaped: this worker's next part sees a dead `serve` and starts another
        raise ClusterError(f"worker {worker_name()}: failed on purpose ({FAULT_FAIL})")


def unpack_bundle(bundle):
    """The shipped files (`--ship copy`): unpacked once per node into its temporary folder, by the
    archive's hash; returns the folder."""
    digest, data = bundle
    root = os.path.join(tempfile.gettempdir(), f"nearfield-cluster-{digest[:16]}")
    if not os.path.isdir(root):
        tmp = tempfile.mkdtemp(prefix=".nearfield-cluster-", dir=tempfile.gettempdir())
        with tarfile.open(fileobj=io.BytesIO(data), mode="r:gz") as tar:
            tar.extractall(tmp, filter="tar")
        try:
            os.rename(tmp, root)
        except OSError:  # another task of this node was first
            shutil.rmtree(tmp, ignore_errors=True)
    return root


SERVE_MARK = "nearfield-serve "


def pocl_env(threads):
    """PoCL's CPU threads limited to the CPUs Ray reserved for the task (PoCL 3: the first name;
    later versions: the second)."""
    return {**os.environ, "POCL_MAX_PTHREAD_COUNT": str(threads), "POCL_CPU_MAX_CU_COUNT": str(threads)}


def server(binary, threads):
    """This Ray worker process's `nearfield serve` (docs/cluster.md, "Per-part cost"), started on
    its first part and kept for the next ones; a new one when the last one died. Kept on `sys`: the
    task's functions arrive pickled by value, with fresh module globals each time."""
    servers = getattr(sys, "_nearfield_cluster_servers", None)
    if servers is None:
        servers = {}
        sys._nearfield_cluster_servers = servers
    proc = servers.get((binary, threads))
    if proc is None or proc.poll() is not None:
        log = tempfile.TemporaryFile()
        proc = subprocess.Popen([binary, "serve"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=log,
                                text=True, env=pocl_env(threads))
        proc.log = log
        servers[(binary, threads)] = proc
    return proc


def served(proc):
    """The answer of `nearfield serve` to the last request: (exit code, error)."""
    while True:
        line = proc.stdout.readline()
        if not line:
            proc.log.seek(0)
            tail = proc.log.read()[-2000:].decode(errors="replace").strip()
            raise ClusterError(f"worker {worker_name()}: nearfield serve exited with {proc.wait()}: {tail}")
        if line.startswith(SERVE_MARK):
            answer = json.loads(line[len(SERVE_MARK):])
            return answer["exit_code"], answer["error"].strip()


def run_part(index, binary, scene, inputs, args, tile, samples, threads, bundle=None, command="reference",
             serve=True):
    """Runs one part with the binary; returns (the part file's bytes, worker, seconds). With a
    bundle, binary, scene and inputs are paths inside it. A render's OpenCL (PoCL) threads are
    limited to `threads`, the CPUs Ray reserved for the task. `serve`: in this worker's `nearfield
    serve` process; else in a process of its own."""
    start = time.time()
    if bundle is not None:
        root = unpack_bundle(bundle)
        binary, scene = os.path.join(root, binary), os.path.join(root, scene)
        inputs = [os.path.join(root, p) for p in inputs]
    check_worker_files(binary, scene, inputs)
    with tempfile.TemporaryDirectory(prefix="nfpart-") as tmp:
        out = os.path.join(tmp, "part.nfpart")
        if command != "render":
            args = [*args, "--threads", str(threads)]
        cmd = part_command(command, binary, scene, args, tile, samples, out)
        if serve:
            request = json.dumps(cmd[1:]) + "\n"
            proc = server(binary, threads)
            try:
                proc.stdin.write(request)
                proc.stdin.flush()
            except BrokenPipeError:  # it died since its last part: another one
                proc.wait()
                proc = server(binary, threads)
                proc.stdin.write(request)
                proc.stdin.flush()
            maybe_inject_fault(index, proc)
            code, err = served(proc)
        else:
            proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                    env=pocl_env(threads))
            maybe_inject_fault(index, proc)
            _, err = proc.communicate()
            code, err = proc.returncode, err.strip()
        if code != 0:
            raise ClusterError(f"worker {worker_name()}: {err or 'exit ' + str(code)}")
        with open(out, "rb") as f:
            return f.read(), worker_name(), time.time() - start


# ---- shipping the binary and the scene ---------------------------------------------------------


def bundle_files(binary, scene, inputs):
    """`--ship copy`: the binary as bin/nearfield and the inputs under files/ (their layout relative
    to their common folder kept) in a tar.gz. Returns ((sha256, bytes), binary, scene, inputs),
    the paths relative to the archive's root."""
    files = sorted(set(inputs) | {scene})
    root = os.path.commonpath([os.path.dirname(f) for f in files])
    rel = {f: os.path.join("files", os.path.relpath(f, root)) for f in files}
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w:gz") as tar:
        tar.add(binary, arcname=os.path.join("bin", "nearfield"))
        for f in files:
            tar.add(f, arcname=rel[f])
    data = buf.getvalue()
    bundle = (hashlib.sha256(data).hexdigest(), data)
    return bundle, os.path.join("bin", "nearfield"), rel[scene], [rel[f] for f in inputs]


# ---- the driver --------------------------------------------------------------------------------


def check_address(address, timeout=3.0):
    """An unreachable --address fails within seconds, naming it."""
    if address in (None, "auto", "local"):
        return
    host, sep, port = address.rpartition(":")
    if not sep or not port.isdigit():
        raise ClusterError(f"--address {address}: expected auto or HOST:PORT")
    host = host.removeprefix("ray://")
    try:
        with socket.create_connection((host, int(port)), timeout=timeout):
            pass
    except OSError as e:
        raise ClusterError(f"--address {address}: cannot reach a Ray cluster there ({e})") from None


def init_ray(ray, opts):
    """Returns True when this call started Ray (and so must shut it down)."""
    if ray.is_initialized():
        return False
    kwargs = {"include_dashboard": False, "log_to_driver": False, "configure_logging": False}
    if opts.address:
        try:
            ray.init(address=opts.address, **kwargs)
        except Exception as e:  # noqa: BLE001 - Ray raises several kinds here
            raise ClusterError(f"--address {opts.address}: cannot join the Ray cluster ({e})") from None
    else:
        if opts.ray_temp_dir:
            kwargs["_temp_dir"] = os.path.abspath(opts.ray_temp_dir)
        ray.init(num_cpus=opts.num_cpus or os.cpu_count(), **kwargs)
    return True


class Progress:
    def __init__(self, total, cached, quiet):
        self.total, self.done, self.cached, self.quiet = total, cached, cached, quiet
        self.start = time.time()

    def part_done(self, index, worker, seconds):
        self.done += 1
        if self.quiet:
            return
        elapsed = time.time() - self.start
        computed = self.done - self.cached
        left = (self.total - self.done) * elapsed / computed if computed else 0.0
        print(f"nearfield-cluster: part {index} done on {worker} in {seconds:.1f} s; {self.done}/{self.total} "
              f"parts, {elapsed:.1f} s elapsed, ~{left:.0f} s left", file=sys.stderr, flush=True)


def run_parts(ray, todo, opts, binary, scene, inputs, args, progress, on_done):
    """Submits the parts (index, tile, samples) and calls on_done(index, data) as they finish. A
    failed part is reported after the others have finished (and are cached)."""
    env_vars = {k: os.environ[k] for k in (FAULT_KILL, FAULT_FAIL, FAULT_DIR) if k in os.environ}
    runtime_env = {"env_vars": env_vars} if env_vars else None
    ship = opts.ship or ("copy" if opts.address else "shared")
    bundle = None
    if ship == "copy":
        bundle, binary, scene, inputs = bundle_files(binary, scene, inputs)
        bundle = ray.put(bundle)  # sent to each node once, through Ray's object store
    # Workers do not have this module on their path: send run_part's code with the task.
    ray.cloudpickle.register_pickle_by_value(sys.modules[__name__])
    task = ray.remote(run_part).options(num_cpus=opts.threads, max_retries=opts.retries, runtime_env=runtime_env)
    serve = not opts.process_per_part
    pending = {task.remote(i, binary, scene, inputs, args, t, s, opts.threads, bundle, opts.command, serve): i
               for i, t, s in todo}
    failures = []
    while pending:
        ready, _ = ray.wait(list(pending), num_returns=1)
        index = pending.pop(ready[0])
        try:
            data, worker, seconds = ray.get(ready[0])
        except Exception as e:  # noqa: BLE001 - a task's error, or a worker lost for good
            failures.append(f"part {index} ({todo_part(todo, index)}): {getattr(e, 'cause', None) or e}")
            continue
        on_done(index, data)
        progress.part_done(index, worker, seconds)
    if failures:
        raise ClusterError("; ".join(failures))


def todo_part(todo, index):
    return next(f"tile {t}, samples {s}" if t else f"frames {s}" for i, t, s in todo if i == index)


def commit_outputs(binary, part_files, opts, summary):
    """nearfield merge into temporaries beside the outputs, then renames (all or nothing)."""
    targets = [("-o", opts.out)] + [(f, p) for f, p in (("--png", opts.png), ("--stats", opts.stats)) if p]
    tmp = tempfile.mkdtemp(prefix=".nearfield-cluster-", dir=os.path.dirname(os.path.abspath(opts.out)))
    try:
        temps = {flag: os.path.join(tmp, os.path.basename(p)) for flag, p in targets}
        cmd = [binary, "-q", "merge", *part_files]
        for flag, _ in targets:
            cmd += [flag, temps[flag]]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise ClusterError(f"nearfield merge: {r.stderr.strip()}")
        if opts.stats:
            with open(temps["--stats"]) as f:
                stats = json.load(f)
            stats["cluster"] = summary
            with open(temps["--stats"], "w") as f:
                json.dump(stats, f, indent=2)
                f.write("\n")
        for flag, path in targets:
            os.replace(temps[flag], path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def job_args(opts):
    """The options of the wrapped command that decide the image: reference's declared ones, or
    --frames and every option given for `nearfield render` (passed through unchanged)."""
    if opts.command == "render":
        return ["--frames", str(opts.frames), *opts.render_args]
    return reference_args(opts)


def run_job(opts):
    """`reference` or `render`: parts on Ray, cached, merged and committed."""
    for flag, path, ext in (("-o", opts.out, ".exr"), ("--png", opts.png, ".png"), ("--stats", opts.stats, ".json")):
        if path and not path.lower().endswith(ext):
            raise ClusterError(f"{flag} {path}: the file name must end in {ext}")
        if path and not os.path.isdir(os.path.dirname(os.path.abspath(path))):
            raise ClusterError(f"{flag} {path}: the folder does not exist")
    if opts.parts < 1:
        raise ClusterError(f"--parts must be >= 1, got {opts.parts}")
    check_address(opts.address)
    binary = find_binary()
    scene = os.path.abspath(opts.scene)
    args = job_args(opts)
    if opts.command == "render":
        opts.split = "frames"
    cache = os.path.abspath(opts.cache or os.path.join(os.path.expanduser("~"), ".cache", "nearfield-cluster"))
    os.makedirs(cache, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="nearfield-cluster-") as work:
        header = preflight(binary, opts.scene, args, work, opts.command)
    inputs = [p for p in header.get("inputs", []) if os.path.abspath(p) != scene]
    binary_hash = sha256_file(binary)
    parts = split(header["width"], header["height"], header["spp"], opts.parts, opts.split)
    if opts.command == "render":
        parts = [(None, s) for _, s in parts]
    files = {}
    todo = []
    for i, (tile, samples) in enumerate(parts):
        files[i] = os.path.join(cache, part_key(header, binary_hash, args, tile, samples) + ".nfpart")
        if not os.path.isfile(files[i]):
            todo.append((i, tile, samples))
    summary = {"parts": len(parts), "cached": len(parts) - len(todo), "computed": 0, "split": opts.split}
    if not opts.quiet:
        print(f"nearfield-cluster: {len(parts)} parts ({opts.split}), {summary['cached']} from the cache "
              f"({cache}), {len(todo)} to run", file=sys.stderr, flush=True)
    start = time.time()
    if todo:
        import ray  # noqa: PLC0415 - only needed when there is work

        started = init_ray(ray, opts)
        try:
            progress = Progress(len(parts), summary["cached"], opts.quiet)

            def store(index, data):
                tmp = f"{files[index]}.tmp{os.getpid()}"
                with open(tmp, "wb") as f:
                    f.write(data)
                os.replace(tmp, files[index])
                summary["computed"] += 1

            run_parts(ray, todo, opts, binary, scene, inputs, args, progress, store)
        finally:
            if started:
                ray.shutdown()
    summary["seconds"] = round(time.time() - start, 3)
    commit_outputs(binary, [files[i] for i in range(len(parts))], opts, summary)
    print(f"nearfield-cluster: {len(parts)} parts ({summary['computed']} computed, {summary['cached']} cached) "
          f"in {summary['seconds']:.1f} s; wrote {opts.out}")
    return summary


def add_ray_options(r):
    """The options of every subcommand about Ray and the cache."""
    r.add_argument("--address", help="auto or HOST:PORT of a Ray cluster (default: a local Ray)")
    r.add_argument("--num-cpus", type=int, help="local Ray's CPUs (default: all)")
    r.add_argument("--ship", choices=("shared", "copy"),
                   help="shared: binary and scene at the same paths on every worker (default without "
                        "--address); copy: sent through Ray's object store (default with --address)")
    r.add_argument("--retries", type=int, default=3, help="Ray retries of a part whose worker died")
    r.add_argument("--process-per-part", action="store_true",
                   help="run every part in a nearfield process of its own (default: one `nearfield serve` "
                        "process per Ray worker runs its parts)")
    r.add_argument("--cache", help="finished parts (default ~/.cache/nearfield-cluster)")
    r.add_argument("--ray-temp-dir", help="local Ray's session folder (default Ray's)")
    r.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")


def add_output_options(r):
    r.add_argument("scene")
    r.add_argument("-o", "--out", required=True, help="output OpenEXR")
    r.add_argument("--png", help="also a tone-mapped PNG")
    r.add_argument("--stats", help="also the merge's JSON stats, with the cluster's")
    r.add_argument("--parts", type=int, default=8, help="number of parts (default 8)")


def parser():
    p = argparse.ArgumentParser(prog="nearfield-cluster", description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("reference", help="a reference render in parts on Ray")
    add_output_options(r)
    for flag, typ, help_text in PASSTHROUGH:
        r.add_argument(flag, type=typ, help=help_text)
    r.add_argument("--jitter", action="store_true", help="jitter samples inside each pixel")
    r.add_argument("--threads", type=int, default=1, help="threads (and Ray CPUs) per part (default 1)")
    r.add_argument("--split", choices=("rows", "samples"), default="rows", help="bands of rows or sample ranges")
    add_ray_options(r)
    d = sub.add_parser("render", allow_abbrev=False, help="a progressive render in parts (frame ranges) on Ray; other options "
                                      "are passed to nearfield render (its settings overrides)")
    add_output_options(d)
    d.add_argument("--frames", type=int, default=1, help="progressive frames of the whole render (default 1)")
    d.add_argument("--threads", type=int, default=1, help="OpenCL (PoCL) threads and Ray CPUs per part (default 1)")
    add_ray_options(d)
    import sweep  # noqa: PLC0415 - cluster/sweep.py, beside this file

    sweep.add_parser(sub, add_ray_options)
    return p


def main(argv=None):
    p = parser()
    opts, extra = p.parse_known_args(argv)
    if opts.command == "render":
        opts.render_args = extra
    elif opts.command == "sweep":
        opts.sweep_args = extra
    elif extra:
        p.error(f"unrecognized arguments: {' '.join(extra)}")
    try:
        if opts.command == "sweep":
            import sweep  # noqa: PLC0415

            return sweep.run(opts)
        return run_job(opts)
    except ClusterError as e:
        print(f"nearfield-cluster: {e}", file=sys.stderr)
        raise SystemExit(1) from None
