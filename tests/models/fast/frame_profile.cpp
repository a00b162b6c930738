// fast_frame_profile: runs the fast engine alone on one stereo pair, for profilers (callgrind,
// perf) and quick timing without the CLI around it. Not a test.
//
//   fast_frame_profile CONFIG.yaml LEFT.png RIGHT.png [ITERATIONS=1] [fast|timing|cycle]
//
// `timing` runs the cycle model's control-path schedule of the design instead (sim::run_timing,
// the part of a cycle run beyond the func run), `cycle` the whole cycle run (sim::run_cycle); both
// also print the time cycle_options() took to derive the design's timing model.
// Prints the SIMD level, each iteration's time and a checksum of the codes (equal checksums
// between builds mean equal codes). Under valgrind, build without -march=native
// (-DPARALLAX_NATIVE=OFF) and set PARALLAX_SIMD=avx2: valgrind does not decode AVX-512.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "parallax/config/config.hpp"
#include "parallax/eval/simulate.hpp"
#include "parallax/fast/engine.hpp"
#include "parallax/sim/cycle.hpp"

int main(int argc, char** argv) {
  if (argc < 4 || argc > 6) {
    std::fprintf(stderr, "usage: %s CONFIG.yaml LEFT.png RIGHT.png [ITERATIONS=1] [fast|timing|cycle]\n", argv[0]);
    return 2;
  }
  try {
    const parallax::config::PipelineConfig config = parallax::config::load_config(argv[1]);
    const cv::Mat left = cv::imread(argv[2], cv::IMREAD_GRAYSCALE);
    const cv::Mat right = cv::imread(argv[3], cv::IMREAD_GRAYSCALE);
    if (left.empty() || right.empty() || left.size() != right.size() || !left.isContinuous() || !right.isContinuous()) {
      std::fprintf(stderr, "%s, %s: cannot read two 8-bit images of one size\n", argv[2], argv[3]);
      return 1;
    }
    const int iterations = argc >= 5 ? std::stoi(argv[4]) : 1;
    const std::string mode = argc == 6 ? argv[5] : "fast";
    const parallax::kern::StereoParams p = config.stereo_params(left.cols, left.rows);
    if (mode == "timing" || mode == "cycle") {
      const parallax::sim::GreyImage gl{left.cols, left.rows, std::vector<uint8_t>(left.datastart, left.dataend)};
      const parallax::sim::GreyImage gr{right.cols, right.rows, std::vector<uint8_t>(right.datastart, right.dataend)};
      for (int i = 0; i < iterations; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        const parallax::sim::CycleOptions opt = parallax::eval::cycle_options(config, config.clock_mhz);
        const auto t1 = std::chrono::steady_clock::now();
        const parallax::sim::CycleReport rep =
            mode == "cycle" ? parallax::sim::run_cycle(gl, gr, p, opt) : parallax::sim::run_timing(gl, gr, p, opt);
        const auto t2 = std::chrono::steady_clock::now();
        std::printf("%s %dx%d iteration %d: %.2f ms (options %.2f ms; %lld cycles per frame)\n", mode.c_str(),
                    left.cols, left.rows, i, std::chrono::duration<double, std::milli>(t2 - t1).count(),
                    std::chrono::duration<double, std::milli>(t1 - t0).count(),
                    static_cast<long long>(rep.cycles_per_frame));
      }
      return 0;
    }
    if (mode != "fast") {
      std::fprintf(stderr, "%s: unknown mode (fast, timing or cycle)\n", mode.c_str());
      return 2;
    }
    parallax::fast::Engine engine;
    uint64_t checksum = 0;
    for (int i = 0; i < iterations; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      const std::vector<uint16_t> codes = engine.run(left.data, right.data, p);
      const auto t1 = std::chrono::steady_clock::now();
      checksum = 1469598103934665603ull;
      for (const uint16_t c : codes) checksum = (checksum ^ c) * 1099511628211ull;
      std::printf("%s %dx%d iteration %d: %.2f ms\n", parallax::fast::simd_level(), left.cols, left.rows, i,
                  std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    std::printf("codes checksum %016llx\n", static_cast<unsigned long long>(checksum));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
