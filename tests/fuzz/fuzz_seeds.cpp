// Writes the fuzzers' seed corpus with the project's own writers:
//   fuzz_seeds OUT_DIR [SCENES_DIR [DATA_DIR]]
//   OUT_DIR/manifest/       manifests (small luminaire, every generator preset at a small scale)
//   OUT_DIR/luminaire_exr/  2 x 2 x (8 x 8) luminaire EXRs: float and half, RGB and Y
//   OUT_DIR/scene/          SCENES_DIR/*.json and a scene naming small.json / small.gltf
//   OUT_DIR/gltf/           a small .gltf (data URI) and .glb
//   OUT_DIR/tm25/           ray sets through write_tm25 (radiant, luminous); real TM-25 files of
//                           DATA_DIR/raysets cut to 200 rays
//   OUT_DIR/lighttools/     LightTools ASCII variants; real .ray files of DATA_DIR/raysets cut to 200 rays
//   OUT_DIR/ies/            LM-63 text for every symmetry, TILT=INCLUDE, write_ies output; DATA_DIR/photometry/ies
//   OUT_DIR/eulumdat/       EULUMDAT for symmetry indicators 0..4; DATA_DIR/photometry/ldt
//   OUT_DIR/envmap/         small lat-long maps as Radiance RGBE (flat and run-length) and EXR
//   OUT_DIR/view_script/    every script command's example, one per file and all in one
// Every ray-set and photometry seed is read back through its reader: a seed the reader refuses
// fails this program (the corpus would start from nothing).
#include <fmt/format.h>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "app/view_script.h"
#include "core/image.h"
#include "core/image_io.h"
#include "core/radiance_hdr.h"
#include "fuzz/fuzz_checks.h"
#include "fuzz/fuzz_seed_files.h"
#include "fuzz/fuzz_support.h"
#include "luminaire/generator.h"
#include "luminaire/goniometric.h"
#include "luminaire/io.h"
#include "luminaire/rayset_lighttools.h"
#include "luminaire/rayset_tm25.h"
#include "reference/environment_map.h"

namespace fs = std::filesystem;

namespace {

// Seeds for the readers added with the measured-data formats; real files from `data` when present.
void write_measured_seeds(const fs::path& out, const fs::path& data) {
  for (const char* d : {"tm25", "lighttools", "ies", "eulumdat"}) fs::create_directories(out / d);
  nf::lum::write_tm25(out / "tm25" / "small_radiant.tm25ray", nf::fuzz::small_rayset(40, nf::lum::FluxKind::radiant));
  nf::lum::write_tm25(out / "tm25" / "small_luminous.tm25ray", nf::fuzz::small_rayset(40, nf::lum::FluxKind::luminous));
  nf::fuzz::write_file(out / "lighttools" / "plain.ray", nf::fuzz::small_lighttools(40, false, false, false));
  nf::fuzz::write_file(out / "lighttools" / "wavelength_origin_end.ray",
                       nf::fuzz::small_lighttools(40, true, true, true));
  for (const char* sym : {"rotational", "bilateral 0-180", "bilateral 90-270", "quadrilateral", "none"}) {
    std::string name = sym;
    for (char& ch : name)
      if (ch == ' ' || ch == '-') ch = '_';
    nf::fuzz::write_file(out / "ies" / (name + ".ies"), nf::fuzz::small_ies(sym, false));
  }
  nf::fuzz::write_file(out / "ies" / "tilt_include.ies", nf::fuzz::small_ies("quadrilateral", true));
  nf::lum::write_ies(out / "ies" / "written.ies", nf::lum::read_ies(out / "ies" / "bilateral_0_180.ies"), "seed");
  for (int sym = 0; sym <= 4; ++sym)
    nf::fuzz::write_file(out / "eulumdat" / fmt::format("symmetry{}.ldt", sym), nf::fuzz::small_eulumdat(sym));

  if (data.empty() || !fs::is_directory(data)) {
    std::printf("fuzz_seeds: no shared data directory: the real ray and photometry files are not seeds\n");
  } else {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(data / "raysets", ec)) {
      const fs::path p = e.path();
      std::string ext = p.extension().string();
      for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      if (ext == ".tm25ray") {
        if (!nf::fuzz::trimmed_tm25(p, out / "tm25" / ("real_" + p.filename().string()), 200))
          throw std::runtime_error(p.string() + ": cannot locate its ray rows to trim it");
      } else if (ext == ".ray") {
        nf::fuzz::trimmed_lighttools(p, out / "lighttools" / ("real_" + p.filename().string()), 200);
      }
    }
    for (const auto& [sub, dir] : {std::pair{"ies", "photometry/ies"}, std::pair{"eulumdat", "photometry/ldt"}})
      for (const auto& e : fs::directory_iterator(data / dir, ec))
        if (e.path().extension() == ".ies" || e.path().extension() == ".ldt")
          fs::copy_file(e.path(), out / sub / ("real_" + e.path().filename().string()),
                        fs::copy_options::overwrite_existing);
  }
  // Read every seed back (and check what the harnesses check).
  for (const auto& e : fs::directory_iterator(out / "tm25")) nf::fuzz::check_rayset(nf::lum::read_tm25(e.path()));
  for (const auto& e : fs::directory_iterator(out / "lighttools"))
    nf::fuzz::check_rayset(nf::lum::read_lighttools_ascii(e.path()));
  for (const auto& e : fs::directory_iterator(out / "ies")) nf::fuzz::check_goniometric(nf::lum::read_ies(e.path()));
  for (const auto& e : fs::directory_iterator(out / "eulumdat"))
    nf::fuzz::check_goniometric(nf::lum::read_eulumdat(e.path()));
}

// Environment maps: a 1 x 1 uniform sky, an 8 x 4 map with a bright horizon band (RGBE rows
// shorter than 8 texels are stored flat) and a 16 x 8 one (run-length rows), each also as EXR.
void write_environment_seeds(const fs::path& out) {
  fs::create_directories(out / "envmap");
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{8, 4}, std::pair{16, 8}}) {
    nf::Image img(w, h, 3);
    for (float& v : img.pixels) v = 0.5f;
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < 3; ++k) img.at(x, h / 2, k) = 40.0f + static_cast<float>(k);
    const std::string stem = fmt::format("sky_{}x{}", w, h);
    nf::write_radiance_hdr(out / "envmap" / (stem + ".hdr"), img, {});
    nf::write_exr(out / "envmap" / (stem + ".exr"), img);
  }
  for (const auto& e : fs::directory_iterator(out / "envmap")) (void)nf::ref::EnvironmentMap::load(e.path(), 0.0, 1.0);
}

// Viewer scripts: every command's own example (they parse: tests/view_script_commands_test.cpp).
void write_script_seeds(const fs::path& out) {
  fs::create_directories(out / "view_script");
  std::string all = "# every command\n";
  for (const auto& spec : nf::app::script_commands()) {
    const std::string line = spec.name + (spec.example.empty() ? "" : " " + spec.example) + "\n";
    nf::fuzz::write_file(out / "view_script" / (spec.name + ".script"), line);
    if (spec.name != "quit") all += line;
  }
  nf::fuzz::write_file(out / "view_script" / "all.script", all + "quit\n");
  for (const auto& e : fs::directory_iterator(out / "view_script"))
    (void)nf::app::load_script(e.path());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: fuzz_seeds OUT_DIR [SCENES_DIR [DATA_DIR]]\n");
    return 2;
  }
  try {
    const fs::path out = argv[1];
    for (const char* d : {"manifest", "luminaire_exr", "scene", "gltf"}) fs::create_directories(out / d);
    const fs::path work = nf::fuzz::scratch();
    // Luminaire EXRs in the four channel layouts.
    for (const bool half : {false, true})
      for (const int ch : {1, 3}) {
        const std::string stem = fmt::format("{}_{}", half ? "half" : "float", ch == 3 ? "rgb" : "y");
        nf::fuzz::write_small_luminaire(work, stem, half, ch);
        fs::copy_file(work / (stem + ".exr"), out / "luminaire_exr" / (stem + ".exr"),
                      fs::copy_options::overwrite_existing);
        fs::copy_file(work / (stem + ".json"), out / "manifest" / (stem + ".json"),
                      fs::copy_options::overwrite_existing);
      }
    nf::fuzz::write_file(out / "manifest" / "small.json", nf::fuzz::small_manifest("small.exr"));
    // Every preset's manifest (small images: only the manifest is a seed).
    for (const auto& name : nf::lum::preset_names()) {
      nf::lum::GenOptions g;
      g.resolution_scale = 0.05;
      const nf::lum::Luminaire l = nf::lum::generate_preset(name, g);
      nf::lum::write_luminaire(work / (name + ".json"), l);
      fs::copy_file(work / (name + ".json"), out / "manifest" / ("preset_" + name + ".json"),
                    fs::copy_options::overwrite_existing);
    }
    // Scenes.
    if (argc > 2)
      for (const auto& e : fs::directory_iterator(argv[2]))
        if (e.path().extension() == ".json")
          fs::copy_file(e.path(), out / "scene" / e.path().filename(), fs::copy_options::overwrite_existing);
    nf::fuzz::write_file(out / "scene" / "small_files.json", R"({
  "format": "nearfield-scene", "version": 1,
  "camera": { "position": [0, 1, 3], "target": [0, 0, 0], "fov_y": 50, "resolution": [64, 48] },
  "materials": { "grey": { "type": "lambert", "base_color": [0.5, 0.5, 0.5] } },
  "objects": [ { "type": "gltf", "file": "small.gltf" },
               { "type": "plane", "size": [2, 2], "material": "grey" },
               { "type": "sphere", "radius": 0.2, "segments": 8, "rings": 4, "transform": { "translate": [0, 0.2, 0] } } ],
  "luminaires": [ { "manifest": "small.json", "intensity": 2, "transform": { "translate": [0, 1, 0], "rotate": [90, 0, 0] } } ],
  "render": { "spp": 4, "method": "ours", "search_depth": 8 }
}
)");
    nf::fuzz::write_file(out / "gltf" / "square.gltf", nf::fuzz::small_gltf());
    nf::fuzz::write_file(out / "gltf" / "square.glb", nf::fuzz::small_glb());
    write_measured_seeds(out, argc > 3 ? fs::path(argv[3]) : fs::path());
    write_environment_seeds(out);
    write_script_seeds(out);
    std::printf("seed corpus written to %s\n", out.string().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
