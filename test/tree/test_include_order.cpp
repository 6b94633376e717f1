// The stage order of docs/layout.md as a test: every include in include/, src/ and apps/ is read, and
// an include of a later stage (of the evaluation code or the PCL skin from the library) fails, with its file and line.
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

namespace fs = std::filesystem;

/// The order and the PCL skin as docs/layout.md states them: the stage table's first column, top to
/// bottom, and the names after "skin:" in the `pcl` row.
struct StageOrder {
  std::vector<std::string> stages;
  std::vector<std::string> skin;
  int index(const std::string& stage) const
  {
    const auto it = std::find(stages.begin(), stages.end(), stage);
    return it == stages.end() ? -1 : static_cast<int>(it - stages.begin());
  }
};

/// The names in `backticks` of a line (lower-case letters and underscores only).
std::vector<std::string> backticked(const std::string& text)
{
  std::vector<std::string> out;
  for (std::size_t open = text.find('`'); open != std::string::npos; open = text.find('`', open + 1)) {
    const std::size_t close = text.find('`', open + 1);
    if (close == std::string::npos)
      break;
    const std::string name = text.substr(open + 1, close - open - 1);
    if (!name.empty() && name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") == std::string::npos)
      out.push_back(name);
    open = close;
  }
  return out;
}

/// An include line's target: the text between <> or "", and its stage — <pcl_patchdict/STAGE/…>, a
/// private "STAGE/…", <pcl_patchdict_eval/…> ("eval"); empty for anything else (<pcl/…> is PCL's).
struct Include {
  std::string text, stage;
  bool quoted = false;
};

bool parseInclude(const std::string& line, Include& out)
{
  std::size_t i = line.find_first_not_of(" \t");
  if (i == std::string::npos || line[i] != '#')
    return false;
  i = line.find_first_not_of(" \t", i + 1);
  if (i == std::string::npos || line.compare(i, 7, "include") != 0)
    return false;
  i = line.find_first_not_of(" \t", i + 7);
  if (i == std::string::npos || (line[i] != '<' && line[i] != '"'))
    return false;
  const char close = line[i] == '<' ? '>' : '"';
  const std::size_t end = line.find(close, i + 1);
  if (end == std::string::npos)
    return false;
  out.quoted = close == '"';
  out.text = line.substr(i, end - i + 1);
  const std::string path = line.substr(i + 1, end - i - 1);
  const auto first = [&](std::size_t from) {
    const std::size_t slash = path.find('/', from);
    return slash == std::string::npos ? std::string() : path.substr(from, slash - from);
  };
  if (!out.quoted && path.rfind("pcl_patchdict_eval/", 0) == 0)
    out.stage = "eval";
  else if (!out.quoted && path.rfind("pcl_patchdict/", 0) == 0)
    out.stage = first(14);
  else if (out.quoted)
    out.stage = first(0);
  return !out.stage.empty();
}

StageOrder readStageOrder(const fs::path& layout)
{
  StageOrder order;
  std::ifstream in(layout);
  std::string line;
  bool table = false;
  while (std::getline(in, line)) {
    if (line.rfind("| stage |", 0) == 0) {
      table = true;
      continue;
    }
    if (!table || line.rfind("|---", 0) == 0)
      continue;
    if (line.rfind("| `", 0) != 0)
      break;  // the table's end
    const std::string first = line.substr(0, line.find('|', 1));
    const std::vector<std::string> names = backticked(first);
    if (names.size() == 1)
      order.stages.push_back(names[0]);
    const std::size_t skin = line.find("skin:");
    if (names.size() == 1 && skin != std::string::npos)
      order.skin = backticked(line.substr(skin, line.find('|', skin) - skin));
  }
  return order;
}

/// The stage a file belongs to: include/pcl_patchdict/<stage>/…, src/<stage>/…; "apps" for the tool.
std::string stageOf(const fs::path& relative)
{
  std::vector<std::string> parts;
  for (const auto& part : relative)
    parts.push_back(part.string());
  if (parts.size() >= 3 && parts[0] == "include" && parts[1] == "pcl_patchdict")
    return parts[2];
  if (parts.size() >= 2 && parts[0] == "src")
    return parts[1];
  return parts.empty() ? "" : parts[0];
}

/// Every include that runs against the order, as "file:line: why".
std::vector<std::string> orderViolations(const fs::path& root, const StageOrder& order)
{
  std::vector<std::string> out;
  std::vector<fs::path> files;
  for (const char* top : {"include", "src", "apps"})
    if (fs::exists(root / top))
      for (const auto& entry : fs::recursive_directory_iterator(root / top)) {
        const std::string ext = entry.path().extension().string();
        if (entry.is_regular_file() && (ext == ".h" || ext == ".hpp" || ext == ".cpp"))
          files.push_back(entry.path());
      }
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    const fs::path relative = fs::relative(file, root);
    const std::string stage = stageOf(relative);
    const bool library = stage != "apps" && stage != "eval";
    if (library && order.index(stage) < 0) {
      out.push_back(relative.string() + ": its folder '" + stage + "' is no stage of docs/layout.md");
      continue;
    }
    const bool skin = stage == "pcl" && std::count(order.skin.begin(), order.skin.end(), file.stem().string()) > 0;
    std::ifstream in(file);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
      Include include;
      if (!parseInclude(line, include))
        continue;
      const std::string& target = include.stage;
      const std::string where = relative.string() + ":" + std::to_string(number) + ": " + include.text;
      if (include.quoted && target == "pcl") {  // "pcl/x.h" reads as PCL's own <pcl/x.h>
        out.push_back(where + ": a private header under \"pcl/\" reads as one of PCL's");
        continue;
      }
      if (target == "eval") {
        if (library)
          out.push_back(where + ": the library includes the evaluation code");
        continue;
      }
      if (order.index(target) < 0 || !library)
        continue;
      // The skin serves users: no stage of the library includes it (docs/layout.md, "The PCL skin").
      const std::string name = fs::path(include.text.substr(1, include.text.size() - 2)).stem().string();
      if (target == "pcl" && stage != "pcl" && std::count(order.skin.begin(), order.skin.end(), name) > 0) {
        out.push_back(where + ": no stage includes the PCL skin");
        continue;
      }  // the tool and the evaluation code may use every stage; "x/y.h" of no stage is local
      // The skin sits after the stages it serves, up to `coding`.
      const int allowed = skin ? std::max(order.index(stage), order.index("coding")) : order.index(stage);
      if (order.index(target) > allowed)
        out.push_back(where + ": stage '" + target + "' comes after '" + stage + "' in docs/layout.md");
    }
  }
  return out;
}

std::string joined(const std::vector<std::string>& lines)
{
  std::ostringstream out;
  for (const std::string& line : lines)
    out << "  " << line << "\n";
  return out.str();
}

TEST(IncludeOrder, TheTreeFollowsTheStageOrderOfTheLayoutPage)
{
  const fs::path root = PCL_PATCHDICT_SOURCE_DIR;
  const StageOrder order = readStageOrder(root / "docs" / "layout.md");
  ASSERT_GE(order.stages.size(), 10u) << "the stage table of docs/layout.md was not found";
  EXPECT_EQ(order.stages.front(), "core");
  EXPECT_EQ(order.skin.size(), 3u);
  const std::vector<std::string> violations = orderViolations(root, order);
  EXPECT_TRUE(violations.empty()) << violations.size() << " includes run against the stage order:\n"
                                  << joined(violations);
}

// A planted tree: a wrong include in each place the check reads is found, with its file and line, and
// the allowed ones (an earlier stage, PCL's own headers, the skin's, the tool's) are not.
TEST(IncludeOrder, APlantedWrongIncludeIsFound)
{
  const fs::path root = fs::temp_directory_path() / ("include_order_" + std::to_string(::getpid()));
  fs::remove_all(root);
  const auto write = [&](const std::string& path, const std::string& text) {
    fs::create_directories((root / path).parent_path());
    std::ofstream(root / path) << text;
  };
  write("include/pcl_patchdict/core/a.h", "#pragma once\n#include <pcl_patchdict/core/b.h>\n#include <pcl/point_types.h>\n");
  write("include/pcl_patchdict/geometry/g.h", "#pragma once\n\n  #  include <pcl_patchdict/cloud/c.h>\n");
  write("src/quads/q.cpp", "#include \"patches/private.h\"\n#include <pcl_patchdict/geometry/g.h>\n"
                           "#include <pcl_patchdict/pcl/quad_frame_estimation.h>\n");
  write("src/io/r.cpp", "#include <pcl_patchdict_eval/shapes.h>\n");
  write("src/pcl/quad_frame_estimation.cpp", "#include <pcl_patchdict/coding/sparse_coding.h>\n");
  write("src/pcl/conversions.cpp", "#include <pcl_patchdict/quads/quad_mesh.h>\n");
  write("src/repair/s.cpp", "#include \"pcl/point_conversion.h\"\n#include <pcl/kdtree/kdtree_flann.h>\n");
  write("apps/cmd.cpp", "#include <pcl_patchdict/cloud/c.h>\n#include <pcl_patchdict_eval/shapes.h>\n");
  StageOrder order;
  order.stages = {"core", "pcl", "io", "geometry", "quads", "patches", "coding", "repair", "codec", "cloud"};
  order.skin = {"quad_frame_estimation"};
  const std::vector<std::string> found = orderViolations(root, order);
  fs::remove_all(root);
  ASSERT_EQ(found.size(), 6u) << joined(found);
  EXPECT_EQ(found[0].rfind("include/pcl_patchdict/geometry/g.h:3: <pcl_patchdict/cloud/c.h>", 0), 0u) << found[0];
  EXPECT_EQ(found[1].rfind("src/io/r.cpp:1:", 0), 0u) << found[1];
  EXPECT_NE(found[1].find("evaluation code"), std::string::npos) << found[1];
  EXPECT_EQ(found[2].rfind("src/pcl/conversions.cpp:1:", 0), 0u) << found[2];  // not skin
  EXPECT_EQ(found[3].rfind("src/quads/q.cpp:1: \"patches/private.h\"", 0), 0u) << found[3];
  EXPECT_EQ(found[4].rfind("src/quads/q.cpp:3: <pcl_patchdict/pcl/quad_frame_estimation.h>: no stage includes", 0),
            0u) << found[4];
  EXPECT_EQ(found[5].rfind("src/repair/s.cpp:1: \"pcl/point_conversion.h\": a private header", 0), 0u) << found[5];
}

}  // namespace
