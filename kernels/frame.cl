/* The frame on the device (docs/rendering.md, "The frame on the device"): the contributions'
   radiance is summed into one float4 frame, the frames are accumulated, and Step 3 (tone mapping
   and the 8-bit display conversion) runs here, so that the host reads back only what a user asks
   for (the viewer's 8-bit image, the EXR/PNG at the end).

   Accumulation: compensated (Kahan) float sums per channel,
     y = frame - comp;  t = sum + y;  comp = (t - sum) - y;  sum = t,
   so that sum - comp carries the running sum with an error of about 2 ulp of the sum however
   many frames are added (Higham, "Accuracy and Stability of Numerical Algorithms", §4.3); the
   host's formula is the double sum of the frames, divided by the frame count on output.
   (The build passes no -cl-fast-relaxed-math, so the compiler keeps the compensation.)

   Tone mapping (core/tonemap.h, the paper's §6.1 operator): with the accumulated radiance
   L = (sum - comp) / frames,
     L_mean = mean of the Rec. 709 luminance over the valid surfaces (non-finite or negative
              luminance counts as 0),  k = exposure / L_mean  (k = 0 when L_mean is 0)
     d_c    = 1 - exp(-k L_c),  out_c = d_c^(1/gamma)
   and the display byte is round(255 clamp(out_c, 0, 1)) (core/image_io.cpp's PNG conversion),
   evaluated through 255 thresholds on L (display_byte below). Negative and NaN values give 0,
   +Inf gives 255. */
#include "shared/surface.h"

/* frame[i] += src[i] (one contribution's radiance into the frame). */
__kernel void frame_add(__global float4* frame, __global const float4* src, int n) {
  const int i = (int)get_global_id(0);
  if (i < n) frame[i] += src[i];
}

/* Adds the frame to the compensated sum (above). */
__kernel void frame_accumulate(__global float4* sum, __global float4* comp, __global const float4* frame, int n) {
  const int i = (int)get_global_id(0);
  if (i >= n) return;
  const float4 s = sum[i];
  const float4 y = frame[i] - comp[i];
  const float4 t = s + y;
  comp[i] = select((float4)(0.0f), (t - s) - y, isfinite(t)); /* +-Inf stays (no Inf - Inf = NaN) */
  sum[i] = t;
}

/* Per work-item partial sums of the accumulated luminance over the valid surfaces and their
   count (x = sum, y = count): work-item g visits pixels g, g + G, g + 2G, ... (G = global size),
   so that neighbouring work-items read neighbouring pixels. The host adds the partials in
   double. */
__kernel void frame_mean_partial(__global const float4* sum, __global const float4* comp,
                                 __global const NfSurface* surfaces, float inv_frames, int n,
                                 __global float2* partial) {
  const int g = (int)get_global_id(0), G = (int)get_global_size(0);
  float acc = 0.0f, count = 0.0f;
  for (int i = g; i < n; i += G) {
    if (!surfaces[i].valid) continue;
    const float4 L = (sum[i] - comp[i]) * inv_frames;
    const float y = 0.2126f * L.x + 0.7152f * L.y + 0.0722f * L.z;
    if (y > 0.0f && !isinf(y)) acc += y;
    count += 1.0f;
  }
  partial[g] = (float2)(acc, count);
}

/* Per work-item partial sums of a uint buffer (the samples drawn per pixel), strided as above. */
__kernel void frame_sum_partial(__global const uint* values, int n, __global ulong* partial) {
  const int g = (int)get_global_id(0), G = (int)get_global_size(0);
  ulong acc = 0;
  for (int i = g; i < n; i += G) acc += values[i];
  partial[g] = acc;
}

/* The operator and the byte in one step, without a transcendental per pixel: the byte is
   round(255 d^(1/gamma)) with d = 1 - exp(-k L), which is monotone in L, so byte >= b (b = 1..255)
   exactly when L >= T_b = -log(1 - ((b - 1/2) / 255)^gamma) / k (the host computes the 255
   thresholds in double; k = 0 gives T_b = +Inf: every byte 0). The byte is the count of
   thresholds <= L, found by bisection (8 steps). NaN compares false (0), +Inf passes all (255),
   negative values pass none (0). */
static uchar display_byte(float L, __global const float* T) {
  int n = 0;
  for (int step = 128; step > 0; step >>= 1)
    if (n + step <= 255 && T[n + step - 1] <= L) n += step;
  return (uchar)n;
}

static uchar4 display_pixel(float4 L, __global const float* T) {
  return (uchar4)(display_byte(L.x, T), display_byte(L.y, T), display_byte(L.z, T), (uchar)255);
}

/* The accumulated frame tone-mapped into 8-bit RGBA (rows from the top, A = 255). */
__kernel void frame_display(__global const float4* sum, __global const float4* comp, float inv_frames,
                            __global const float* thresholds, int n, __global uchar4* out) {
  const int i = (int)get_global_id(0);
  if (i >= n) return;
  out[i] = display_pixel((sum[i] - comp[i]) * inv_frames, thresholds);
}

/* The pixels that see a luminaire: their radiance L(u -> s) (rgb) replaces the accumulation's. */
__kernel void frame_display_luminaires(__global const int* pixel, __global const float4* radiance, int m,
                                       __global const float* thresholds, __global uchar4* out) {
  const int j = (int)get_global_id(0);
  if (j < m) out[pixel[j]] = display_pixel(radiance[j], thresholds);
}
