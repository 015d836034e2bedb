#pragma once
// Small helpers around the OpenCL C++ bindings used by every module that talks to the device:
// binding exceptions become nf::Error naming the OpenCL error and what was being done, host
// vectors become device buffers and device buffers host vectors. Every module uses these rather
// than its own try/catch (docs/kernels.md, "Host side").
#include <algorithm>
#include <string>
#include <vector>

#include "cl/cl_error.h"
#include "cl/runtime.h"
#include "core/invariant.h"

namespace nf::cl {

// Runs f(); a ::cl::Error it throws becomes nf::Error "<what>: <error name> (<code>)".
template <typename F>
void call(F&& f, const std::string& what) {
  try {
    f();
  } catch (const ::cl::Error& e) {
    check(e.err(), what);
  }
}

// A device buffer of max(bytes, 16) bytes (OpenCL has no empty buffers, and kernels may still
// take the argument). With `data` (which holds `bytes`) and CL_MEM_COPY_HOST_PTR, a copy smaller
// than 16 bytes is written into the padded buffer instead of letting CL_MEM_COPY_HOST_PTR read past
// the host memory (found by ASan).
inline ::cl::Buffer make_buffer(Runtime& rt, cl_mem_flags flags, std::size_t bytes, const void* data,
                                const std::string& what) {
  constexpr std::size_t kMin = 16;
  ::cl::Buffer b;
  call(
      [&] {
        if (data && bytes < kMin) {
          b = ::cl::Buffer(rt.context(), flags & ~static_cast<cl_mem_flags>(CL_MEM_COPY_HOST_PTR), kMin);
          if (bytes > 0) rt.queue().enqueueWriteBuffer(b, CL_TRUE, 0, bytes, data);
        } else {
          b = ::cl::Buffer(rt.context(), flags, std::max(bytes, kMin), const_cast<void*>(data));
        }
      },
      what);
  return b;
}

// A read-only device copy of v; an empty v gives one value-initialised element.
template <typename T>
::cl::Buffer upload(Runtime& rt, const std::vector<T>& v, const std::string& what) {
  const std::vector<T> one(1, T{});
  const auto& src = v.empty() ? one : v;
  return make_buffer(rt, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, src.size() * sizeof(T), src.data(), what);
}

// A read-write device copy of v (kernels and copies write into these buffers later); an empty v
// gives 16 uninitialised bytes.
template <typename T>
::cl::Buffer upload_rw(Runtime& rt, const std::vector<T>& v, const std::string& what) {
  if (v.empty()) return make_buffer(rt, CL_MEM_READ_WRITE, 16, nullptr, what);
  return make_buffer(rt, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, v.size() * sizeof(T), v.data(), what);
}

// Elements [first, first + count) of b (blocking). Invariant: they lie inside the buffer.
template <typename T>
std::vector<T> download(Runtime& rt, const ::cl::Buffer& b, std::size_t count, std::size_t first,
                        const std::string& what) {
  std::vector<T> out(count);
  if (count == 0) return out;
  call(
      [&] {
        invariant((first + count) * sizeof(T) <= b.getInfo<CL_MEM_SIZE>(),
                  what + ": read past the end of the device buffer");
        rt.queue().enqueueReadBuffer(b, CL_TRUE, first * sizeof(T), count * sizeof(T), out.data());
      },
      what);
  return out;
}

}  // namespace nf::cl
