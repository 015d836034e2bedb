#include "luminaire/rayset.h"

#include <sys/mman.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "core/memory.h"
#include "luminaire/rayset_lighttools.h"
#include "luminaire/rayset_tm25.h"

namespace nf::lum {

const char* flux_unit(FluxKind k) { return k == FluxKind::luminous ? "lm" : "W"; }

double RaySet::total_flux() const {
  double s = 0.0;
  for (double f : flux) s += f;
  return s;
}

void RaySet::add(glm::dvec3 p, glm::dvec3 d, double f) {
  position.push_back(p);
  direction.push_back(d);
  flux.push_back(f);
}

namespace {

RaySet read_regular(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(fmt::format("{}: cannot open the ray file", file.string()));
  std::array<char, 4> magic{};
  in.read(magic.data(), 4);
  in.close();
  if (in.gcount() == 4 && magic == std::array<char, 4>{'T', 'M', '2', '5'}) return read_tm25(file);
  return read_lighttools_ascii(file);
}

// A file descriptor closed when it goes out of scope.
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

// A pipe, FIFO or character device (`<(...)`, /dev/stdin) can be read only once: its bytes are
// read into an anonymous in-memory file (memfd) that the readers then open like a regular file,
// with the caller's name in every message.
RaySet read_stream(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(fmt::format("{}: cannot open the ray file", name));
  Fd mem;
  mem.fd = ::memfd_create("nearfield-rays", MFD_CLOEXEC);
  if (mem.fd < 0) fail(fmt::format("{}: cannot buffer the stream in memory: {}", name, std::strerror(errno)));
  std::vector<char> buf(1 << 20);
  std::uint64_t total = 0;
  const std::uint64_t available = available_host_memory();
  for (;;) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (got == 0) break;
    total += got;
    check_memory(name, "buffering the ray stream in memory", total, available);
    for (std::size_t done = 0; done < got;) {
      const ssize_t w = ::write(mem.fd, buf.data() + done, got - done);
      if (w < 0) {
        if (errno == EINTR) continue;
        fail(fmt::format("{}: cannot buffer the stream in memory: {}", name, std::strerror(errno)));
      }
      done += static_cast<std::size_t>(w);
    }
  }
  if (in.bad()) fail(fmt::format("{}: read error", name));
  const std::string proxy = fmt::format("/proc/self/fd/{}", mem.fd);
  try {
    RaySet rs = read_regular(proxy);
    rs.source = name;
    return rs;
  } catch (const Error& e) {  // the readers name the proxy: name the user's file instead
    std::string what = e.what();
    for (std::size_t p = what.find(proxy); p != std::string::npos; p = what.find(proxy, p + name.size()))
      what.replace(p, proxy.size(), name);
    fail(what);
  }
}

}  // namespace

RaySet read_rayset(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) fail(fmt::format("{}: is a directory, not a ray file", file.string()));
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec)) return read_stream(file);
  return read_regular(file);
}

}  // namespace nf::lum
