// Frame time per step against K and resolution, with a still and a moving camera (issue 25,
// docs/rendering.md "Frame time per step"): the viewer's loop without a window. For each
// resolution and K a Renderer renders, as the viewer does, a frame and its display (Step 3 on
// the device and the 8-bit image shown in GL):
//   first   the first frame (programs and Step 0 built before, as the viewer's first frame is)
//   still   --still frames with the camera still (progressive accumulation)
//   moving  --moving frames, each from a new view (the camera orbits the target by --orbit-deg per
//           frame): every frame reruns Step 0 (G-buffer, read-back, visibility) and restarts the
//           accumulation
// and prints one CSV row per (mode, resolution, K): mean ms per frame of each step, fps, samples
// per second and the process CPU time per frame (on a shared machine, CPU ms ~ cores x wall ms when
// the program has the cores to itself). Machine, load and device in the first lines (# comments).
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "bench/sweep/machine.h"
#include "core/error.h"
#include "core/timer.h"
#include "render/frame.h"
#include "scene/scene.h"

namespace {

struct Options {
  std::string scene = NEARFIELD_SOURCE_DIR "/scenes/default.json";
  std::string resolutions = "320x180";
  std::string spps = "16";
  int still = 10, moving = 10;
  double orbit_deg = 1.0;
  std::string visibility_pass;  // empty: the scene's
  std::string out;              // CSV file (also printed)
  std::string label;            // a column to tell runs apart (e.g. before / after)
};

double cpu_ms() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-3;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

// One frame as the viewer renders it: the frame, then its display (Step 3).
nf::render::StepTimes frame(nf::render::Renderer& r) {
  r.render_frame();
  r.tonemap_display();
  return r.last_times();
}

struct Row {
  std::string mode;
  int width = 0, height = 0, spp = 0, frames = 0;
  nf::render::StepTimes t;  // summed over the frames
  double loop_ms = 0, cpu = 0;
};

std::string csv_header() {
  return "label,mode,width,height,spp,frames,fps,loop_ms,wall_ms,gbuffer_ms,gbuffer_readback_ms,shadow_maps_ms,"
         "visibility_ms,step0_other_ms,step1_ms,step2_ms,cl_other_ms,accumulation_ms,step3_ms,msamples_per_s,"
         "cpu_ms_per_frame";
}

std::string csv_row(const std::string& label, const Row& r) {
  const double n = std::max(r.frames, 1);
  const auto& t = r.t;
  const double step0_other = t.luminaire_view_ms + t.surfaces_upload_ms + t.visibility_upload_ms;
  return fmt::format(
      "{},{},{},{},{},{},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:."
      "2f},{:.1f}",
      label, r.mode, r.width, r.height, r.spp, r.frames, 1e3 * n / r.loop_ms, r.loop_ms / n, t.wall_ms / n,
      t.gbuffer_ms / n, t.gbuffer_readback_ms / n, t.shadow_maps_ms / n, t.visibility_ms / n, step0_other / n,
      t.step1_ms / n, t.step2_ms / n, t.cl_other_ms() / n, (t.readback_ms + t.accumulate_ms) / n, t.step3_ms / n,
      static_cast<double>(t.samples) / (r.loop_ms * 1e3), r.cpu / n);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Frame time per step vs K and resolution, still and moving camera (docs/rendering.md)"};
  app.add_option("--scene", o.scene, "Scene file")->capture_default_str();
  app.add_option("--res", o.resolutions, "Resolutions, comma-separated WxH")->capture_default_str();
  app.add_option("--spp", o.spps, "K values, comma-separated")->capture_default_str();
  app.add_option("--still", o.still, "Still frames after the first")->capture_default_str();
  app.add_option("--moving", o.moving, "Moving-camera frames")->capture_default_str();
  app.add_option("--orbit-deg", o.orbit_deg, "Camera orbit per moving frame (degrees)")->capture_default_str();
  app.add_option("--visibility-pass", o.visibility_pass, "opencl or gl (default: the scene's)");
  app.add_option("--out", o.out, "Also write the CSV here");
  app.add_option("--label", o.label, "Label column (e.g. before/after)");
  CLI11_PARSE(app, argc, argv);
  try {
    std::vector<std::string> lines;
    nf::cl::Runtime rt;
    const nf::bench::MachineInfo m = nf::bench::collect_machine(rt);
    lines.push_back(fmt::format("# cpu: {} ({}, {} cores); OpenCL: {}; load average at start: {}; {}", m.cpu_model,
                                m.isa, m.cores, m.cl_device.name, m.loadavg, m.date_utc));
    lines.push_back(fmt::format("# scene {}; commit {}", o.scene, m.git_commit));
    lines.push_back(csv_header());
    std::fputs((lines[0] + "\n" + lines[1] + "\n" + lines[2] + "\n").c_str(), stdout);
    for (const auto& res : split(o.resolutions))
      for (const auto& k : split(o.spps)) {
        int w = 0, h = 0;
        if (std::sscanf(res.c_str(), "%dx%d", &w, &h) != 2) nf::fail(fmt::format("--res: '{}' is not WxH", res));
        nf::scene::Scene s = nf::scene::load_scene(o.scene);
        s.camera.width = w;
        s.camera.height = h;
        s.render.spp = std::stoi(k);
        if (!o.visibility_pass.empty()) s.render.visibility_pass = o.visibility_pass;
        nf::render::RendererOptions ro;
        ro.runtime = &rt;
        nf::render::Renderer r(s, ro);
        std::vector<Row> rows;
        const auto run = [&](const std::string& mode, int frames, bool move) {
          Row row{mode, w, h, s.render.spp, frames, {}, 0.0, 0.0};
          for (int f = 0; f < frames; ++f) {
            if (move) {
              nf::scene::Camera c = r.camera();
              const glm::dmat4 rot = glm::rotate(glm::dmat4(1.0), glm::radians(o.orbit_deg), c.up);
              c.position = c.target + glm::dvec3(rot * glm::dvec4(c.position - c.target, 0.0));
              r.set_camera(c);
            }
            const double c0 = cpu_ms();
            nf::Timer loop;
            const nf::render::StepTimes t = frame(r);
            row.loop_ms += loop.ms();
            row.cpu += cpu_ms() - c0;
            row.t += t;
          }
          rows.push_back(row);
        };
        run("first", 1, false);
        run("still", o.still, false);
        run("moving", o.moving, true);
        for (const auto& row : rows) {
          if (row.frames == 0) continue;
          lines.push_back(csv_row(o.label, row));
          std::fputs((lines.back() + "\n").c_str(), stdout);
          std::fflush(stdout);
        }
      }
    lines.push_back(fmt::format("# load average at end: {}", nf::bench::read_loadavg()));
    std::fputs((lines.back() + "\n").c_str(), stdout);
    if (!o.out.empty()) {
      std::ofstream f(o.out);
      for (const auto& l : lines) f << l << "\n";
      if (!f) nf::fail(fmt::format("{}: cannot write", o.out));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_frame: %s\n", e.what());
    return 1;
  }
  return 0;
}
