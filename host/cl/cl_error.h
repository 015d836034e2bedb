#pragma once
#include <string>

namespace nf::cl {

// "CL_OUT_OF_RESOURCES" etc. for an OpenCL error code.
const char* error_name(int code);
// Throws nf::Error "<what>: <error name> (<code>)" when code != CL_SUCCESS.
void check(int code, const std::string& what);

}  // namespace nf::cl
