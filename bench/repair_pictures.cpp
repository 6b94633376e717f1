// repair_pictures: a close-up of repaired holes beside the truth, in one PNG — top row the truth
// and each output shaded, bottom row the input and each output coloured by the distance to the
// truth (repair_figure.h), one camera for every panel. The window is the largest region an output
// added (its faces after the input's, as fill-holes writes them) unless --centre and --radius give
// it; --error-scale fixes the distance coloured red (default: the outputs' 99th percentile in the
// window).
//
// usage: repair_pictures TRUTH INPUT LABEL=OUTPUT... -o FIGURE.png [--error-scale E]
//        [--centre X,Y,Z --radius R] [--pixels N]
#include <pcl_patchdict_eval/repair_figure.h>
#include <pcl_patchdict/io/mesh_io.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

using namespace pcl::patchdict;

namespace {

struct Arguments {
  std::vector<std::string> positional;
  std::string output;
  double error_scale = 0.0, radius = 0.0;
  int pixels = 400;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  bool has_centre = false;
};

bool parse(int argc, char** argv, Arguments& args)
{
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "-o" && has_value)
      args.output = argv[++i];
    else if (a == "--error-scale" && has_value)
      args.error_scale = std::atof(argv[++i]);
    else if (a == "--radius" && has_value)
      args.radius = std::atof(argv[++i]);
    else if (a == "--pixels" && has_value)
      args.pixels = std::atoi(argv[++i]);
    else if (a == "--centre" && has_value) {
      std::stringstream list(argv[++i]);
      std::string item;
      for (int k = 0; k < 3; ++k) {
        if (!std::getline(list, item, ','))
          return false;
        args.centre[k] = std::atof(item.c_str());
      }
      args.has_centre = true;
    } else if (!a.empty() && a[0] == '-')
      return false;
    else
      args.positional.push_back(a);
  }
  return args.positional.size() >= 3 && !args.output.empty() && args.pixels >= 16 && args.pixels <= 4096 &&
         args.has_centre == (args.radius > 0.0);
}

}  // namespace

int main(int argc, char** argv)
{
  Arguments args;
  if (!parse(argc, argv, args)) {
    std::fprintf(stderr, "usage: repair_pictures TRUTH INPUT LABEL=OUTPUT... -o FIGURE.png [--error-scale E] "
                         "[--centre X,Y,Z --radius R] [--pixels N]\n");
    return 2;
  }
  try {
    TriangleMesh truth, input;
    readMesh(args.positional[0], truth);
    readMesh(args.positional[1], input);
    std::vector<TriangleMesh> meshes(args.positional.size() - 2);
    std::vector<FigureMesh> outputs;
    for (std::size_t i = 2; i < args.positional.size(); ++i) {
      const std::string& item = args.positional[i];
      const std::size_t equals = item.find('=');
      readMesh(equals == std::string::npos ? item : item.substr(equals + 1), meshes[i - 2]);
      outputs.push_back({equals == std::string::npos ? "output" : item.substr(0, equals), &meshes[i - 2]});
    }
    CloseUpWindow window;
    if (args.has_centre)
      window = windowAround(truth, args.centre, args.radius);
    else if (!windowAroundNewFaces(meshes[0], input.numFaces(), window)) {
      std::fprintf(stderr, "repair_pictures: the first output adds no faces to the input; give --centre and --radius\n");
      return 1;
    }
    writeImagePNG(args.output, comparisonFigure(truth, {"input", &input}, outputs, window, args.error_scale, args.pixels));
    std::printf("%s: window centre %.6g,%.6g,%.6g radius %.6g\n", args.output.c_str(), window.centre.x(),
                window.centre.y(), window.centre.z(), window.radius);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "repair_pictures: %s\n", e.what());
    return 1;
  }
  return 0;
}
