#include "editor/ui/frame_timing.h"

#include <algorithm>
#include <cstdio>
#include <ctime>

namespace orogen::editor {

namespace {

void report(const char* what, std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const auto pick = [&](double q) {
    return v.empty() ? 0.0 : v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
  };
  std::printf("  %-44s %4zu frames: median %6.1f ms, p90 %6.1f, p99 %6.1f, max %6.1f\n", what, v.size(), pick(0.5),
              pick(0.9), pick(0.99), v.empty() ? 0.0 : v.back());
}

}  // namespace

double FrameTiming::thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

void FrameTiming::record(bool building, double interval_ms, double work_ms, double cpu_ms, double raster_ms) {
  Series& s = building ? building_ : idle_;
  s.interval.push_back(interval_ms);
  s.work.push_back(work_ms);
  s.cpu.push_back(cpu_ms);
  s.raster.push_back(raster_ms);
}

void FrameTiming::print(const BuildStatus& build, const char* renderer) const {
  std::printf("OpenGL renderer: %s\n", renderer);
  std::printf("build %s at %d x %d in %.1f s\n", build.ok ? "ok" : "FAILED", build.domain.width(),
              build.domain.height(), build.milliseconds / 1000.0);
  report("frame interval, idle", idle_.interval);
  report("frame interval, during the build", building_.interval);
  report("UI thread work per frame, idle", idle_.work);
  report("UI thread work per frame, during the build", building_.work);
  report("UI thread CPU per frame, idle", idle_.cpu);
  report("UI thread CPU per frame, during the build", building_.cpu);
  report("rasterization per frame, idle", idle_.raster);
  report("rasterization per frame, during the build", building_.raster);
}

}  // namespace orogen::editor
