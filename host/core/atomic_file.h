#pragma once
// Write-then-rename: the caller writes temp_path(); commit() renames it onto the target.
// If commit() is never reached (an exception), the temporary is removed and the target,
// if it existed, is untouched.
#include <filesystem>

namespace nf {

class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::filesystem::path& temp_path() const { return temp_; }
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  bool committed_ = false;
};

}  // namespace nf
