// glTF 2.0 through tinygltf. This is the one translation unit with TINYGLTF_IMPLEMENTATION.
// Debian's tinygltf would use libstb for images; we build it without stb (no stb_image, no
// stb_image_write) and keep each image's encoded bytes (as_is), then decode only the images
// that materials use, through OpenImageIO from memory (texture.cpp).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>

#include <fmt/format.h>
#include <algorithm>
#include <cstring>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <map>

#include "core/error.h"
#include "core/log.h"
#include "scene/loaders.h"

namespace nf::scene {
namespace {

bool keep_encoded(tinygltf::Image* image, const int /*index*/, std::string* /*err*/, std::string* /*warn*/,
                  int /*req_w*/, int /*req_h*/, const unsigned char* bytes, int size, void* /*user*/) {
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

class GltfReader {
 public:
  GltfReader(const std::filesystem::path& file, Geometry& out) : file_(file), name_(file.string()), out_(out) {}

  GltfLoadStats load(const glm::dmat4& object_to_world, int object_index, int material_override) {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keep_encoded, nullptr);
    std::string err, warn;
    std::string ext = file_.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (!std::filesystem::exists(file_)) fail(fmt::format("{}: file not found", name_));
    bool ok = false;
    if (ext == ".glb") {
      ok = loader.LoadBinaryFromFile(&model_, &err, &warn, file_.string());
    } else if (ext == ".gltf") {
      ok = loader.LoadASCIIFromFile(&model_, &err, &warn, file_.string());
    } else {
      fail(fmt::format("{}: not a glTF file (expected .gltf or .glb)", name_));
    }
    if (!ok) fail(fmt::format("{}: cannot load glTF: {}", name_, trim(err.empty() ? warn : err)));
    if (!warn.empty()) log::debug("{}: tinygltf: {}", name_, trim(warn));
    material_override_ = material_override;
    object_index_ = object_index;

    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      const int s = model_.defaultScene >= 0 && model_.defaultScene < static_cast<int>(model_.scenes.size())
                        ? model_.defaultScene
                        : 0;
      roots = model_.scenes[static_cast<std::size_t>(s)].nodes;
    } else {  // no scene: every node that is nobody's child
      std::vector<bool> child(model_.nodes.size(), false);
      for (const auto& n : model_.nodes)
        for (int c : n.children)
          if (c >= 0 && c < static_cast<int>(child.size())) child[static_cast<std::size_t>(c)] = true;
      for (std::size_t i = 0; i < child.size(); ++i)
        if (!child[i]) roots.push_back(static_cast<int>(i));
    }
    for (int r : roots) visit(r, object_to_world, 0);
    return stats_;
  }

 private:
  static std::string trim(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    return s;
  }

  void visit(int node_index, const glm::dmat4& parent, int depth) {
    if (node_index < 0 || node_index >= static_cast<int>(model_.nodes.size()))
      fail(fmt::format("{}: node index {} out of range", name_, node_index));
    if (depth > 256) fail(fmt::format("{}: node hierarchy deeper than 256 (a cycle?)", name_));
    const tinygltf::Node& node = model_.nodes[static_cast<std::size_t>(node_index)];
    glm::dmat4 local(1.0);
    if (node.matrix.size() == 16) {
      local = glm::make_mat4(node.matrix.data());
    } else {
      glm::dmat4 t(1.0), r(1.0), s(1.0);
      if (node.translation.size() == 3)
        t = glm::translate(glm::dmat4(1.0), glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
      if (node.rotation.size() == 4)
        r = glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
      if (node.scale.size() == 3)
        s = glm::scale(glm::dmat4(1.0), glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
      local = t * r * s;
    }
    const glm::dmat4 world = parent * local;
    if (node.mesh >= 0) {
      if (node.mesh >= static_cast<int>(model_.meshes.size()))
        fail(fmt::format("{}: node {} uses mesh {} (out of range)", name_, node_index, node.mesh));
      const auto& mesh = model_.meshes[static_cast<std::size_t>(node.mesh)];
      for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
        const int m = primitive_mesh(node.mesh, static_cast<int>(p));
        if (m < 0) continue;
        Instance inst;
        inst.mesh = m;
        inst.material = material_override_ >= 0 ? material_override_ : material(mesh.primitives[p].material);
        inst.to_world = world;
        inst.object = object_index_;
        out_.instances.push_back(inst);
        ++stats_.instances;
      }
    }
    for (int c : node.children) visit(c, world, depth + 1);
  }

  // Reads accessor `index` as `comps` floats per element (normalised integers scaled to [0,1]
  // or [-1,1] as glTF 2.0 §3.11 says).
  std::vector<float> read_floats(int index, int comps, const std::string& what) {
    const tinygltf::Accessor& acc = accessor(index, what);
    if (tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type)) != comps)
      fail(fmt::format("{}: {} accessor {} has {} components (need {})", name_, what, index,
                       tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type)), comps));
    std::vector<float> v(acc.count * static_cast<std::size_t>(comps));
    for_each_component(acc, index, what, [&](std::size_t i, const unsigned char* p) {
      float f = 0.0f;
      switch (acc.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
          std::memcpy(&f, p, 4);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          f = acc.normalized ? *p / 255.0f : *p;
          break;
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
          const auto b = static_cast<std::int8_t>(*p);
          f = acc.normalized ? std::max(b / 127.0f, -1.0f) : b;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          std::uint16_t s;
          std::memcpy(&s, p, 2);
          f = acc.normalized ? s / 65535.0f : s;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
          std::int16_t s;
          std::memcpy(&s, p, 2);
          f = acc.normalized ? std::max(s / 32767.0f, -1.0f) : s;
          break;
        }
        default:
          fail(fmt::format("{}: {} accessor {} has unsupported component type {}", name_, what, index,
                           acc.componentType));
      }
      v[i] = f;
    });
    return v;
  }

  std::vector<std::uint32_t> read_indices(int index) {
    const tinygltf::Accessor& acc = accessor(index, "indices");
    if (acc.type != TINYGLTF_TYPE_SCALAR) fail(fmt::format("{}: index accessor {} is not SCALAR", name_, index));
    std::vector<std::uint32_t> v(acc.count);
    for_each_component(acc, index, "indices", [&](std::size_t i, const unsigned char* p) {
      switch (acc.componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          v[i] = *p;
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          std::uint16_t s;
          std::memcpy(&s, p, 2);
          v[i] = s;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
          std::memcpy(&v[i], p, 4);
          break;
        default:
          fail(fmt::format("{}: index accessor {} has component type {}", name_, index, acc.componentType));
      }
    });
    return v;
  }

  const tinygltf::Accessor& accessor(int index, const std::string& what) const {
    if (index < 0 || index >= static_cast<int>(model_.accessors.size()))
      fail(fmt::format("{}: {} accessor index {} out of range", name_, what, index));
    const auto& acc = model_.accessors[static_cast<std::size_t>(index)];
    if (acc.sparse.isSparse) fail(fmt::format("{}: {} accessor {} is sparse (not supported)", name_, what, index));
    return acc;
  }

  // Calls f(component index, pointer to the component's bytes) for every component, after
  // checking that the accessor lies inside its buffer.
  template <typename F>
  void for_each_component(const tinygltf::Accessor& acc, int index, const std::string& what, F&& f) const {
    if (acc.count == 0) return;
    if (acc.bufferView < 0 || acc.bufferView >= static_cast<int>(model_.bufferViews.size()))
      fail(fmt::format("{}: {} accessor {} has no buffer view (not supported)", name_, what, index));
    const auto& view = model_.bufferViews[static_cast<std::size_t>(acc.bufferView)];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size()))
      fail(fmt::format("{}: buffer view {} names buffer {} (out of range)", name_, acc.bufferView, view.buffer));
    const auto& buf = model_.buffers[static_cast<std::size_t>(view.buffer)].data;
    const int comps = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type));
    const int csize = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(acc.componentType));
    const int stride = acc.ByteStride(view);
    if (comps <= 0 || csize <= 0 || stride <= 0)
      fail(fmt::format("{}: {} accessor {} has an invalid type or stride", name_, what, index));
    const std::size_t begin = view.byteOffset + acc.byteOffset;
    const std::size_t end = begin + static_cast<std::size_t>(stride) * (acc.count - 1) +
                            static_cast<std::size_t>(comps) * static_cast<std::size_t>(csize);
    if (end > view.byteOffset + view.byteLength || end > buf.size())
      fail(fmt::format("{}: {} accessor {} reads past the end of its buffer", name_, what, index));
    for (std::size_t e = 0; e < acc.count; ++e)
      for (int c = 0; c < comps; ++c)
        f(e * static_cast<std::size_t>(comps) + static_cast<std::size_t>(c),
          &buf[begin + e * static_cast<std::size_t>(stride) + static_cast<std::size_t>(c * csize)]);
  }

  // Our mesh for primitive p of glTF mesh m (loaded once however many nodes use it); -1 to skip.
  int primitive_mesh(int m, int p) {
    const auto key = std::make_pair(m, p);
    if (auto it = mesh_cache_.find(key); it != mesh_cache_.end()) return it->second;
    const auto& prim = model_.meshes[static_cast<std::size_t>(m)].primitives[static_cast<std::size_t>(p)];
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      log::debug("{}: mesh {} primitive {}: mode {} (points/lines) skipped", name_, m, p, mode);
      return mesh_cache_[key] = -1;
    }
    const std::string what = fmt::format("mesh {} primitive {}", m, p);
    const auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end()) fail(fmt::format("{}: {} has no POSITION", name_, what));
    const std::vector<float> pos = read_floats(pos_it->second, 3, what + " POSITION");
    const std::size_t nv = pos.size() / 3;
    std::vector<float> nrm, uv;
    if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
      nrm = read_floats(it->second, 3, what + " NORMAL");
      if (nrm.size() != pos.size()) fail(fmt::format("{}: {} NORMAL count differs from POSITION", name_, what));
    }
    if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
      uv = read_floats(it->second, 2, what + " TEXCOORD_0");
      if (uv.size() / 2 != nv) fail(fmt::format("{}: {} TEXCOORD_0 count differs from POSITION", name_, what));
    }
    std::vector<std::uint32_t> idx;
    if (prim.indices >= 0) {
      idx = read_indices(prim.indices);
    } else {
      idx.resize(nv);
      for (std::size_t i = 0; i < nv; ++i) idx[i] = static_cast<std::uint32_t>(i);
    }
    for (auto i : idx)
      if (i >= nv) fail(fmt::format("{}: {} index {} out of range ({} vertices)", name_, what, i, nv));
    std::vector<std::uint32_t> tri;  // as a triangle list
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      tri = idx;
      tri.resize(tri.size() / 3 * 3);
    } else {
      for (std::size_t k = 2; k < idx.size(); ++k) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
          if (k % 2 == 0) {
            tri.insert(tri.end(), {idx[k - 2], idx[k - 1], idx[k]});
          } else {
            tri.insert(tri.end(), {idx[k - 1], idx[k - 2], idx[k]});
          }
        } else {
          tri.insert(tri.end(), {idx[0], idx[k - 1], idx[k]});
        }
      }
    }

    Mesh mesh;
    mesh.name = fmt::format("{}#{}",
                            model_.meshes[static_cast<std::size_t>(m)].name.empty()
                                ? fmt::format("mesh{}", m)
                                : model_.meshes[static_cast<std::size_t>(m)].name,
                            p);
    const auto vec3 = [](const std::vector<float>& a, std::size_t i) {
      return glm::vec3(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
    };
    if (!nrm.empty()) {
      mesh.positions.resize(nv);
      mesh.normals.resize(nv);
      for (std::size_t i = 0; i < nv; ++i) {
        mesh.positions[i] = vec3(pos, i);
        const glm::vec3 n = vec3(nrm, i);
        const float len = glm::length(n);
        mesh.normals[i] = len > 0.0f ? n / len : glm::vec3(0, 0, 1);
      }
      if (!uv.empty()) {
        mesh.uvs.resize(nv);
        for (std::size_t i = 0; i < nv; ++i) mesh.uvs[i] = {uv[2 * i], uv[2 * i + 1]};
      }
      mesh.indices = std::move(tri);
    } else {  // flat normals: one vertex per triangle corner
      for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
        const glm::vec3 a = vec3(pos, tri[t]), b = vec3(pos, tri[t + 1]), c = vec3(pos, tri[t + 2]);
        glm::vec3 n = glm::cross(b - a, c - a);
        const float len = glm::length(n);
        n = len > 0.0f ? n / len : glm::vec3(0, 0, 1);
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t v = tri[t + static_cast<std::size_t>(k)];
          mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
          mesh.positions.push_back(vec3(pos, v));
          mesh.normals.push_back(n);
          if (!uv.empty()) mesh.uvs.emplace_back(uv[2 * v], uv[2 * v + 1]);
        }
      }
    }
    stats_.vertices += mesh.vertex_count();
    stats_.triangles += mesh.triangle_count();
    ++stats_.meshes;
    out_.meshes.push_back(std::move(mesh));
    return mesh_cache_[key] = static_cast<int>(out_.meshes.size() - 1);
  }

  int material(int index) {
    if (auto it = material_cache_.find(index); it != material_cache_.end()) return it->second;
    Material mat;
    mat.kind = MaterialKind::ggx;
    const std::string stem = file_.stem().string();
    if (index < 0) {  // glTF 2.0 §3.9.6 default material
      mat.name = stem + "/default";
      mat.base_color = glm::vec3(1.0f);
      mat.metallic = 1.0f;
      mat.roughness = 1.0f;
    } else {
      if (index >= static_cast<int>(model_.materials.size()))
        fail(fmt::format("{}: material index {} out of range", name_, index));
      const auto& g = model_.materials[static_cast<std::size_t>(index)];
      mat.name = stem + "/" + (g.name.empty() ? fmt::format("material{}", index) : g.name);
      const auto& pbr = g.pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() >= 3)
        mat.base_color =
            glm::vec3(static_cast<float>(pbr.baseColorFactor[0]), static_cast<float>(pbr.baseColorFactor[1]),
                      static_cast<float>(pbr.baseColorFactor[2]));
      mat.metallic = static_cast<float>(std::clamp(pbr.metallicFactor, 0.0, 1.0));
      mat.roughness = static_cast<float>(std::clamp(pbr.roughnessFactor, 0.0, 1.0));
      mat.base_color = glm::clamp(mat.base_color, 0.0f, 1.0f);
      if (pbr.baseColorTexture.index >= 0) {
        if (pbr.baseColorTexture.texCoord != 0)
          log::warn("{}: material '{}' uses TEXCOORD_{} for its base colour; only TEXCOORD_0 is supported", name_,
                    mat.name, pbr.baseColorTexture.texCoord);
        mat.base_color_texture = texture(pbr.baseColorTexture.index);
      }
      if (pbr.metallicRoughnessTexture.index >= 0)
        mat.metallic_roughness_texture = texture(pbr.metallicRoughnessTexture.index);
    }
    out_.materials.push_back(std::move(mat));
    ++stats_.materials;
    return material_cache_[index] = static_cast<int>(out_.materials.size() - 1);
  }

  int texture(int index) {
    if (index < 0 || index >= static_cast<int>(model_.textures.size()))
      fail(fmt::format("{}: texture index {} out of range", name_, index));
    const int source = model_.textures[static_cast<std::size_t>(index)].source;
    if (source < 0 || source >= static_cast<int>(model_.images.size()))
      fail(fmt::format("{}: texture {} has no image source", name_, index));
    if (auto it = texture_cache_.find(source); it != texture_cache_.end()) return it->second;
    const auto& img = model_.images[static_cast<std::size_t>(source)];
    const std::string label =
        fmt::format("{}#image{}{}", name_, source, img.name.empty() ? std::string() : " (" + img.name + ")");
    if (img.image.empty())
      fail(fmt::format("{}: image data missing{}", label, img.uri.empty() ? "" : " (file '" + img.uri + "')"));
    out_.textures.push_back(decode_texture(img.image.data(), img.image.size(), img.mimeType, label));
    ++stats_.textures;
    return texture_cache_[source] = static_cast<int>(out_.textures.size() - 1);
  }

  std::filesystem::path file_;
  std::string name_;
  Geometry& out_;
  tinygltf::Model model_;
  int material_override_ = -1;
  int object_index_ = 0;
  GltfLoadStats stats_;
  std::map<std::pair<int, int>, int> mesh_cache_;
  std::map<int, int> material_cache_;
  std::map<int, int> texture_cache_;
};

}  // namespace

GltfLoadStats load_gltf(const std::filesystem::path& file, const glm::dmat4& object_to_world, int object_index,
                        int material_override, Geometry& out) {
  GltfReader reader(file, out);
  return reader.load(object_to_world, object_index, material_override);
}

}  // namespace nf::scene
