#pragma once
// Image files through OpenImageIO. Writes go to a temporary file in the target directory that
// is renamed into place, so a failure never leaves a partial image and never destroys the
// previous file of that name before the new one is complete.
#include <filesystem>
#include <utility>

#include "core/image.h"

namespace nf {

class OutputTransaction;

// Linear float OpenEXR (channels R,G,B[,A] or Y), with string attributes in the header.
void write_exr(const std::filesystem::path& path, const Image& image, const ImageAttributes& attributes = {});
// 8-bit PNG of values already in display space [0, 1] (clamped, rounded).
void write_png(const std::filesystem::path& path, const Image& image);
// The same into a transaction (core/atomic_file.h): the file is written to the transaction's
// temporary for `path` (added when needed) and appears only when the transaction commits.
void write_exr(OutputTransaction& tx, const std::filesystem::path& path, const Image& image,
               const ImageAttributes& attributes = {});
void write_png(OutputTransaction& tx, const std::filesystem::path& path, const Image& image);
// Any format OpenImageIO reads, as linear float (no colour conversion). Attributes optional.
Image read_image(const std::filesystem::path& path, ImageAttributes* attributes = nullptr);
// Width and height from the file's header only (estimates before loading). Throws nf::Error.
std::pair<int, int> read_image_size(const std::filesystem::path& path);

}  // namespace nf
