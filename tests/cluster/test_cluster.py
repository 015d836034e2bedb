"""cluster/nearfield-cluster on a local Ray (2 CPUs) (docs/cluster.md, "Tests").

- a reference split into bands of rows and into sample ranges (one bounce) merges to the bits of
  `nearfield reference -o` on one machine;
- a render (luminaire, environment map and far-field light) split into frame ranges merges to the
  bits of `nearfield render --exact-sums -o`;
- a sweep split by target gives the points and references of bench_sweep on one machine (all but
  the timing columns), and a rerun takes every target from the cache;
- a worker killed in the middle of a part (fault injection) is retried, the image unchanged;
- after a run that failed in one part, a rerun computes that part alone (the others are cached);
- a bad scene fails fast with the scene's own error and leaves no output; an unreachable
  --address fails within seconds naming it; a missing file on a worker names the worker and file.

Usage: python test_cluster.py NEARFIELD_BIN. Exits 77 (skipped) when Ray is not installed.
"""

import csv
import os
import socket
import struct
import subprocess
import sys
import tempfile
import time
import unittest

try:
    import ray
except ImportError:
    print("test_cluster: ray is not installed (scripts/setup_python.sh): skipped")
    sys.exit(77)

HERE = os.path.dirname(os.path.abspath(__file__))
CLUSTER = os.path.join(HERE, "..", "..", "cluster")
sys.path.insert(0, CLUSTER)
import nearfield_cluster as nc  # noqa: E402

BIN = None
SCENE = """{
  "camera": { "position": [0.3, 1.6, 1.9], "target": [0, 0, 0], "fov_y": 60, "resolution": [24, 16] },
  "objects": [ { "type": "plane", "size": [4, 4] },
               { "type": "box", "size": [0.4, 0.4, 0.4], "transform": { "translate": [0, 0.2, 0] } } ],
  "luminaires": [ { "preset": "panel", "transform": { "translate": [0, 0.8, 0], "rotate": [90, 0, 0] } } ]
}"""
SETTINGS = ["--spp", "6", "--seed", "4", "--bounces", "1"]
# The render test's scene: three contributions (luminaire, environment map, far-field light).
RENDER_SCENE = """{
  "radiometric_to_photometric": 683,
  "camera": { "position": [0.3, 1.6, 1.9], "target": [0, 0, 0], "fov_y": 60, "resolution": [24, 16] },
  "objects": [ { "type": "plane", "size": [4, 4] },
               { "type": "box", "size": [0.4, 0.4, 0.4], "transform": { "translate": [0, 0.2, 0] } } ],
  "luminaires": [ { "preset": "panel", "transform": { "translate": [0.3, 0.8, 0], "rotate": [90, 0, 0] } } ],
  "environment": { "file": "sky.hdr" },
  "farfield_lights": [ { "file": "down.ies", "transform": { "translate": [-0.6, 1.5, 0.2], "rotate": [90, 0, 0] } } ]
}"""
IES = ("IESNA:LM-63-2002\n[TEST] test_cluster\nTILT=NONE\n1 -1 1.0 7 3 1 2 0 0 0\n1.0 1.0 0\n"
       "0 15 30 45 60 75 90\n0 90 180\n" + "300 280 240 180 110 40 0\n" * 3)
# Columns of points.csv that do not depend on timing (the images' errors, the plan's settings).
SWEEP_COLUMNS = ("study", "target", "method", "sampler", "K", "frames", "spp", "samples", "delta_e", "rel_mse",
                 "ref_key")


def write_sky(path, width=8, height=4):
    """A small Radiance .hdr (uncompressed RGBE scanlines) with a gradient."""
    with open(path, "wb") as f:
        f.write(f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n".encode())
        for y in range(height):
            for x in range(width):
                f.write(bytes([60 + 20 * x, 80 + 10 * y, 120, 126]))


def exr_pixels(path):
    """The pixel chunks of an OpenEXR file (everything after the header and the offset table):
    nearfield writes the same pixels as the same bytes (lossless, deterministic compression), so
    equal chunks mean equal float32 bits, whatever the attributes (date, parts) in the header."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:4] == b"\x76\x2f\x31\x01", f"{path}: not an OpenEXR file"
    pos = 8
    while data[pos] != 0:  # attributes: name\0 type\0 size value
        pos = data.index(b"\x00", pos) + 1
        pos = data.index(b"\x00", pos) + 1
        pos += 4 + struct.unpack_from("<i", data, pos)[0]
    first_chunk = struct.unpack_from("<Q", data, pos + 1)[0]
    return data[first_chunk:]


class ClusterTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        os.environ["NEARFIELD_BIN"] = BIN
        cls.tmp = tempfile.TemporaryDirectory(prefix="nfcluster-")
        cls.dir = cls.tmp.name
        cls.scene = os.path.join(cls.dir, "scene.json")
        with open(cls.scene, "w") as f:
            f.write(SCENE)
        cls.one = os.path.join(cls.dir, "one.exr")
        subprocess.run([BIN, "-q", "reference", cls.scene, *SETTINGS, "-o", cls.one], check=True)
        start = time.time()
        ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False,
                 _temp_dir=os.path.join(cls.dir, "ray"), configure_logging=False)
        print(f"ray.init: {time.time() - start:.1f} s", file=sys.stderr)

    @classmethod
    def tearDownClass(cls):
        ray.shutdown()
        cls.tmp.cleanup()

    def cluster(self, name, *extra, cache=None):
        out = os.path.join(self.dir, name + ".exr")
        argv = ["reference", self.scene, *SETTINGS, "-o", out, "--cache", cache or os.path.join(self.dir, name),
                "-q", *extra]
        return nc.main(argv), out

    def test_rows_and_samples_merge_to_one_machine_bits(self):
        summary, out = self.cluster("rows", "--parts", "3")
        self.assertEqual(summary["computed"], 3)
        self.assertEqual(exr_pixels(out), exr_pixels(self.one))
        summary, out = self.cluster("samples", "--parts", "4", "--split", "samples", "--ship", "copy")
        self.assertEqual(summary["computed"], 4)
        self.assertEqual(exr_pixels(out), exr_pixels(self.one))

    def test_killed_worker_is_retried(self):
        faults = os.path.join(self.dir, "faults")
        os.makedirs(faults)
        os.environ.update({nc.FAULT_KILL: "1", nc.FAULT_DIR: faults})
        try:
            summary, out = self.cluster("killed", "--parts", "2")
        finally:
            del os.environ[nc.FAULT_KILL], os.environ[nc.FAULT_DIR]
        self.assertTrue(os.path.exists(os.path.join(faults, "nearfield-cluster-killed-1")), "the fault was not injected")
        self.assertEqual(summary["computed"], 2)
        self.assertEqual(exr_pixels(out), exr_pixels(self.one))

    def test_rerun_computes_only_the_missing_parts(self):
        cache = os.path.join(self.dir, "resume-cache")
        os.environ[nc.FAULT_FAIL] = "2"
        try:
            with self.assertRaises(SystemExit):
                self.cluster("resume", "--parts", "4", cache=cache)
        finally:
            del os.environ[nc.FAULT_FAIL]
        self.assertFalse(os.path.exists(os.path.join(self.dir, "resume.exr")))
        self.assertEqual(len([f for f in os.listdir(cache) if f.endswith(".nfpart")]), 3)
        summary, out = self.cluster("resume", "--parts", "4", cache=cache)
        self.assertEqual((summary["computed"], summary["cached"]), (1, 3))
        self.assertEqual(exr_pixels(out), exr_pixels(self.one))
        summary, _ = self.cluster("resume", "--parts", "4", cache=cache)
        self.assertEqual((summary["computed"], summary["cached"]), (0, 4))

    def test_render_frame_ranges_merge_to_one_machine_bits(self):
        scene = os.path.join(self.dir, "render.json")
        with open(scene, "w") as f:
            f.write(RENDER_SCENE)
        with open(os.path.join(self.dir, "down.ies"), "w") as f:
            f.write(IES)
        write_sky(os.path.join(self.dir, "sky.hdr"))
        one = os.path.join(self.dir, "render-one.exr")
        subprocess.run([BIN, "-q", "render", scene, "--frames", "3", "--exact-sums", "-o", one], check=True)
        out = os.path.join(self.dir, "render.exr")
        summary = nc.main(["render", scene, "--frames", "3", "-o", out, "--parts", "2", "-q",
                           "--cache", os.path.join(self.dir, "render-cache")])
        self.assertEqual(summary["computed"], 2)
        self.assertEqual(exr_pixels(out), exr_pixels(one))

    def test_sweep_by_target_equals_one_machine(self):
        bench = os.path.join(os.path.dirname(BIN), "bench", "bench_sweep")
        if not os.path.isfile(bench):
            self.skipTest(f"{bench} is not built")
        # The kmax study: its two points per target differ only in a run-time argument, so each target
        # builds one sampling program (a PoCL build costs seconds; the sampler study built three). What
        # is checked is the split by target, not the study (bench_sweep_quick runs every study).
        args = ["--quick", "--no-scene", "--luminaires", "car1,bike", "--studies", "kmax", "--res", "16"]
        one = os.path.join(self.dir, "sweep-one")
        subprocess.run([bench, "-q", *args, "--out", one], check=True)
        out = os.path.join(self.dir, "sweep")
        cache = os.path.join(self.dir, "sweep-cache")
        summary = nc.main(["sweep", *args, "--out", out, "--cache", cache, "-q"])
        self.assertEqual((summary["targets"], summary["computed"]), (2, 2))

        def rows(folder):
            with open(os.path.join(folder, "points.csv")) as f:
                return [tuple(r[c] for c in SWEEP_COLUMNS) for r in csv.DictReader(f)]

        self.assertGreater(len(rows(one)), 2)
        self.assertEqual(rows(out), rows(one))
        summary = nc.main(["sweep", *args, "--out", out, "--cache", cache, "-q"])
        self.assertEqual((summary["computed"], summary["cached"]), (0, 2))

    def test_missing_file_on_a_worker_names_worker_and_file(self):
        missing = os.path.join(self.dir, "nowhere", "nearfield")
        with self.assertRaises(nc.ClusterError) as e:
            nc.run_part(0, missing, self.scene, [], [], "0,0,1,1", "0,1", 1)
        self.assertIn(socket.gethostname(), str(e.exception))
        self.assertIn(missing, str(e.exception))


class ClusterCliTest(unittest.TestCase):
    """The command as a process, failing before Ray starts."""

    def run_cli(self, *args):
        start = time.time()
        r = subprocess.run([sys.executable, os.path.join(CLUSTER, "nearfield-cluster"), *args],
                           capture_output=True, text=True, env={**os.environ, "NEARFIELD_BIN": BIN}, timeout=60)
        return r, time.time() - start

    def test_bad_scene_fails_fast_without_output(self):
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "bad.json")
            with open(scene, "w") as f:
                f.write('{ "camera": { "position": [0, 1, 2], "target": [0, 0, 0], "fov_y": 50, "resolution": [8, 8] },'
                        ' "objects": [ { "type": "plane", "material": "nope" } ] }')
            r, seconds = self.run_cli("reference", scene, "-o", os.path.join(d, "out.exr"), "--cache", d)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("bad.json", r.stderr)
            self.assertIn("nope", r.stderr)
            self.assertLess(seconds, 30)
            self.assertEqual(sorted(os.listdir(d)), ["bad.json"])

    def test_unreachable_address_fails_within_seconds(self):
        with socket.socket() as s:  # a local port nobody listens on
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "scene.json")
            with open(scene, "w") as f:
                f.write(SCENE)
            address = f"127.0.0.1:{port}"
            r, seconds = self.run_cli("reference", scene, "-o", os.path.join(d, "o.exr"), "--address", address)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn(address, r.stderr)
            self.assertLess(seconds, 10)
            self.assertEqual(os.listdir(d), ["scene.json"])


if __name__ == "__main__":
    BIN = os.path.abspath(sys.argv.pop(1))
    unittest.main(verbosity=2)
