// The bad-input matrix (issue 10): every subcommand against broken files of every format, bad index
// files, bad option values, wrong dictionaries and bad output paths. Each case must end with exit
// code 1 (or 2 for usage errors), one error line last on stderr, and the working folder exactly as
// it was: inputs unchanged, no output and no temporary file left behind. Meshes that are odd but
// valid (degenerate, non-manifold, several components, extreme scales) must be processed (a lone
// triangle may be refused a quad layout or an inpainting, cleanly), and a result must be finite and at the input's scale.
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>
#include <pcl_patchdict_eval/shapes.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <random>

using namespace pcl::patchdict;
using test_support::endsWithOneErrorLine;
using test_support::q;
using test_support::runTool;

namespace {

namespace fs = std::filesystem;

/** Every regular file below `dir`, by relative name, with its bytes. */
std::map<std::string, std::string> snapshot(const std::string& dir)
{
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    files[fs::relative(entry.path(), dir).string()] =
        entry.is_regular_file() ? test_support::readFile(entry.path().string()) : std::string("<dir>");
  return files;
}

PatchDictionary randomDictionary(int grid, int atoms, unsigned seed)
{
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd d(grid * grid, atoms);
  for (Eigen::Index k = 0; k < d.size(); ++k)
    d.data()[k] = normal(random);
  d.colwise().normalize();
  PatchDictionary dictionary;
  dictionary.setAtoms(d);
  return dictionary;
}

/** A folder of fixtures: good inputs and every kind of broken one. */
class BadInputFixtures {
public:
  BadInputFixtures()
  {
    sphere_ = makeIcosphere(3);
    writeMesh(file("sphere.ply"), sphere_);
    writeMesh(file("sphere.obj"), sphere_);
    savePatchDictionary(file("dict16.pdd"), randomDictionary(16, 24, 1));
    savePatchDictionary(file("dict6.pdd"), randomDictionary(6, 12, 2));
    put("missing.txt", "0\n7\n14\n21\n");

    const std::string ply = test_support::readFile(file("sphere.ply"));
    put("truncated.ply", ply.substr(0, ply.size() / 2));
    for (const char* ext : {"off", "stl", "pcd"}) {
      const std::string whole = file(std::string("whole.") + ext);
      writeMesh(whole, sphere_);
      const std::string bytes = test_support::readFile(whole);
      fs::remove(whole);
      put(std::string("truncated.") + ext, bytes.substr(0, bytes.size() / 2 + 1));
    }
    put("header_only.ply", ply.substr(0, ply.find("end_header") + 11));
    put("empty.ply", "");
    put("empty.obj", "");
    put("empty.off", "");
    put("empty.stl", "");
    put("empty.pcd", "");
    std::mt19937 random(7);
    std::string garbage(4096, '\0');
    for (auto& c : garbage)
      c = static_cast<char>(random());
    for (const char* ext : {"ply", "obj", "off", "stl", "pcd", "pdd", "pdc"})
      put(std::string("garbage.") + ext, garbage);
    put("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    put("inf.off", "OFF\n3 1 0\n0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n");
    put("overflow.obj", "v 0 0 0\nv 1e400 0 0\nv 0 1 0\nf 1 2 3\n");
    put("nan.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
    put("huge_count.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                          "property float y\nproperty float z\nend_header\n" + std::string(36, '\0'));
    put("huge_faces.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 2000000000\nproperty list uchar int vertex_indices\n"
                          "end_header\n" + std::string(36, '\0') + std::string(13, '\0'));
    put("huge_count.off", "OFF\n3000000000 1 0\n0 0 0\n");
    std::string stl(80, ' ');
    const std::uint32_t triangles = 1000000000u;
    stl.append(reinterpret_cast<const char*>(&triangles), 4);
    stl.append(100, '\0');
    put("huge_count.stl", stl);
    put("huge_count.pcd", "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 900000000\n"
                          "HEIGHT 1\nPOINTS 900000000\nDATA binary\n" + std::string(24, '\0'));
    put("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    put("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n");
    put("unknown.xyz", "0 0 0\n");
    fs::create_directory(file("folder.ply"));

    put("idx_range.txt", "0\n642\n");
    put("idx_negative.txt", "3\n-1\n");
    put("idx_duplicate.txt", "5\n6\n5\n");
    put("idx_text.txt", "5\nseven\n");
    put("idx_float.txt", "5\n6.5\n");
    put("idx_huge.txt", "99999999999999999999999\n");
    put("idx_nul.txt", std::string("12\0" "34\n", 6));

    const std::string pdd = test_support::readFile(file("dict16.pdd"));
    put("dict_truncated.pdd", pdd.substr(0, pdd.size() - 9));
    std::string flipped = pdd;
    flipped[flipped.size() / 2] ^= 0x10;
    put("dict_flipped.pdd", flipped);
  }

  std::string file(const std::string& name) const { return dir_.file(name); }
  /** sphere.pds, by the tool (a fixture only some tests need). */
  bool makePatchSet() const
  {
    return runTool("patches " + q(file("sphere.ply")) + " -o " + q(file("sphere.pds")) + " --quiet").exit_code == 0;
  }
  std::string path() const { return dir_.path(); }
  const TriangleMesh& sphere() const { return sphere_; }

private:
  void put(const std::string& name, const std::string& bytes) { test_support::writeFile(file(name), bytes); }
  test_support::TempDir dir_;
  TriangleMesh sphere_;
};

struct BadCase {
  std::string arguments;  ///< with {} standing for the fixture folder
  int exit_code;          ///< 1: error, 2: usage error
  std::string says;       ///< a part of the error line
};

std::string expand(const std::string& text, const std::string& folder)
{
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text.compare(i, 2, "{}") == 0) {
      out += folder;
      ++i;
    } else {
      out += text[i];
    }
  }
  return out;
}

void expectCleanRefusals(const BadInputFixtures& fixtures, const std::vector<BadCase>& cases)
{
  const auto before = snapshot(fixtures.path());
  for (const BadCase& c : cases) {
    const std::string arguments = expand(c.arguments, fixtures.path());
    const auto result = runTool(arguments + " --quiet");
    EXPECT_EQ(result.exit_code, c.exit_code) << arguments << "\n" << result.err;
    if (c.exit_code == 2)  // usage errors: "pcl_patchdict CMD: option --x: ..."
      EXPECT_TRUE(test_support::isOneLine(result.err)) << arguments << "\n" << result.err;
    else
      EXPECT_TRUE(endsWithOneErrorLine(result.err)) << arguments << "\n" << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << arguments << "\n" << result.err;
    EXPECT_NE(result.err.find(c.says), std::string::npos) << arguments << "\nexpected: " << c.says << "\n" << result.err;
    EXPECT_TRUE(snapshot(fixtures.path()) == before) << arguments << ": the folder changed";
  }
}

}  // namespace

// Every mesh-reading subcommand, against every broken input file.
TEST(CliBadInput, BrokenMeshFilesInEverySubcommand)
{
  const BadInputFixtures fixtures;
  const std::vector<std::pair<std::string, std::string>> files{
      {"absent.ply", "no such file"},
      {"empty.ply", "empty"},
      {"empty.obj", "empty"},
      {"empty.off", "empty"},
      {"empty.stl", "empty"},
      {"empty.pcd", "empty"},
      {"truncated.ply", "truncated"},
      {"truncated.off", "cannot read"},
      {"truncated.stl", "cannot read"},
      {"truncated.pcd", "cannot read"},
      {"header_only.ply", "truncated"},
      {"garbage.ply", "cannot read"},
      {"garbage.obj", "cannot read"},
      {"garbage.off", "cannot read"},
      {"garbage.stl", "cannot read"},
      {"garbage.pcd", "cannot read"},
      {"nan.obj", "non-finite"},
      {"nan.ply", "non-finite"},
      {"inf.off", "non-finite"},
      {"overflow.obj", "non-finite"},
      {"huge_count.ply", "cannot read"},
      {"huge_faces.ply", "cannot read"},
      {"huge_count.off", "cannot read"},
      {"huge_count.stl", "cannot read"},
      {"huge_count.pcd", "cannot read"},
      {"range.obj", "out of range"},
      {"range.off", "out of range"},
      {"unknown.xyz", "unknown extension"},
      {"folder.ply", "cannot read"},
  };
  const std::vector<std::string> commands{
      "info %",
      "eval % {}/sphere.ply",
      "eval {}/sphere.ply %",
      "quads % -o {}/out.obj",
      "patches % -o {}/out.pds",
      "reconstruct % -o {}/out.ply",
      "compress % --dict {}/dict16.pdd -o {}/out.pdc",
      "denoise % -o {}/out.ply",
      "fill-missing % --missing {}/missing.txt --no-patches -o {}/out.ply",
      "fill-holes % --no-patches -o {}/out.ply",
      "fill-holes % --dict {}/dict16.pdd -o {}/out.ply",
  };
  std::vector<BadCase> cases;
  for (const auto& command : commands)
    for (const auto& [name, says] : files) {
      std::string arguments = command;
      arguments.replace(arguments.find('%'), 1, "{}/" + name);
      cases.push_back({arguments, 1, says});
    }
  expectCleanRefusals(fixtures, cases);
}

TEST(CliBadInput, IndexFiles)
{
  const BadInputFixtures fixtures;
  std::vector<BadCase> cases;
  for (const auto& [name, says] : std::vector<std::pair<std::string, std::string>>{
           {"idx_range.txt", "out of range"},
           {"idx_negative.txt", "negative"},
           {"idx_duplicate.txt", "listed twice"},
           {"idx_text.txt", "not an integer"},
           {"idx_float.txt", "not an integer"},
           {"idx_huge.txt", "not an integer"},
           {"idx_nul.txt", "not an integer"},
           {"absent.txt", "no such file"},
           {"garbage.pdc", "line"}}) {
    cases.push_back({"fill-missing {}/sphere.ply --missing {}/" + name + " --no-patches -o {}/out.ply", 1, says});
    cases.push_back({"eval {}/sphere.ply {}/sphere.obj --vertices {}/" + name, 1, says});
  }
  expectCleanRefusals(fixtures, cases);
}

TEST(CliBadInput, OptionValuesOutOfRange)
{
  const BadInputFixtures fixtures;
  const std::string in = "{}/sphere.ply", out = " -o {}/out.ply";
  expectCleanRefusals(fixtures, {
      {"quads " + in + " -o {}/out.obj --quad-length -1", 2, "--quad-length"},
      {"quads " + in + " -o {}/out.obj --quad-length nan", 2, "--quad-length"},
      {"quads " + in + " -o {}/out.obj --overlap 99", 2, "--overlap"},
      {"patches " + in + " -o {}/out.pds --grid 1", 2, "--grid"},
      {"patches " + in + " -o {}/out.pds --grid 100000", 2, "--grid"},
      {"eval " + in + " {}/sphere.obj --samples -5", 2, "--samples"},
      {"denoise " + in + out + " --threads -2", 2, "--threads"},
      {"denoise " + in + out + " --noise -1", 2, "--noise"},
      {"denoise " + in + out + " --noise inf", 2, "--noise"},
      {"denoise " + in + out + " --seed x", 2, "--seed"},
      {"fill-holes " + in + out + " --max-hole-diameter -1", 2, "--max-hole-diameter"},
      {"fill-holes " + in + out + " --surface bumpy", 2, "--surface"},
      {"fill-holes " + in + out + " --sparsity 0", 2, "--sparsity"},
      {"fill-holes " + in + out + " --quad-factor 0", 2, "--quad-factor"},
      {"fill-missing " + in + " --missing {}/missing.txt" + out + " --mu -3", 2, "--mu"},
      {"compress " + in + " --dict {}/dict16.pdd -o {}/out.pdc --coefficient-bits 0", 2, "--coefficient-bits"},
      {"compress " + in + " --dict {}/dict16.pdd -o {}/out.pdc --coefficient-bits 40", 2, "--coefficient-bits"},
      {"compress " + in + " --dict {}/dict16.pdd -o {}/out.pdc --position-bits 99", 2, "--position-bits"},
      {"compress " + in + " --dict {}/dict16.pdd -o {}/out.pdc --sparsity 0", 2, "--sparsity"},
      // --coefficients, compress's old spelling of --sparsity (test/codec uses it), still reads.
      {"compress " + in + " --dict {}/dict16.pdd -o {}/out.pdc --coefficients 0", 2, "--sparsity"},
      {"compress " + in + " --dict {}/dict16.pdd -o {}/out.pdc --atom-cost -1", 2, "--atom-cost"},
      {"learn {}/absent.pds -o {}/out.pdd --atoms 0", 2, "--atoms"},
      {"denoise " + in, 2, "-o"},
      {"denoise " + in + out + " --dict {}/dict16.pdd --self-similar", 2, "excludes"},
      // The range in the message is the table's, as the help shows it (one range per option name).
      {"denoise " + in + out + " --grid 0 --self-similar", 2, "option --grid: 0 is out of range (2 to 256)"},
      {"patches " + in + " -o {}/out.pds --grid 65", 2, "(2 to 64)"},
      {"fill-holes " + in + out + " --overlap 17", 2, "option --overlap: 17 is out of range (0 to 16)"},
      {"denoise " + in + out + " --self-similar --base-iterations -2", 2, "(-1 to 10000)"},
      {"denoise " + in + out + " --self-similar --fidelity 0", 2, "option --fidelity: 0 is out of range"},
      {"compress " + in + " --dict {}/dict16.pdd -o {}/out.pdc --patch-scale 5", 2, "(0.5 to 4)"},
      {"fill-holes {}/empty.pcd -o {}/out.pcd --max-hole-diameter 0", 2, "(> 0)"},
      {"fill-holes {}/empty.pcd -o {}/out.pcd --height-field maybe", 2, "not one of auto, yes, no"},
      {"learn {}/absent.pds -o {}/out.pdd --method magic", 2, "not one of ksvd, online"},
      {"reconstruct " + in + out + " --rule nearest", 2, "not one of bilinear, bin-centres"},
  });
}

TEST(CliBadInput, WrongAndBrokenDictionaries)
{
  const BadInputFixtures fixtures;
  // A .pdc made with one dictionary, to be decoded with others.
  ASSERT_EQ(runTool("compress " + q(fixtures.file("sphere.ply")) + " --dict " + q(fixtures.file("dict16.pdd")) +
                    " -o " + q(fixtures.file("sphere.pdc")) + " --quiet --no-eval")
                .exit_code,
            0);
  const std::string pdc = test_support::readFile(fixtures.file("sphere.pdc"));
  test_support::writeFile(fixtures.file("cut.pdc"), pdc.substr(0, pdc.size() - 5));
  std::string flipped = pdc;
  flipped[flipped.size() / 2] ^= 0x01;
  test_support::writeFile(fixtures.file("flipped.pdc"), flipped);
  ASSERT_TRUE(fixtures.makePatchSet());
  const std::string pds = test_support::readFile(fixtures.file("sphere.pds"));
  test_support::writeFile(fixtures.file("cut.pds"), pds.substr(0, pds.size() - 100));
  const std::string in = "{}/sphere.ply", out = " -o {}/out.ply";
  expectCleanRefusals(fixtures, {
      // The repair commands take the grid from the dictionary unless --grid asks for another.
      {"fill-holes " + in + out + " --dict {}/dict6.pdd --grid 8", 1, "6×6"},
      {"fill-missing " + in + " --missing {}/missing.txt --dict {}/dict6.pdd --grid 8" + out, 1, "6×6"},
      {"denoise " + in + out + " --dict {}/dict6.pdd --grid 8", 1, "6×6"},
      {"reconstruct " + in + out + " --dict {}/dict6.pdd", 1, "6×6"},
      {"fill-holes " + in + out + " --dict {}/garbage.pdd", 1, "not a .pdd file"},
      {"fill-holes " + in + out + " --dict {}/dict_truncated.pdd", 1, "truncated"},
      {"fill-holes " + in + out + " --dict {}/dict_flipped.pdd", 1, "checksum"},
      {"fill-holes " + in + out + " --dict {}/absent.pdd", 1, "no such file"},
      {"decompress {}/sphere.pdc --dict {}/dict6.pdd" + out, 1, "another dictionary"},
      {"decompress {}/garbage.pdc --dict {}/dict16.pdd" + out, 1, ".pdc"},
      {"decompress {}/sphere.ply --dict {}/dict16.pdd" + out, 1, ".pdc"},
      {"decompress {}/cut.pdc --dict {}/dict16.pdd" + out, 1, "cut.pdc"},
      {"decompress {}/flipped.pdc --dict {}/dict16.pdd" + out, 1, "checksum"},
      {"learn {}/garbage.pdd -o {}/out.pdd", 1, "not a .pds file"},
      {"learn {}/cut.pds -o {}/out.pdd", 1, "truncated"},
      {"learn {}/sphere.pds {}/absent.pds -o {}/out.pdd", 1, "no such file"},
  });
}

TEST(CliBadInput, OutputPaths)
{
  const BadInputFixtures fixtures;
  ASSERT_TRUE(fixtures.makePatchSet());
  const std::string in = "{}/sphere.ply";
  std::vector<BadCase> cases;
  for (const std::string& command : {"denoise " + in, "fill-holes " + in + " --no-patches",
                                     "fill-missing " + in + " --missing {}/missing.txt --no-patches",
                                     "reconstruct " + in}) {
    cases.push_back({command + " -o {}/no/such/folder/out.ply", 1, "does not exist"});
    cases.push_back({command + " -o " + in, 1, "input"});
    cases.push_back({command + " -o {}/out.xyz", 1, "must be a mesh"});
    cases.push_back({command + " -o {}/folder.ply", 1, "is a directory"});
  }
  cases.push_back({"quads " + in + " -o {}/no/such/out.obj", 1, "does not exist"});
  cases.push_back({"patches " + in + " -o {}/no/such/out.pds", 1, "does not exist"});
  cases.push_back({"compress " + in + " --dict {}/dict16.pdd -o {}/dict16.pdd", 2, "same file"});
  cases.push_back({"compress " + in + " --dict {}/dict16.pdd -o {}/no/such/out.pdc", 1, "does not exist"});
  cases.push_back({"learn {}/sphere.pds -o {}/sphere.pds", 1, "input"});
  cases.push_back({"learn {}/sphere.pds -o {}/no/such/out.pdd", 1, "does not exist"});
  expectCleanRefusals(fixtures, cases);
}

namespace {

TriangleMesh scaled(TriangleMesh mesh, double factor)
{
  for (auto& v : mesh.vertices)
    v *= factor;
  return mesh;
}

/** Meshes that are odd but valid input: each must be processed or refused cleanly. */
std::vector<std::pair<std::string, TriangleMesh>> oddMeshes()
{
  const TriangleMesh sphere = makeIcosphere(3);
  std::vector<std::pair<std::string, TriangleMesh>> meshes;
  TriangleMesh m = sphere;
  m.faces.push_back({0, 0, 1});
  m.faces.push_back({2, 3, 3});
  meshes.emplace_back("zero_area", m);
  m = sphere;
  m.faces.insert(m.faces.end(), sphere.faces.begin(), sphere.faces.begin() + 40);
  meshes.emplace_back("duplicate_faces", m);
  m = sphere;
  m.vertices.emplace_back(2.0, 2.0, 2.0);
  m.faces.push_back({sphere.faces[0][0], sphere.faces[0][1], static_cast<int>(sphere.vertices.size())});
  meshes.emplace_back("nonmanifold_edge", m);
  m = sphere;  // two spheres touching at one shared vertex
  {
    int top = 0;
    for (std::size_t v = 0; v < sphere.vertices.size(); ++v)
      if (sphere.vertices[v].z() > sphere.vertices[top].z())
        top = static_cast<int>(v);
    int bottom = 0;
    for (std::size_t v = 0; v < sphere.vertices.size(); ++v)
      if (sphere.vertices[v].z() < sphere.vertices[bottom].z())
        bottom = static_cast<int>(v);
    const int n = static_cast<int>(sphere.vertices.size());
    for (const auto& v : sphere.vertices)
      m.vertices.push_back(v + Eigen::Vector3d(0, 0, sphere.vertices[top].z() - sphere.vertices[bottom].z()));
    for (const auto& f : sphere.faces) {
      Face g;
      for (int k = 0; k < 3; ++k)
        g[k] = f[k] == bottom ? top : f[k] + n;
      m.faces.push_back(g);
    }
  }
  meshes.emplace_back("nonmanifold_vertex", m);
  m = sphere;
  m.vertices.emplace_back(3.0, 0.0, 0.0);
  m.vertices.emplace_back(0.0, 3.0, 0.0);
  meshes.emplace_back("isolated_vertices", m);
  m = sphere;
  for (const auto& v : sphere.vertices)
    m.vertices.push_back(v + Eigen::Vector3d(3.0, 0.0, 0.0));
  for (const auto& f : sphere.faces)
    m.faces.push_back({f[0] + 642, f[1] + 642, f[2] + 642});
  meshes.emplace_back("two_components", m);
  m = TriangleMesh();
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2}};
  meshes.emplace_back("single_triangle", m);
  meshes.emplace_back("scale_1e30", scaled(sphere, 1e30));
  meshes.emplace_back("scale_1e-30", scaled(sphere, 1e-30));
  return meshes;
}

}  // namespace

TEST(CliBadInput, OddButValidMeshesAreProcessedOrRefusedCleanly)
{
  test_support::TempDir dir;
  test_support::writeFile(dir.file("missing.txt"), "0\n1\n");
  const std::vector<std::string> commands{
      "info %", "eval % %", "quads % -o OUT.obj", "denoise % -o OUT.ply",
      "fill-holes % --no-patches -o OUT.ply", "fill-missing % --missing " + q(dir.file("missing.txt")) + " --no-patches -o OUT.ply"};
  for (const auto& [name, mesh] : oddMeshes()) {
    const std::string input = dir.file(name + ".ply");
    writeMesh(input, mesh);
    Eigen::Vector3d lo, hi;
    mesh.boundingBox(lo, hi);
    for (const std::string& command : commands) {
      fs::remove_all(dir.file("out"));
      fs::create_directory(dir.file("out"));
      std::string arguments = command;
      for (std::size_t at; (at = arguments.find('%')) != std::string::npos;)
        arguments.replace(at, 1, q(input));
      const std::string extension = arguments.find("OUT.obj") != std::string::npos ? ".obj" : ".ply";
      const std::string output = dir.file("out/result" + extension);
      const auto out_at = arguments.find("OUT" + extension);
      if (out_at != std::string::npos)
        arguments.replace(out_at, 3 + extension.size(), q(output));
      const std::string before = test_support::readFile(input);
      const auto result = runTool(arguments + " --quiet");
      SCOPED_TRACE(name + ": " + arguments + "\n" + result.err);
      EXPECT_EQ(test_support::readFile(input), before);
      // Only a lone triangle may be refused: too small for a quad layout, and with two of its three
      // vertices missing nothing is left to interpolate from. Everything else must be processed.
      const bool may_refuse =
          name == "single_triangle" && (command.rfind("quads", 0) == 0 || command.rfind("fill-missing", 0) == 0);
      if (!may_refuse) {
        EXPECT_EQ(result.exit_code, 0);
      }
      if (result.exit_code != 0) {
        EXPECT_EQ(result.exit_code, 1);
        EXPECT_TRUE(endsWithOneErrorLine(result.err));
        EXPECT_TRUE(fs::is_empty(dir.file("out")));
        continue;
      }
      if (out_at == std::string::npos)
        continue;
      TriangleMesh written;
      ASSERT_NO_THROW(readMesh(output, written));
      for (const auto& v : written.vertices)
        ASSERT_TRUE(v.allFinite());
      if (extension == ".ply" && written.vertices.size() >= mesh.vertices.size()) {
        // Repairs keep the input's place and size at any scale: hardly a vertex moves by more than
        // a tenth of the mesh's size (a fin or a lone triangle may be smoothed away, not the mesh).
        const double size = (hi - lo).maxCoeff();
        std::size_t far = 0;
        for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
          far += (written.vertices[v] - mesh.vertices[v]).norm() > 0.1 * size;
        EXPECT_LE(far, mesh.vertices.size() / 100) << far << " vertices moved far";
      }
    }
  }
}

TEST(CliBadInput, StrayVerticesAreNamed)
{
  test_support::TempDir dir;
  TriangleMesh mesh = makeIcosphere(3);
  mesh.vertices.emplace_back(1e30, 0.0, 0.0);
  mesh.faces.push_back({0, 1, static_cast<int>(mesh.vertices.size()) - 1});
  writeMesh(dir.file("stray.ply"), mesh);
  for (const std::string command : {"denoise", "fill-holes --no-patches", "quads"}) {
    const std::string output = dir.file(command == std::string("quads") ? "out.obj" : "out.ply");
    const auto result = runTool(command + " " + q(dir.file("stray.ply")) + " -o " + q(output) + " --quiet");
    EXPECT_EQ(result.exit_code, 1) << command;
    EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
    EXPECT_NE(result.err.find("stray vertices"), std::string::npos) << result.err;
    EXPECT_NE(result.err.find("vertex 642"), std::string::npos) << result.err;
    EXPECT_FALSE(fs::exists(output));
  }
}

// Options the command would ignore, or that contradict each other or the mode, are refused (issue
// 26): one line, exit code 2, nothing written. Each of these ran and exited 0 before.
TEST(CliBadInput, IgnoredAndContradictoryOptions)
{
  const BadInputFixtures fixtures;
  const std::string in = "{}/sphere.ply", out = " -o {}/out.ply";
  const std::string compress = "compress " + in + " --dict {}/dict16.pdd -o {}/out.pdc";
  expectCleanRefusals(fixtures, {
      // --grid 0 was "the dictionary's" by accident of the range; explicit grids are 2-256.
      {"denoise " + in + out + " --grid 0 --self-similar", 2, "--grid"},
      {"fill-missing " + in + " --missing {}/missing.txt" + out + " --grid 1", 2, "--grid"},
      // Patch-stage options when no patch stage runs.
      {"denoise " + in + out + " --grid 8", 2, "--grid tunes the patch stage"},
      {"denoise " + in + out + " --sparsity 4", 2, "--sparsity tunes the patch stage"},
      {"denoise " + in + out + " --no-patches --fidelity 0.5", 2, "--fidelity tunes the patch stage"},
      {"fill-holes " + in + out + " --no-patches --quad-length 0.05", 2, "--quad-length tunes the patch stage"},
      {"fill-holes " + in + out + " --no-patches --surface relief", 2, "--surface tunes the patch stage"},
      {"fill-missing " + in + " --missing {}/missing.txt" + out + " --no-patches --mu 1", 2, "--mu tunes the patch stage"},
      // A dictionary brings its own atoms.
      {"fill-missing " + in + " --missing {}/missing.txt" + out + " --dict {}/dict16.pdd --atoms 10", 2, "--atoms"},
      // Options that only mean something with another.
      {"fill-holes " + in + out + " --report {}/report --error-scale 0.1", 2, "--error-scale needs --ref"},
      {"fill-holes " + in + out + " --absolute", 2, "--absolute needs --max-hole-diameter"},
      {compress + " --location-bits 8", 2, "--location-bits needs --keep-connectivity"},
      {compress + " --no-eval --samples 5000", 2, "--samples"},
      {"decompress {}/absent.pdc --dict {}/dict16.pdd -o {}/out.ply --samples 5000", 2, "--samples needs --ref"},
      {"learn {}/absent.pds -o {}/out.pdd --method ksvd --batch 64", 2, "--batch"},
      {"denoise {}/empty.pcd -o {}/out.pcd --no-outlier-filter --outlier-std 2", 2, "--outlier-std"},
      // One spelling: the old --smooth-iterations is gone (--smoothing-iterations everywhere).
      {"fill-holes " + in + out + " --smooth-iterations 3", 2, "unknown option '--smooth-iterations'"},
      {"quads " + in + " -o {}/out.obj --smooth-iterations 3", 2, "unknown option"},
      // An option of the other path (a mesh given, a cloud option asked for).
      {"denoise " + in + out + " --bandwidth 0.1", 2, "unknown option '--bandwidth'"},
      {"help --bogus", 2, "usage: pcl_patchdict help"},
  });
}

// decompress reads --ref only after writing its output: a missing one is refused before.
TEST(CliBadInput, MissingReferenceIsRefusedBeforeTheOutput)
{
  const BadInputFixtures fixtures;
  ASSERT_EQ(runTool("compress " + q(fixtures.file("sphere.ply")) + " --dict " + q(fixtures.file("dict16.pdd")) +
                    " -o " + q(fixtures.file("sphere.pdc")) + " --no-eval --quiet")
                .exit_code,
            0);
  expectCleanRefusals(fixtures, {
      {"decompress {}/sphere.pdc --dict {}/dict16.pdd -o {}/out.ply --ref {}/absent.ply", 1, "no such file"},
  });
}

// -o where a command writes nothing was silently ignored; it is refused like any unknown option.
TEST(CliBadInput, OutputOptionOfACommandWithoutOutput)
{
  const BadInputFixtures fixtures;
  expectCleanRefusals(fixtures, {
      {"info {}/sphere.ply -o {}/out.ply", 2, "unknown option '-o'"},
      {"eval {}/sphere.ply {}/sphere.obj -o {}/out.txt", 2, "unknown option '-o'"},
  });
}
