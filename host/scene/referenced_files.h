#pragma once
// The files a scene depends on: the scene file itself and every file its JSON names (strings that
// name an existing regular file, relative to the naming file's folder), followed into .json and
// .gltf files so that luminaire manifests bring their EXR files and glTF files their buffers and
// images. Used to refuse outputs that would overwrite an input, and by cache keys.
#include <filesystem>
#include <set>

namespace nf::scene {

// Canonical paths (weakly canonical; absolute and normalised when that fails).
std::set<std::filesystem::path> referenced_files(const std::filesystem::path& file, int depth = 3);
std::filesystem::path canonical_or_self(const std::filesystem::path& p);

}  // namespace nf::scene
