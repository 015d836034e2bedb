#include "core/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <fmt/format.h>

#include "core/error.h"

namespace nf {

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path dir = target_.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    fail(fmt::format("{}: output directory {} does not exist", target_.string(), dir.string()));
  // Keep the extension last so format-sniffing writers pick the right format.
  temp_ = dir / fmt::format(".{}.tmp{}-{}{}", target_.stem().string(), getpid(), counter++,
                            target_.extension().string());
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

void AtomicFile::commit() {
  std::error_code ec;
  std::filesystem::rename(temp_, target_, ec);
  if (ec) fail(fmt::format("{}: cannot move finished file into place: {}", target_.string(), ec.message()));
  committed_ = true;
}

}  // namespace nf
