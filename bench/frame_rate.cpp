// frame_rate: how fast one organised frame (a depth camera's or a spinning LiDAR's) is repaired by
// the library, as a robot would run it: the sensor model estimated once, then every frame filled
// and denoised on it.
//
//   frame_rate IN.pcd [--frames N] [--threads T] [--json] [--fresh-pages]
//
// Reads IN.pcd once (not timed). Frame 1 is processed as a first frame is (the sensor model fitted
// and its noise law estimated) and its model kept with setSensorModel; frames 2..N reprocess the same
// cloud on that model (Mode::DenoiseAndComplete: denoised, then filled). Prints the median
// milliseconds of frames 2..N, each stage's median (building the image on the model, denoising,
// filling, writing the output cloud), the first frame's, and the memory bound: the time to copy the
// frame's input and output clouds once (the least any repair that reads and writes them can take).
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

#include <pcl/io/pcd_io.h>

#include <omp.h>
#include <pcl/point_types.h>

#include <algorithm>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using Inpainter = pcl::patchdict::GeometricCloudRepair<pcl::PointXYZ, pcl::PointXYZ>;

double ms(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }

double median(std::vector<double> v)
{
  if (v.empty())
    return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

struct Options {
  std::string input;
  int frames = 20, threads = 0;
  bool json = false, fresh_pages = false;
};

bool readOptions(int argc, char** argv, Options& o)
{
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto number = [&](int& out, int low, int high) {
      if (i + 1 >= argc)
        return false;
      char* end = nullptr;
      const long v = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || v < low || v > high)
        return false;
      out = static_cast<int>(v);
      return true;
    };
    if (a == "--frames") {
      if (!number(o.frames, 2, 100000))
        return false;
    } else if (a == "--threads") {
      if (!number(o.threads, 1, 1024))
        return false;
    } else if (a == "--json") {
      o.json = true;
    } else if (a == "--fresh-pages") {
      o.fresh_pages = true;
    } else if (!a.empty() && a[0] != '-' && o.input.empty()) {
      o.input = a;
    } else {
      return false;
    }
  }
  return !o.input.empty();
}

}  // namespace

int main(int argc, char** argv)
{
  Options o;
  if (!readOptions(argc, argv, o)) {
    std::fprintf(stderr, "usage: frame_rate IN.pcd [--frames N (2..)] [--threads T (1..)] [--json] [--fresh-pages]\n");
    return 2;
  }
#ifdef __GLIBC__
  // As the tool does (apps/main.cpp), and as a robot's process repairing frame after frame should:
  // the frames' large blocks stay in the heap instead of being mapped and unmapped (page faults)
  // each frame. --fresh-pages measures without it.
  if (!o.fresh_pages) {
    mallopt(M_MMAP_THRESHOLD, 256 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
  }
#endif
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  if (pcl::io::loadPCDFile(o.input, *cloud) != 0 || cloud->height < 2) {
    std::fprintf(stderr, "frame_rate: %s is not a readable organised PCD\n", o.input.c_str());
    return 1;
  }
  Inpainter inpainter;
  inpainter.setInputCloud(cloud);
  inpainter.setMode(Inpainter::Mode::DenoiseAndComplete);
  if (o.threads > 0) {
    inpainter.setNumberOfThreads(o.threads);
    omp_set_num_threads(o.threads);  // the stages without a thread setting of their own too
  }
  pcl::PointCloud<pcl::PointXYZ> out;
  std::vector<double> total, model, denoise, fill, rest;
  double first = 0.0;
  try {
    for (int f = 0; f < o.frames; ++f) {
      const auto t0 = Clock::now();
      inpainter.process(out);
      const auto t1 = Clock::now();
      if (f == 0) {
        first = ms(t0, t1);
        if (inpainter.getSensorModel().kind == pcl::patchdict::SensorModel::Kind::None) {
          std::fprintf(stderr, "frame_rate: %s: %s\n", o.input.c_str(), inpainter.getSensorModel().failure.c_str());
          return 1;
        }
        inpainter.setSensorModel(inpainter.getSensorModel());
        continue;
      }
      const auto& r = inpainter.getReport();
      total.push_back(ms(t0, t1));
      model.push_back(1000.0 * r.seconds_sensor_model);
      denoise.push_back(1000.0 * r.seconds_fit);
      fill.push_back(1000.0 * r.completion.seconds_fill);
      rest.push_back(total.back() - model.back() - denoise.back() - fill.back());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "frame_rate: %s\n", e.what());
    return 1;
  }
  // The memory bound: copying the input and output clouds once each.
  std::vector<pcl::PointXYZ> a(cloud->points.begin(), cloud->points.end()), b(a.size());
  std::vector<double> copies;
  for (int k = 0; k < 20; ++k) {
    const auto t0 = Clock::now();
    std::memcpy(b.data(), a.data(), a.size() * sizeof(pcl::PointXYZ));
    std::memcpy(a.data(), b.data(), a.size() * sizeof(pcl::PointXYZ));
    copies.push_back(ms(t0, Clock::now()));
  }
  const auto& r = inpainter.getReport();
  const char* kind = pcl::patchdict::sensorKindName(inpainter.getSensorModel().kind);
  const double frame_ms = median(total);
  if (o.json) {
    std::printf("{\"input\":\"%s\",\"sensor\":\"%s\",\"width\":%u,\"height\":%u,\"frames\":%d,\"threads\":%d,"
                "\"ms_per_frame\":%.3f,\"ms_first_frame\":%.3f,\"ms_image_on_model\":%.3f,\"ms_denoise\":%.3f,"
                "\"ms_fill\":%.3f,\"ms_rest\":%.3f,\"ms_copy_bound\":%.3f,\"points_added\":%zu,\"hz\":%.1f}\n",
                o.input.c_str(), kind, cloud->width, cloud->height, o.frames, o.threads, frame_ms, first,
                median(model), median(denoise), median(fill), median(rest), median(copies), r.points_added,
                frame_ms > 0.0 ? 1000.0 / frame_ms : 0.0);
  } else {
    std::printf("%s: %s %u x %u, %d frames on %d threads: %.2f ms a frame (%.1f Hz; first frame %.1f ms)\n"
                "  image on the model %.2f, denoise %.2f, fill %.2f, the rest (copies, normals, output) %.2f ms;"
                " copying the clouds once %.3f ms\n",
                o.input.c_str(), kind, cloud->width, cloud->height, o.frames, o.threads, frame_ms,
                frame_ms > 0.0 ? 1000.0 / frame_ms : 0.0, first, median(model), median(denoise), median(fill),
                median(rest), median(copies));
  }
  return 0;
}
