#pragma once
// Small helpers around the OpenCL C++ bindings used by every module that talks to the device:
// binding exceptions become nf::Error naming the OpenCL error and what was being done, and host
// vectors become read-only device buffers.
#include <string>
#include <vector>

#include "cl/cl_error.h"
#include "cl/runtime.h"

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

// A read-only device copy of v; an empty v gives one value-initialised element (OpenCL has no
// empty buffers, and kernels may still take the argument).
template <typename T>
::cl::Buffer upload(Runtime& rt, const std::vector<T>& v, const std::string& what) {
  ::cl::Buffer b;
  const std::vector<T> one(1, T{});
  const auto& src = v.empty() ? one : v;
  call(
      [&] {
        b = ::cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, src.size() * sizeof(T),
                         const_cast<T*>(src.data()));
      },
      what);
  return b;
}

}  // namespace nf::cl
