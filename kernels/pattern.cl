/* Diagnostic kernel for the GL -> CL path: per pixel, out = gain * in^gamma (rgb), alpha kept.
   Host reference: nf::app pattern command and tests/cl_runtime_test.cpp. */
__kernel void pattern_shade(__global const float4* in, __global float4* out, const float gain, const float gamma,
                            const int count) {
  const int i = get_global_id(0);
  if (i >= count) return;
  const float4 v = in[i];
  out[i] = (float4)(gain * pow(v.x, gamma), gain * pow(v.y, gamma), gain * pow(v.z, gamma), v.w);
}
