// Writes the fuzzers' seed corpus with the project's own writers: fuzz_seeds OUT_DIR [SCENES_DIR]
//   OUT_DIR/manifest/       manifests (small luminaire, every generator preset at a small scale)
//   OUT_DIR/luminaire_exr/  2 x 2 x (8 x 8) luminaire EXRs: float and half, RGB and Y
//   OUT_DIR/scene/          SCENES_DIR/*.json and a scene naming small.json / small.gltf
//   OUT_DIR/gltf/           a small .gltf (data URI) and .glb
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>

#include "fuzz/fuzz_support.h"
#include "luminaire/generator.h"
#include "luminaire/io.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: fuzz_seeds OUT_DIR [SCENES_DIR]\n");
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
    std::printf("seed corpus written to %s\n", out.string().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
