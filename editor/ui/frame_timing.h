#pragma once
// Frame timing for `orogen-editor --benchmark-build`: the interval between frames, the UI thread's own
// work per frame, and the OpenGL rasterisation (the CPU's with software OpenGL), idle and while a build
// runs in the background.
#include <vector>

#include "editor/model/evaluation_controller.h"

namespace orogen::editor {

class FrameTiming {
 public:
  // work: wall time of building and submitting the frame; cpu: the UI thread's CPU time for it (the
  // difference is time the thread waited: preempted on a busy machine, or blocked).
  void record(bool building, double interval_ms, double work_ms, double cpu_ms, double raster_ms);
  // CPU time of the calling thread, in milliseconds.
  static double thread_cpu_ms();
  std::size_t idle_frames() const { return idle_.interval.size(); }
  // Prints the figures to stdout.
  void print(const BuildStatus& build, const char* renderer) const;

 private:
  struct Series {
    std::vector<double> interval, work, cpu, raster;
  };
  Series idle_, building_;
};

}  // namespace orogen::editor
