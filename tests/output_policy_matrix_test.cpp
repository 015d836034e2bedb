// The output policy as a generated matrix (issue 28, docs/robustness.md "Outputs"): every command
// that writes files x every output option x every way an output can be wrong. Each case gives one
// bad output (the command's other outputs get fresh, valid paths) and must end with a non-zero
// exit, a message naming the bad path, and the work directory exactly as it was: no input changed,
// no file created, no temporary left.
//
// File outputs (render, reference, probe --grid, merge, luminaire farfield, view) are wrong as:
//   input        an input of the job with the output's extension (else the main input)
//   alias        that input spelled through "sub/.."
//   symlink      a symbolic link to it
//   hard link    a hard link to it
//   other output the same file as another output of the command (a hard link with its extension)
//   directory    an existing directory named like an output
//   missing dir  a file in a directory that does not exist
//   under a file a file "inside" a regular file
//   extension    a name with the wrong extension
// Directory outputs (luminaire gen, luminaire import, pattern: -o DIR) are wrong as a regular
// file, a path under a regular file, and (gen, import) a DIR whose output file name is a directory.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/image_io.h"
#include "luminaire/rayset.h"
#include "luminaire/rayset_tm25.h"
#include "robustness_support.h"
#include "support/testing.h"

namespace {

namespace fs = std::filesystem;
using nf::robustness::q;
using nf::robustness::slurp;
using nf::robustness::write;
using nf::testing::run_nearfield;

// Everything under `dir`: regular files by content, links by target, directories by name.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> s;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string rel = fs::relative(e.path(), dir).string();
    if (e.is_symlink())
      s[rel] = "link:" + fs::read_symlink(e.path()).string();
    else if (e.is_directory())
      s[rel] = "dir";
    else
      s[rel] = "file:" + slurp(e.path());
  }
  return s;
}

// The differences between two snapshots, for the failure message.
std::string differences(const std::map<std::string, std::string>& a, const std::map<std::string, std::string>& b) {
  std::string out;
  for (const auto& [k, v] : a)
    if (!b.count(k))
      out += " removed " + k + ";";
    else if (b.at(k) != v)
      out += " changed " + k + ";";
  for (const auto& [k, v] : b)
    if (!a.count(k)) out += " created " + k + ";";
  return out;
}

struct Output {
  std::string flag, ext;
};

struct FileCommand {
  std::string args;                 // the command and its inputs, before the outputs
  std::vector<Output> outputs;      // file outputs
  std::vector<fs::path> inputs;     // the job's input files (the first is the main input)
};

// The work directory shared by the cases: a luminaire (manifest + EXR), an environment map, a
// scene naming both, a reference part, a TM-25 ray file and a viewer script.
struct Work {
  fs::path dir, scene, manifest, image, env, part, rays, script;
};

const Work& work() {
  static const Work w = [] {
    Work k;
    k.dir = nf::testing::temp_dir("output_matrix");
    fs::create_directories(k.dir / "sub");
    auto r = run_nearfield("luminaire gen --preset panel --res-scale 0.05 -o " + q(k.dir / "lum"));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    k.manifest = k.dir / "lum" / "panel.json";
    k.image = k.dir / "lum" / "panel.exr";
    nf::Image sky(8, 4, 3);
    for (float& v : sky.pixels) v = 0.25f;
    k.env = k.dir / "sky.exr";
    nf::write_exr(k.env, sky);
    k.scene = write(k.dir, "scene.json", R"({
  "camera": { "position": [0.3, 1.6, 1.9], "target": [0, 0, 0], "fov_y": 60, "resolution": [16, 10] },
  "objects": [ { "type": "plane", "size": [4, 4] } ],
  "luminaires": [ { "manifest": "lum/panel.json", "transform": { "translate": [0, 0.5, 0], "rotate": [90, 0, 0] } } ],
  "environment": { "file": "sky.exr" },
  "render": { "spp": 4 } })");
    k.part = k.dir / "p.nfpart";
    r = run_nearfield("reference " + q(k.scene) + " --spp 1 --part " + q(k.part));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    nf::lum::RaySet rs;
    rs.kind = nf::lum::FluxKind::luminous;
    rs.format = "generated";
    for (int i = 0; i < 400; ++i) {
      const double a = 2.399963 * i, s = std::sqrt((i % 8 + 0.5) / 8.0);
      rs.add({(i % 20) * 5e-5 - 5e-4, (i / 20) * 5e-5 - 5e-4, 0.0},
             {s * std::cos(a), s * std::sin(a), std::sqrt(1.0 - s * s)}, 1.0 / 400.0);
    }
    k.rays = k.dir / "rays.TM25RAY";
    nf::lum::write_tm25(k.rays, rs);
    k.script = write(k.dir, "quit.script", "quit\n");
    write(k.dir, "afile.txt", "a regular file");
    return k;
  }();
  return w;
}

// The first input with extension `ext`, else the main input.
fs::path input_like(const FileCommand& c, const std::string& ext) {
  for (const auto& p : c.inputs)
    if (p.extension() == ext) return p;
  return c.inputs.front();
}

// Runs `c` with output `k` at `bad` (and output `twin`, when >= 0, at `twin_path`) and checks the
// policy.
void expect_refused(const FileCommand& c, std::size_t k, const fs::path& bad, const std::string& label,
                    int twin = -1, const fs::path& twin_path = {}) {
  const Work& w = work();
  SCOPED_TRACE(c.args + " " + c.outputs[k].flag + " [" + label + "] " + bad.string());
  std::string cmd = c.args;
  for (std::size_t i = 0; i < c.outputs.size(); ++i) {
    const fs::path p = i == k                         ? bad
                       : static_cast<int>(i) == twin ? twin_path
                                                     : w.dir / "fresh" / ("ok" + std::to_string(i) + c.outputs[i].ext);
    cmd += " " + c.outputs[i].flag + " " + q(p);
  }
  fs::create_directories(w.dir / "fresh");
  const auto before = snapshot(w.dir);
  const auto r = run_nearfield(cmd);
  EXPECT_NE(r.exit_code, 0) << r.out;
  EXPECT_NE(r.err.find(bad.filename().string()), std::string::npos) << r.err;
  EXPECT_EQ(differences(before, snapshot(w.dir)), "");
}

void run_matrix(const FileCommand& c) {
  const Work& w = work();
  for (std::size_t k = 0; k < c.outputs.size(); ++k) {
    const std::string& ext = c.outputs[k].ext;
    const fs::path input = input_like(c, ext);
    expect_refused(c, k, input, "input");
    expect_refused(c, k, input.parent_path() / ".." / input.parent_path().filename() / input.filename(), "alias");
    const fs::path link = w.dir / ("link" + ext), hard = w.dir / ("hard" + ext);
    fs::remove(link);
    fs::create_symlink(input, link);
    expect_refused(c, k, link, "symlink");
    fs::remove(link);
    fs::remove(hard);
    fs::create_hard_link(input, hard);
    expect_refused(c, k, hard, "hard link");
    fs::remove(hard);
    if (c.outputs.size() > 1) {
      // Another output names the same file: an existing file and a hard link to it, each with its
      // option's extension (the same path would fail on the extension first).
      const std::size_t t = (k + 1) % c.outputs.size();
      const fs::path same = w.dir / ("same" + ext), twin = w.dir / ("same_twin" + c.outputs[t].ext);
      write(w.dir, same.filename().string(), "an earlier result");
      fs::remove(twin);
      if (c.outputs[t].ext == ext)
        expect_refused(c, k, same, "other output", static_cast<int>(t), same);
      else {
        fs::create_hard_link(same, twin);
        expect_refused(c, k, same, "other output", static_cast<int>(t), twin);
      }
      fs::remove(twin);
      fs::remove(same);
    }
    fs::create_directories(w.dir / ("folder" + ext));
    expect_refused(c, k, w.dir / ("folder" + ext), "directory");
    fs::remove(w.dir / ("folder" + ext));
    expect_refused(c, k, w.dir / "missing" / ("x" + ext), "missing dir");
    expect_refused(c, k, w.dir / "afile.txt" / ("x" + ext), "under a file");
    expect_refused(c, k, w.dir / "x.wrong", "extension");
  }
}

TEST(OutputPolicyMatrix, Render) {
  const Work& w = work();
  run_matrix({"render " + q(w.scene),
              {{"-o", ".exr"},
               {"--png", ".png"},
               {"--stats", ".json"},
               {"--illuminance", ".exr"},
               {"--false-colour luminance", ".png"},
               {"--false-colour illuminance", ".png"}},
              {w.scene, w.manifest, w.image, w.env}});
}

TEST(OutputPolicyMatrix, Reference) {
  const Work& w = work();
  run_matrix({"reference " + q(w.scene) + " --spp 1", {{"-o", ".exr"}, {"--png", ".png"}, {"--stats", ".json"}},
              {w.scene, w.manifest, w.image, w.env}});
}

TEST(OutputPolicyMatrix, ProbeGrid) {
  const Work& w = work();
  run_matrix({"probe " + q(w.manifest) + " --grid '-1,-1,-1;0,0,2;2,0,0'", {{"--csv", ".csv"}, {"--png", ".png"}},
              {w.manifest, w.image}});
}

TEST(OutputPolicyMatrix, Merge) {
  const Work& w = work();
  run_matrix({"merge " + q(w.part), {{"-o", ".exr"}, {"--png", ".png"}, {"--stats", ".json"}}, {w.part}});
}

TEST(OutputPolicyMatrix, LuminaireFarfield) {
  const Work& w = work();
  run_matrix({"luminaire farfield " + q(w.manifest), {{"-o", ".ies"}}, {w.manifest, w.image}});
}

TEST(OutputPolicyMatrix, Viewer) {
  const Work& w = work();
  run_matrix({"view " + q(w.scene) + " --script " + q(w.script), {{"--screenshot", ".png"}, {"--stats", ".json"}},
              {w.scene, w.manifest, w.image, w.env, w.script}});
}

// Directory outputs: -o DIR.
void expect_dir_refused(const std::string& args, const fs::path& bad, const std::string& label) {
  const Work& w = work();
  SCOPED_TRACE(args + " -o [" + label + "] " + bad.string());
  const auto before = snapshot(w.dir);
  const auto r = run_nearfield(args + " -o " + q(bad));
  EXPECT_NE(r.exit_code, 0) << r.out;
  EXPECT_NE(r.err.find(bad.filename().string()), std::string::npos) << r.err;
  EXPECT_EQ(differences(before, snapshot(w.dir)), "");
}

void run_dir_matrix(const std::string& args, const std::string& output_file) {
  const Work& w = work();
  expect_dir_refused(args, w.dir / "afile.txt", "a regular file");
  expect_dir_refused(args, w.dir / "afile.txt" / "out", "under a file");
  if (output_file.empty()) return;
  fs::create_directories(w.dir / "occupied" / output_file);
  expect_dir_refused(args, w.dir / "occupied", "output name is a directory");
  fs::remove_all(w.dir / "occupied");
}

TEST(OutputPolicyMatrix, LuminaireGen) {
  run_dir_matrix("luminaire gen --preset panel --res-scale 0.05", "panel.json");
}

TEST(OutputPolicyMatrix, LuminaireImport) {
  run_dir_matrix("luminaire import " + q(work().rays) + " --grid 4x4 --resolution 12 --axis 0,0,1", "rays.json");
}

TEST(OutputPolicyMatrix, Pattern) { run_dir_matrix("pattern", ""); }

}  // namespace
