#include "app/reference_parts.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "reference/cache_key.h"
#include "reference/part_file.h"
#include "reference/sample_sums.h"
#include "render/reference_run.h"
#include "scene/referenced_files.h"

namespace nf::app {
namespace {

std::vector<int> parse_ints(const std::string& text, std::size_t n, const std::string& option,
                            const std::string& form) {
  std::vector<int> v;
  std::size_t pos = 0;
  while (v.size() < n) {
    std::size_t used = 0;
    try {
      v.push_back(std::stoi(text.substr(pos), &used));
    } catch (const std::exception&) {
      fail(fmt::format("{} '{}': expected {} (integers)", option, text, form));
    }
    pos += used;
    if (v.size() < n) {
      if (pos >= text.size() || text[pos] != ',') fail(fmt::format("{} '{}': expected {}", option, text, form));
      ++pos;
    }
  }
  if (pos != text.size()) fail(fmt::format("{} '{}': expected {}", option, text, form));
  return v;
}

// The key fields two parts of one render share; a difference is named in the error.
// "renderer": "reference" (reference --part) or "render" (render --part; absent in older parts).
const char* const kSharedFields[] = {"renderer", "width", "height", "spp", "settings", "tonemap", "content_key"};

nlohmann::json field_of(const nlohmann::json& j, const std::string& key) {
  return j.contains(key) ? j.at(key) : nlohmann::json();
}

void check_same_render(const std::vector<ref::PartFile>& parts, const std::vector<std::string>& files) {
  for (std::size_t i = 1; i < parts.size(); ++i)
    for (const char* field : kSharedFields) {
      const nlohmann::json a = field_of(parts[0].header, field), b = field_of(parts[i].header, field);
      if (a == b) continue;
      std::string what = fmt::format("{} ({} vs {})", field, a.dump(), b.dump());
      if (a.is_object() && b.is_object())
        for (const auto& [k, v] : a.items())
          if (field_of(b, k) != v) {
            what = fmt::format("{} ({} vs {})", k, v.dump(), field_of(b, k).dump());
            break;
          }
      if (std::string(field) == "content_key") what = "the scene or its files (content key)";
      fail(fmt::format("{} and {} are parts of different renders: they differ in {}", files[0], files[i], what));
    }
}

struct Cell {
  int x0, y0, x1, y1;
};

std::vector<int> boundaries(const std::vector<ref::PartFile>& parts, int size, bool along_x) {
  std::set<int> b{0, size};
  for (const auto& p : parts) {
    const auto& r = p.part.region;
    b.insert(along_x ? r.x : r.y);
    b.insert(along_x ? r.x + r.width : r.y + r.height);
  }
  return {b.begin(), b.end()};
}

bool contains(const ref::ImageRegion& r, const Cell& c) {
  return r.x <= c.x0 && c.x1 <= r.x + r.width && r.y <= c.y0 && c.y1 <= r.y + r.height;
}

// The parts covering a cell, in sample order; each sample of 0..spp in exactly one of them.
std::vector<std::size_t> cell_parts(const std::vector<ref::PartFile>& parts, const std::vector<std::string>& files,
                                    const Cell& c, int spp) {
  std::vector<std::size_t> in;
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (contains(parts[i].part.region, c)) in.push_back(i);
  std::sort(in.begin(), in.end(), [&](std::size_t a, std::size_t b) {
    return parts[a].part.region.first_sample < parts[b].part.region.first_sample;
  });
  const std::string pixels = fmt::format("pixels {},{},{},{}", c.x0, c.y0, c.x1 - c.x0, c.y1 - c.y0);
  int next = 0;
  for (std::size_t k = 0; k < in.size(); ++k) {
    const auto& r = parts[in[k]].part.region;
    if (r.first_sample > next)
      fail(fmt::format("{}: samples {}..{} are in none of the parts (a gap)", pixels, next, r.first_sample - 1));
    if (r.first_sample < next)
      fail(fmt::format("{} and {} overlap: {} samples {}..{}", files[in[k - 1]], files[in[k]], pixels, r.first_sample,
                       next - 1));
    next = r.first_sample + r.sample_count;
  }
  if (next < spp) fail(fmt::format("{}: samples {}..{} are in none of the parts (a gap)", pixels, next, spp - 1));
  return in;
}

void merge_cell(const std::vector<ref::PartFile>& parts, const std::vector<std::size_t>& in, const Cell& c, int spp,
                MergedReference& m) {
  ref::PairwiseSums acc;
  for (int y = c.y0; y < c.y1; ++y)
    for (int x = c.x0; x < c.x1; ++x) {
      acc.clear();
      std::uint8_t kind = 0;
      for (std::size_t i : in) {
        const auto& p = parts[i].part;
        const auto& r = p.region;
        const std::size_t px = static_cast<std::size_t>(y - r.y) * r.width + (x - r.x);
        const double* s = p.sums.data() + px * p.nodes.size() * ref::kSumChannels;
        for (std::size_t n = 0; n < p.nodes.size(); ++n) {
          ref::SampleSums v;
          std::copy_n(s + n * ref::kSumChannels, ref::kSumChannels, v.begin());
          acc.push(p.nodes[n].level, v);
        }
        if (r.first_sample == 0) kind = p.kinds[px];
      }
      const ref::SampleSums root = acc.result();
      std::copy(root.begin(), root.end(),
                m.sums.begin() + (static_cast<std::size_t>(y) * m.image.width + x) * ref::kSumChannels);
      float rgb[3];
      ref::finish_pixel(root, spp, rgb, m.variance.at(x, y, 0));
      for (int k = 0; k < 3; ++k) m.image.at(x, y, k) = rgb[k];
      m.kinds[static_cast<std::size_t>(y) * m.image.width + x] = kind;
    }
}

void add_stats(ref::ReferenceStats& t, const ref::ReferenceStats& s) {
  t.camera_rays += s.camera_rays;
  t.shadow_rays += s.shadow_rays;
  t.bounce_rays += s.bounce_rays;
  t.samples += s.samples;
  t.dropped += s.dropped;
  t.render_ms += s.render_ms;
  t.build_ms += s.build_ms;
  t.threads = std::max(t.threads, s.threads);
  t.triangles = s.triangles;
}

}  // namespace

ref::ImageRegion parse_region(const std::string& tile, const std::string& samples, int width, int height, int spp) {
  ref::ImageRegion r = ref::ImageRegion::whole(width, height, spp);
  if (!tile.empty()) {
    const auto v = parse_ints(tile, 4, "--tile", "x,y,w,h");
    r.x = v[0], r.y = v[1], r.width = v[2], r.height = v[3];
  }
  if (!samples.empty()) {
    const auto v = parse_ints(samples, 2, "--samples", "first,count");
    r.first_sample = v[0], r.sample_count = v[1];
  }
  r.validate(width, height, spp);
  return r;
}

void write_reference_part(const scene::Scene& scene, const std::string& scene_name, const ref::ReferenceSettings& set,
                          const ref::ImageRegion& region, const std::string& part_path) {
  AtomicFile file(part_path);
  const render::ReferencePartRun run = render::run_reference_part(scene, set, region);
  nlohmann::json settings = nlohmann::json::object();
  for (const auto& [k, v] : set.attributes()) settings[k] = v;
  nlohmann::json header{
      {"renderer", "reference"},
      {"content_key", run.content_key},
      {"nearfield_version", NEARFIELD_VERSION},
      {"source_hash", ref::reference_source_hash()},
      {"scene", scene_name},
      {"width", scene.camera.width},
      {"height", scene.camera.height},
      {"spp", set.spp},
      {"settings", settings},
      {"tonemap", {{"exposure", scene.render.tonemap.exposure}, {"gamma", scene.render.tonemap.gamma}}},
      {"load_ms", run.load_ms}};
  // The files the scene reads (where they were on the machine that rendered the part): what a
  // cluster must make available to its workers.
  nlohmann::json inputs = nlohmann::json::array();
  if (!scene.file.empty())
    for (const auto& f : scene::referenced_files(scene.file)) inputs.push_back(f.string());
  header["inputs"] = inputs;
  ref::write_part(file.temp_path(), header, run.part);
  file.commit();
  const auto& r = region;
  if (log::level() != log::Level::quiet)
    std::fputs(fmt::format("reference part: tile {},{},{},{} samples {},{} of {}: {} rays in {:.1f} s; wrote {}\n", r.x,
                           r.y, r.width, r.height, r.first_sample, r.sample_count, set.spp, run.part.stats.rays(),
                           run.part.stats.render_ms / 1000.0, part_path)
                   .c_str(),
               stdout);
}

MergedReference merge_reference_parts(const std::vector<std::string>& files) {
  if (files.empty()) fail("merge: no part files given");
  std::vector<ref::PartFile> parts;
  for (const auto& f : files) parts.push_back(ref::read_part(f));
  check_same_render(parts, files);
  const int w = parts[0].width, h = parts[0].height, spp = parts[0].spp;
  MergedReference m;
  m.header = parts[0].header;
  m.tonemap.exposure = m.header["tonemap"].value("exposure", 1.0);
  m.tonemap.gamma = m.header["tonemap"].value("gamma", 2.2);
  m.image = Image(w, h, 3);
  m.variance = Image(w, h, 1);
  m.kinds.assign(static_cast<std::size_t>(w) * h, 0);
  m.sums.assign(static_cast<std::size_t>(w) * h * ref::kSumChannels, 0.0);
  const std::vector<int> xs = boundaries(parts, w, true), ys = boundaries(parts, h, false);
  for (std::size_t j = 0; j + 1 < ys.size(); ++j)
    for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
      const Cell c{xs[i], ys[j], xs[i + 1], ys[j + 1]};
      merge_cell(parts, cell_parts(parts, files, c, spp), c, spp, m);
    }
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const auto& r = parts[i].part.region;
    add_stats(m.stats, parts[i].part.stats);
    m.parts.push_back(fmt::format("{}: tile {},{},{},{} samples {},{}", files[i], r.x, r.y, r.width, r.height,
                                  r.first_sample, r.sample_count));
  }
  return m;
}

void write_merged_part(const std::filesystem::path& path, const MergedReference& m) {
  const int w = m.image.width, h = m.image.height, spp = m.header.at("spp").get<int>();
  ref::ReferencePart part;
  part.region = ref::ImageRegion::whole(w, h, spp);
  part.nodes = ref::sample_nodes(0, spp, spp);
  part.sums = m.sums;
  part.kinds = m.kinds;
  part.stats = m.stats;
  nlohmann::json header = m.header;
  header["merged_parts"] = m.parts;
  ref::write_part(path, header, part);
}

}  // namespace nf::app
