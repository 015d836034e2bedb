#pragma once
// The one include of the Khronos C++ bindings (exceptions on, OpenCL 1.2 target; set in CMake).
#include <CL/opencl.hpp>
