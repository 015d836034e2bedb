"""nearfield-cluster sweep: the bench sweep (bench/README.md, bench_sweep) with its targets as Ray
tasks (docs/cluster.md, "nearfield-cluster sweep").

A target is a close-up luminaire or the scene; its reference and all its points run in one task
(`bench_sweep --luminaires X --no-scene`, or `--luminaires none` for the scene), because the points
are measured against that reference and share its renderer. The driver asks bench_sweep for the
plan (`--print-plan`: a bad option fails here, before Ray starts), runs every target not already in
the cache, keeps each finished target's tables in the cache under a content hash (a rerun resumes),
and writes the concatenated points.csv, references.csv, breakdown.csv and meta.json into --out
together.
"""

import csv
import hashlib
import io
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import nearfield_cluster as nc

TABLES = ("points.csv", "references.csv", "breakdown.csv")
SWEEP_FORMAT = 1


def add_parser(sub, add_ray_options):
    s = sub.add_parser("sweep", allow_abbrev=False,
                       help="the bench sweep, one Ray task per target; other options are bench_sweep's")
    s.add_argument("--out", required=True, help="folder for points.csv, references.csv, breakdown.csv, meta.json")
    s.add_argument("--luminaires", help="close-ups (bench_sweep --luminaires; default: the plan's)")
    s.add_argument("--no-scene", action="store_true", help="no scene target")
    s.add_argument("--bench-cache", help="bench_sweep's reference cache (default <out>/cache; on a cluster: a "
                                         "shared path)")
    s.add_argument("--threads", type=int, default=1, help="OpenCL (PoCL) threads and Ray CPUs per target (default 1)")
    add_ray_options(s)


def find_bench_binary(nearfield):
    path = os.environ.get("NEARFIELD_BENCH_SWEEP") or os.path.join(os.path.dirname(nearfield), "bench", "bench_sweep")
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        raise nc.ClusterError(f"{path}: no bench_sweep there (build the bench_sweep target, or set NEARFIELD_BENCH_SWEEP)")
    return os.path.abspath(path)


def plan(bench, args):
    r = subprocess.run([bench, *args, "--print-plan"], capture_output=True, text=True)
    if r.returncode != 0:
        raise nc.ClusterError(r.stderr.strip() or f"{bench} exited with {r.returncode}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def run_target(index, bench, args, threads):
    """One target of the sweep (runs on a worker): its tables' bytes, the worker, seconds."""
    start = time.time()
    nc.check_worker_files(bench, "/", [])
    with tempfile.TemporaryDirectory(prefix="nfsweep-") as tmp:
        env = {**os.environ, "POCL_MAX_PTHREAD_COUNT": str(threads), "POCL_CPU_MAX_CU_COUNT": str(threads)}
        proc = subprocess.Popen([bench, "-q", *args, "--out", tmp], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, env=env)
        nc.maybe_inject_fault(index, proc)
        _, err = proc.communicate()
        if proc.returncode != 0:
            raise nc.ClusterError(f"worker {nc.worker_name()}: {err.strip() or 'exit ' + str(proc.returncode)}")
        files = {}
        for name in (*TABLES, "meta.json"):
            with open(os.path.join(tmp, name), "rb") as f:
                files[name] = f.read()
        return files, nc.worker_name(), time.time() - start


def concat_csv(chunks):
    """The tables of the targets as one: the header once, the rows in target order."""
    out = io.StringIO()
    writer = None
    for data in chunks:
        rows = list(csv.reader(io.StringIO(data.decode())))
        if not rows:
            continue
        if writer is None:
            writer = csv.writer(out, lineterminator="\n")
            writer.writerow(rows[0])
            header = rows[0]
        elif rows[0] != header:
            raise nc.ClusterError(f"the targets' tables have different columns ({rows[0]} vs {header})")
        writer.writerows(rows[1:])
    return out.getvalue().encode()


def merge_meta(metas, summary):
    """meta.json of the whole sweep: the first target's machine and settings, every target, the
    points added up, each task's own meta under cluster.tasks."""
    meta = dict(metas[0])
    meta["targets"] = [t for m in metas for t in m.get("targets", [])]
    meta["points"] = sum(m.get("points", 0) for m in metas)
    meta["complete"] = all(m.get("complete", False) for m in metas)
    meta["wall_s"] = summary["seconds"]
    meta["cluster"] = {**summary, "tasks": [{"command": m.get("command"), "machine": m.get("machine"),
                                             "wall_s": m.get("wall_s"), "load_start": m.get("load_start"),
                                             "load_end": m.get("load_end")} for m in metas]}
    return (json.dumps(meta, indent=2) + "\n").encode()


def run(opts):
    nc.check_address(opts.address)
    nearfield = nc.find_binary()
    bench = find_bench_binary(nearfield)
    out = os.path.abspath(opts.out)
    if not os.path.isdir(os.path.dirname(out)):
        raise nc.ClusterError(f"--out {opts.out}: the folder above it does not exist")
    common = list(opts.sweep_args)
    bench_cache = os.path.abspath(opts.bench_cache or os.path.join(out, "cache"))
    given = [*common, *(["--luminaires", opts.luminaires] if opts.luminaires else []),
             *(["--no-scene"] if opts.no_scene else [])]
    p = plan(bench, given)
    targets = [["--luminaires", c, "--no-scene"] for c in p["closeups"]]
    if p["scene"]:
        targets.append(["--luminaires", "none"])
    if not targets:
        raise nc.ClusterError("the sweep has no targets (--luminaires none and --no-scene)")
    cache = os.path.abspath(opts.cache or os.path.join(os.path.expanduser("~"), ".cache", "nearfield-cluster"))
    os.makedirs(cache, exist_ok=True)
    bench_hash = nc.sha256_file(bench)
    dirs, todo = {}, []
    for i, t in enumerate(targets):
        key = hashlib.sha256(json.dumps({"format": SWEEP_FORMAT, "bench": bench_hash, "args": common, "target": t},
                                        sort_keys=True).encode()).hexdigest()[:32]
        dirs[i] = os.path.join(cache, f"sweep-{key}")
        if not os.path.isfile(os.path.join(dirs[i], "meta.json")):
            todo.append((i, t))
    summary = {"targets": len(targets), "cached": len(targets) - len(todo), "computed": 0, "points": p["points"]}
    if not opts.quiet:
        print(f"nearfield-cluster: sweep of {p['points']} points in {len(targets)} targets, {summary['cached']} "
              f"from the cache ({cache}), {len(todo)} to run", file=sys.stderr, flush=True)
    start = time.time()
    if todo:
        import ray  # noqa: PLC0415

        started = nc.init_ray(ray, opts)
        try:
            env_vars = {k: os.environ[k] for k in (nc.FAULT_KILL, nc.FAULT_FAIL, nc.FAULT_DIR) if k in os.environ}
            ray.cloudpickle.register_pickle_by_value(sys.modules[__name__])
            ray.cloudpickle.register_pickle_by_value(nc)
            task = ray.remote(run_target).options(num_cpus=opts.threads, max_retries=opts.retries,
                                                  runtime_env={"env_vars": env_vars} if env_vars else None)
            pending = {task.remote(i, bench, [*common, "--cache", bench_cache, *t], opts.threads): i for i, t in todo}
            progress = nc.Progress(len(targets), summary["cached"], opts.quiet)
            failures = []
            while pending:
                ready, _ = ray.wait(list(pending), num_returns=1)
                i = pending.pop(ready[0])
                try:
                    files, worker, seconds = ray.get(ready[0])
                except Exception as e:  # noqa: BLE001
                    failures.append(f"target {' '.join(targets[i])}: {getattr(e, 'cause', None) or e}")
                    continue
                tmp = tempfile.mkdtemp(prefix=".sweep-", dir=cache)
                for name, data in files.items():
                    with open(os.path.join(tmp, name), "wb") as f:
                        f.write(data)
                shutil.rmtree(dirs[i], ignore_errors=True)
                os.replace(tmp, dirs[i])
                summary["computed"] += 1
                progress.part_done(i, worker, seconds)
            if failures:
                raise nc.ClusterError("; ".join(failures))
        finally:
            if started:
                ray.shutdown()
    summary["seconds"] = round(time.time() - start, 3)
    commit(out, dirs, len(targets), summary)
    print(f"nearfield-cluster: sweep of {len(targets)} targets ({summary['computed']} computed, {summary['cached']} "
          f"cached) in {summary['seconds']:.1f} s; wrote {out}")
    return summary


def commit(out, dirs, n, summary):
    """The merged tables into a temporary folder beside --out, then renamed into it."""
    def read(i, name):
        with open(os.path.join(dirs[i], name), "rb") as f:
            return f.read()

    os.makedirs(out, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix=".nearfield-sweep-", dir=out)
    try:
        outputs = {name: concat_csv([read(i, name) for i in range(n)]) for name in TABLES}
        outputs["meta.json"] = merge_meta([json.loads(read(i, "meta.json")) for i in range(n)], summary)
        for name, data in outputs.items():
            with open(os.path.join(tmp, name), "wb") as f:
                f.write(data)
        for name in outputs:
            os.replace(os.path.join(tmp, name), os.path.join(out, name))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
