#include "render/device_frame.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cl/buffers.h"

namespace nf::render {

namespace {

constexpr int kMaxPartials = 4096;  // work-items of the reductions (kernels/frame.cl)

::cl::NDRange range(std::size_t n) { return ::cl::NDRange(std::max<std::size_t>(n, 1)); }

}  // namespace

DeviceFrame::DeviceFrame(cl::Runtime& rt) : rt_(rt) {}

void DeviceFrame::build() {
  cl::call(
      [&] {
        if (!add_) add_ = {rt_, "frame.cl", "frame_add"};
        if (!accumulate_) accumulate_ = {rt_, "frame.cl", "frame_accumulate"};
        if (!mean_) mean_ = {rt_, "frame.cl", "frame_mean_partial"};
        if (!sum_partial_) sum_partial_ = {rt_, "frame.cl", "frame_sum_partial"};
        if (!display_k_) display_k_ = {rt_, "frame.cl", "frame_display"};
        if (!display_lum_) display_lum_ = {rt_, "frame.cl", "frame_display_luminaires"};
        if (n_ == 0) return;
        // One launch of each at this size (PoCL compiles a kernel for its work-group size at the
        // first launch), so that no frame's times include a compiler run. The frame, sum and mean
        // kernels get a pixel count of 0 and change nothing; the display is rewritten anyway.
        const int n = static_cast<int>(n_);
        add_.bind(frame_, sum_, 0);
        rt_.launch(add_.get(), range(n_));
        accumulate_.bind(sum_, comp_, frame_, 0);
        rt_.launch(accumulate_.get(), range(n_));
        mean_.bind(sum_, comp_, frame_, 0.0f, 0, partial_);
        rt_.launch(mean_.get(), range(static_cast<std::size_t>(partials())));
        sum_partial_.bind(display_, n, partial_);
        rt_.launch(sum_partial_.get(), range(static_cast<std::size_t>(partials())));
        display_k_.bind(sum_, comp_, 0.0f, partial_, n, display_);
        rt_.launch(display_k_.get(), range(n_));
        rt_.queue().finish();
      },
      "building kernels/frame.cl");
}

int DeviceFrame::partials() const {
  return static_cast<int>(std::clamp<std::size_t>(n_, 1, static_cast<std::size_t>(kMaxPartials)));
}

void DeviceFrame::resize(std::size_t n) {
  if (n != n_ || !frame_()) {
    n_ = n;
    const std::size_t px = std::max<std::size_t>(n, 1);
    cl::call(
        [&] {
          frame_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, px * sizeof(cl_float4));
          sum_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, px * sizeof(cl_float4));
          comp_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, px * sizeof(cl_float4));
          display_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, px * sizeof(cl_uchar4));
          partial_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, kMaxPartials * sizeof(cl_ulong));
        },
        "allocating the device frame");
    clear_frame();
  }
  reset();
}

void DeviceFrame::reset() {
  frames_ = 0;
  if (!sum_()) return;
  cl::call(
      [&] {
        const cl_float4 zero{{0.0f, 0.0f, 0.0f, 0.0f}};
        const std::size_t bytes = std::max<std::size_t>(n_, 1) * sizeof(cl_float4);
        rt_.queue().enqueueFillBuffer(sum_, zero, 0, bytes);
        rt_.queue().enqueueFillBuffer(comp_, zero, 0, bytes);
      },
      "clearing the device accumulation");
}

void DeviceFrame::clear_frame() {
  cl::call(
      [&] {
        const cl_float4 zero{{0.0f, 0.0f, 0.0f, 0.0f}};
        rt_.queue().enqueueFillBuffer(frame_, zero, 0, std::max<std::size_t>(n_, 1) * sizeof(cl_float4));
      },
      "clearing the device frame");
}

void DeviceFrame::add(const ::cl::Buffer& src) {
  if (n_ == 0) return;
  cl::call(
      [&] {
        if (!add_) add_ = {rt_, "frame.cl", "frame_add"};
        add_.bind(frame_, src, static_cast<int>(n_));
        rt_.launch(add_.get(), range(n_));
      },
      "adding a contribution into the device frame");
}

void DeviceFrame::add_host(const std::vector<glm::vec4>& src) {
  if (n_ == 0 || src.empty()) return;
  if (src.size() >= n_) {
    add(cl::upload(rt_, src, "uploading a contribution's radiance"));
    return;
  }
  std::vector<glm::vec4> full(src);  // a short contribution: its pixels only (the rest stay 0)
  full.resize(n_, glm::vec4(0.0f));
  add(cl::upload(rt_, full, "uploading a contribution's radiance"));
}

double DeviceFrame::accumulate() {
  double ms = 0.0;
  if (n_ > 0)
    cl::call(
        [&] {
          if (!accumulate_) accumulate_ = {rt_, "frame.cl", "frame_accumulate"};
          accumulate_.bind(sum_, comp_, frame_, static_cast<int>(n_));
          ::cl::Event e = rt_.launch(accumulate_.get(), range(n_));
          e.wait();
          ms = cl::Runtime::event_ms(e);
        },
        "accumulating the device frame");
  ++frames_;
  return ms;
}

std::uint64_t DeviceFrame::sum(const ::cl::Buffer& values) {
  if (n_ == 0) return 0;
  const int g = partials();
  std::vector<cl_ulong> part(static_cast<std::size_t>(g));
  cl::call(
      [&] {
        if (!sum_partial_) sum_partial_ = {rt_, "frame.cl", "frame_sum_partial"};
        sum_partial_.bind(values, static_cast<int>(n_), partial_);
        rt_.launch(sum_partial_.get(), range(static_cast<std::size_t>(g)));
        rt_.queue().enqueueReadBuffer(partial_, CL_TRUE, 0, part.size() * sizeof(cl_ulong), part.data());
      },
      "summing the samples drawn");
  std::uint64_t s = 0;
  for (const auto v : part) s += v;
  return s;
}

std::vector<double> DeviceFrame::accumulated() const {
  std::vector<double> out(3 * n_, 0.0);
  if (n_ == 0 || frames_ == 0) return out;
  std::vector<cl_float4> s(n_), c(n_);
  cl::call(
      [&] {
        rt_.queue().enqueueReadBuffer(sum_, CL_FALSE, 0, n_ * sizeof(cl_float4), s.data());
        rt_.queue().enqueueReadBuffer(comp_, CL_TRUE, 0, n_ * sizeof(cl_float4), c.data());
      },
      "reading the accumulation back");
  const double inv = 1.0 / frames_;
  for (std::size_t p = 0; p < n_; ++p)
    for (int ch = 0; ch < 3; ++ch)
      out[3 * p + static_cast<std::size_t>(ch)] =
          (static_cast<double>(s[p].s[ch]) - static_cast<double>(c[p].s[ch])) * inv;
  return out;
}

std::vector<glm::vec4> DeviceFrame::last_frame() const {
  std::vector<glm::vec4> out(n_, glm::vec4(0.0f));
  if (n_ == 0) return out;
  cl::call([&] { rt_.queue().enqueueReadBuffer(frame_, CL_TRUE, 0, n_ * sizeof(glm::vec4), out.data()); },
           "reading the last frame back");
  return out;
}

double DeviceFrame::mean_luminance(const ::cl::Buffer& surfaces) const {
  if (n_ == 0 || frames_ == 0) return 0.0;
  const int g = partials();
  std::vector<cl_float2> part(static_cast<std::size_t>(g));
  cl::call(
      [&] {
        if (!mean_) mean_ = {rt_, "frame.cl", "frame_mean_partial"};
        mean_.bind(sum_, comp_, surfaces, static_cast<float>(1.0 / frames_), static_cast<int>(n_), partial_);
        rt_.launch(mean_.get(), range(static_cast<std::size_t>(g)));
        rt_.queue().enqueueReadBuffer(partial_, CL_TRUE, 0, part.size() * sizeof(cl_float2), part.data());
      },
      "the tone-mapping mean");
  double sum = 0.0, count = 0.0;
  for (const auto& v : part) {
    sum += v.s[0];
    count += v.s[1];
  }
  return count > 0.0 ? sum / count : 0.0;
}

std::vector<std::uint8_t> DeviceFrame::display(const ::cl::Buffer& surfaces, const std::vector<std::int32_t>& pixels,
                                               const std::vector<glm::vec4>& radiance, const TonemapParams& params,
                                               double* mean_out) {
  std::vector<std::uint8_t> out(4 * n_, 0);
  const double mean = mean_luminance(surfaces);
  if (mean_out) *mean_out = mean;
  if (n_ == 0) return out;
  // The byte thresholds on L (kernels/frame.cl display_byte): byte >= b iff L >= T_b, in double.
  const double k = mean > 0.0 && std::isfinite(mean) ? params.exposure / mean : 0.0;
  std::vector<float> thresholds(255, std::numeric_limits<float>::infinity());
  if (k > 0.0 && std::isfinite(k))
    for (int b = 1; b <= 255; ++b) {
      const double d = std::pow((b - 0.5) / 255.0, params.gamma);  // d^(1/gamma) = (b - 1/2) / 255
      thresholds[static_cast<std::size_t>(b - 1)] = static_cast<float>(-std::log1p(-d) / k);
    }
  const int m = static_cast<int>(std::min(pixels.size(), radiance.size()));
  cl::call(
      [&] {
        // The partial sums' buffer is free once the mean is read: it holds the thresholds.
        rt_.queue().enqueueWriteBuffer(partial_, CL_FALSE, 0, thresholds.size() * sizeof(float), thresholds.data());
        if (!display_k_) display_k_ = {rt_, "frame.cl", "frame_display"};
        display_k_.bind(sum_, comp_, frames_ > 0 ? static_cast<float>(1.0 / frames_) : 0.0f, partial_,
                        static_cast<int>(n_), display_);
        rt_.launch(display_k_.get(), range(n_));
        if (m > 0) {
          if (lum_capacity_ < static_cast<std::size_t>(m)) {
            lum_pixel_ = ::cl::Buffer(rt_.context(), CL_MEM_READ_ONLY, static_cast<std::size_t>(m) * sizeof(cl_int));
            lum_radiance_ =
                ::cl::Buffer(rt_.context(), CL_MEM_READ_ONLY, static_cast<std::size_t>(m) * sizeof(cl_float4));
            lum_capacity_ = static_cast<std::size_t>(m);
          }
          rt_.queue().enqueueWriteBuffer(lum_pixel_, CL_FALSE, 0, static_cast<std::size_t>(m) * sizeof(cl_int),
                                         pixels.data());
          rt_.queue().enqueueWriteBuffer(lum_radiance_, CL_FALSE, 0, static_cast<std::size_t>(m) * sizeof(cl_float4),
                                         radiance.data());
          if (!display_lum_) display_lum_ = {rt_, "frame.cl", "frame_display_luminaires"};
          display_lum_.bind(lum_pixel_, lum_radiance_, m, partial_, display_);
          rt_.launch(display_lum_.get(), range(static_cast<std::size_t>(m)));
        }
        rt_.queue().enqueueReadBuffer(display_, CL_TRUE, 0, out.size(), out.data());
      },
      "Step 3 on the device (tone mapping, display conversion)");
  return out;
}

std::size_t DeviceFrame::device_bytes() const {
  if (!frame_()) return 0;
  return std::max<std::size_t>(n_, 1) * kBytesPerPixel + kMaxPartials * sizeof(cl_ulong) +
         lum_capacity_ * (sizeof(cl_int) + sizeof(cl_float4));
}

}  // namespace nf::render
