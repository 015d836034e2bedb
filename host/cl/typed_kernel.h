#pragma once
// Typed kernel arguments (docs/kernels.md, "Host side"). A kernel's OpenCL C parameter list is
// declared once on the host, as the type TypedKernel<Args...>, and every argument is bound through
// it:
//  - a value must have exactly the declared type (no conversion), so an int in a float slot or a
//    float in a uint slot does not compile, although OpenCL would accept it (same size); the
//    binding functions are constrained (not static_assert), so tests can check what is refused;
//  - bind(...) sets every argument in one call, so none is forgotten or counted twice;
//  - when the kernel is created, its CL_KERNEL_NUM_ARGS must equal the declared count (minus the
//    trailing arguments that the build options compile out), a checked nf::invariant.
// The idea is that of the typed kernel functors of the Khronos C++ bindings; here binding and
// launching stay separate, because launches go through Runtime::launch (profiling events).
#include <cstddef>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "cl/cl_error.h"
#include "cl/opencl.h"
#include "cl/runtime.h"
#include "core/invariant.h"

namespace nf::cl {

// A kernel's argument count (CL_KERNEL_NUM_ARGS); errors name the kernel.
inline cl_uint kernel_arg_count(const ::cl::Kernel& k, const std::string& name) {
  cl_uint n = 0;
  try {
    n = k.getInfo<CL_KERNEL_NUM_ARGS>();
  } catch (const ::cl::Error& e) {
    check(e.err(), name + ": querying its argument count");
  }
  return n;
}
// Sets argument `index` of kernel `name` (bytes as ::cl::Kernel::setArg); errors name both.
template <typename T>
void set_kernel_arg(::cl::Kernel& k, cl_uint index, const T& value, const char* name) {
  try {
    k.setArg(index, value);
  } catch (const ::cl::Error& e) {
    check(e.err(), std::string(name) + ": setting argument " + std::to_string(index));
  }
}

template <typename... Args>
class TypedKernel {
 public:
  static constexpr std::size_t kArgs = sizeof...(Args);
  template <std::size_t I>
  using Arg = std::tuple_element_t<I, std::tuple<Args...>>;

  // Whether values of types Ts... may be bound from argument First on: they fit in the declared
  // list and each has exactly the declared type.
  template <std::size_t First, typename... Ts>
  static constexpr bool matches() {
    if constexpr (First + sizeof...(Ts) > kArgs) {
      return false;
    } else {
      return []<std::size_t... I>(std::index_sequence<I...>) {
        return (std::is_same_v<Ts, Arg<First + I>> && ...);
      }(std::index_sequence_for<Ts...>{});
    }
  }

  TypedKernel() = default;
  // Wraps k, a handle of kernel `name`. absent_tail: how many trailing declared arguments the build
  // options compile out (the light field's direction buffer without -DNF_MEAN_DIRECTION=1).
  TypedKernel(::cl::Kernel k, std::string name, std::size_t absent_tail = 0)
      : kernel_(std::move(k)), name_(std::move(name)), present_(kArgs - absent_tail) {
    invariant(absent_tail <= kArgs, name_ + ": more absent arguments than declared ones");
    const cl_uint n = kernel_arg_count(kernel_, name_);
    invariant(n == present_, name_ + ": the kernel takes " + std::to_string(n) + " arguments, the host declares " +
                                 std::to_string(present_));
  }
  // Creates kernel `name` of kernels/<file> built with `options`.
  TypedKernel(Runtime& rt, const std::string& file, const std::string& name, const std::string& options = "",
              std::size_t absent_tail = 0)
      : TypedKernel(rt.kernel(file, name, options), name, absent_tail) {}

  // Every argument, in the declared order and types.
  template <typename... Ts>
    requires(sizeof...(Ts) == kArgs && matches<0, Ts...>())
  void bind(const Ts&... v) {
    bind_at<0>(v...);
  }
  // Arguments First, First + 1, ...: for a shared leading block (the light field's NF_KERNEL_ARGS) or
  // a kernel's own tail.
  template <std::size_t First, typename... Ts>
    requires(matches<First, Ts...>())
  void bind_at(const Ts&... v) {
    [&]<std::size_t... I>(std::index_sequence<I...>) {
      (set<First + I>(v), ...);
    }(std::index_sequence_for<Ts...>{});
  }
  // Argument I alone (one that changes between launches, as the light field's image index).
  template <std::size_t I, typename T>
    requires(matches<I, T>())
  void set(const T& v) {
    invariant(I < present_, name_ + ": argument " + std::to_string(I) + " is compiled out by the build options");
    set_kernel_arg(kernel_, static_cast<cl_uint>(I), v, name_.c_str());
  }

  ::cl::Kernel& get() { return kernel_; }
  const ::cl::Kernel& get() const { return kernel_; }
  const std::string& name() const { return name_; }
  explicit operator bool() const { return kernel_() != nullptr; }

 private:
  ::cl::Kernel kernel_;
  std::string name_;
  std::size_t present_ = 0;
};

// TypedKernel of the arguments of std::tuple Prefix followed by More... (kernels that share a
// leading parameter block).
template <typename Prefix, typename... More>
struct ExtendKernel;
template <typename... A, typename... More>
struct ExtendKernel<std::tuple<A...>, More...> {
  using type = TypedKernel<A..., More...>;
};

}  // namespace nf::cl
