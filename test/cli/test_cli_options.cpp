// The command-line table (apps/options.h) walked as data: one name has one meaning, every default
// lies in its range, the defaults a command passes on are the library's own, and the getters read
// the table and nothing else (issue 26).
#include "cli.h"
#include "options.h"

#include <pcl_patchdict/cloud/cloud_hole_completion.h>
#include <pcl_patchdict/cloud/organized_hole_filling.h>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>
#include <pcl_patchdict/codec/patch_codec.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/quads/patch_layout.h>
#include <pcl_patchdict/repair/patch_repairs.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>

using namespace pcl::patchdict;
using namespace pcl::patchdict::cli;

namespace {

/** Every option of the table with where it stands ("denoise", "fill-holes (cloud)", "common"). */
std::vector<std::pair<std::string, const OptionSpec*>> allOptions()
{
  std::vector<std::pair<std::string, const OptionSpec*>> all;
  for (const OptionSpec& option : commonOptions())
    all.emplace_back("common", &option);
  for (const CommandSpec& spec : commandSpecs())
    for (const OptionSpec& option : spec.options)
      all.emplace_back(spec.name + (spec.variant.empty() ? "" : " (" + spec.variant + ")"), &option);
  return all;
}

/** What must agree between two options of one name: kind, argument (a file's name says which file
  * it is, so Text arguments may differ), range, words. */
std::string meaning(const OptionSpec& o)
{
  std::string text = std::to_string(static_cast<int>(o.kind));
  if (o.kind != OptionKind::Text)
    text += " " + o.argument;
  if (o.kind == OptionKind::Integer || o.kind == OptionKind::Real)
    text += " " + rangeText(o);
  return text;
}

const OptionSpec& optionOf(const std::string& command, const std::string& name, const std::string& variant = "")
{
  const OptionSpec* option = findOption(commandSpec(command, variant), name);
  if (!option)
    throw std::logic_error(command + " has no --" + name);
  return *option;
}

double realDefault(const std::string& command, const std::string& name, const std::string& variant = "")
{
  const OptionSpec& option = optionOf(command, name, variant);
  EXPECT_EQ(option.kind, OptionKind::Real) << command << " --" << name;
  EXPECT_TRUE(option.has_default) << command << " --" << name;
  return option.real_default;
}

long long intDefault(const std::string& command, const std::string& name, const std::string& variant = "")
{
  const OptionSpec& option = optionOf(command, name, variant);
  EXPECT_EQ(option.kind, OptionKind::Integer) << command << " --" << name;
  EXPECT_TRUE(option.has_default) << command << " --" << name;
  return option.int_default;
}

}  // namespace

// An option spelled the same in two commands has the same kind, argument and range, unless the
// table says why not (OptionSpec::differs).
TEST(CliOptions, OneNameHasOneMeaning)
{
  std::map<std::string, std::pair<std::string, std::string>> first;  // name -> (where, meaning)
  for (const auto& [where, option] : allOptions()) {
    if (!option->differs.empty())
      continue;
    const std::string m = meaning(*option);
    const auto [it, inserted] = first.emplace(option->name, std::make_pair(where, m));
    EXPECT_TRUE(inserted || it->second.second == m)
        << "--" << option->name << " means '" << it->second.second << "' in " << it->second.first << " but '" << m
        << "' in " << where << " (same meaning, or say why in OptionSpec::differs)";
  }
}

// A typed default lies in its range (a word among the words); a number has a range; what has no
// typed default says how the command computes it, unless the option is simply off when absent.
TEST(CliOptions, DefaultsLieInTheirRanges)
{
  for (const auto& [where, option] : allOptions()) {
    const std::string what = where + " --" + option->name;
    switch (option->kind) {
    case OptionKind::Integer:
      EXPECT_LE(option->int_min, option->int_max) << what;
      EXPECT_GT(option->int_min, std::numeric_limits<long long>::min()) << what << ": no range";
      if (option->has_default) {
        EXPECT_GE(option->int_default, option->int_min) << what;
        EXPECT_LE(option->int_default, option->int_max) << what;
      }
      break;
    case OptionKind::Real:
      EXPECT_LE(option->real_min, option->real_max) << what;
      EXPECT_TRUE(std::isfinite(option->real_min)) << what << ": no range";
      if (option->has_default) {
        EXPECT_GE(option->real_default, option->real_min) << what;
        EXPECT_LE(option->real_default, option->real_max) << what;
        EXPECT_FALSE(option->above_min && option->real_default == option->real_min) << what;
      }
      break;
    case OptionKind::Word:
      EXPECT_GE(option->words.size(), 2u) << what;
      if (option->has_default) {
        EXPECT_NE(std::find(option->words.begin(), option->words.end(), option->text_default), option->words.end())
            << what;
      }
      break;
    case OptionKind::Flag:
      EXPECT_FALSE(option->has_default) << what;
      EXPECT_TRUE(option->argument.empty()) << what;
      break;
    case OptionKind::Text: break;
    }
    EXPECT_TRUE(option->hidden || !option->help.empty()) << what;
    EXPECT_FALSE(option->required && option->has_default) << what;
  }
}

// The defaults a command passes on are the library's: the table cannot drift from the structs.
TEST(CliOptions, DefaultsAreTheLibrarys)
{
  const auto checkShared = [](const std::string& command, const PatchRepairCommon& p) {
    SCOPED_TRACE(command);
    const std::vector<std::pair<const char*, double>> reals{
        {"quad-length", p.quad_length},   {"quad-factor", p.quad_length_factor}, {"patch-scale", p.patch_scale},
        {"centre-sigma", p.centre_sigma}, {"observed-power", p.observed_power},  {"fit-scale", p.fit_scale},
        {"agreement-scale", p.agreement_scale}, {"min-observed", p.min_observed_fraction}};
    for (const auto& [name, value] : reals)
      EXPECT_EQ(realDefault(command, name), value) << name;
    const std::vector<std::pair<const char*, long long>> integers{
        {"sparsity", p.sparsity}, {"overlap", p.overlap}, {"smoothing-iterations", p.smoothing_iterations},
        {"atoms", p.self_similar_atoms}, {"seed", static_cast<long long>(p.seed)}};
    for (const auto& [name, value] : integers)
      EXPECT_EQ(intDefault(command, name), value) << name;
    EXPECT_FALSE(optionOf(command, "grid").has_default);  // the dictionary's: p.grid_size 0
    EXPECT_EQ(p.grid_size, 0);
  };
  checkShared("fill-missing", MissingVerticesOptions());
  checkShared("fill-holes", HoleRepairOptions());
  checkShared("denoise", DenoiseOptions());
  EXPECT_EQ(realDefault("fill-holes", "hole-factor"), HoleRepairOptions().decision.quad_factor);
  const DenoiseOptions denoise;  // and the entry point's own options struct
  EXPECT_EQ(realDefault("denoise", "noise"), denoise.noise_sigma);
  EXPECT_EQ(realDefault("denoise", "error-factor"), denoise.error_factor);
  EXPECT_EQ(realDefault("denoise", "fidelity"), denoise.fidelity);
  EXPECT_EQ(intDefault("denoise", "base-iterations"), denoise.base_iterations);
  EXPECT_EQ(realDefault("denoise", "discrepancy"), denoise.discrepancy);
  EXPECT_EQ(realDefault("denoise", "quad-factor"), denoise.quad_length_factor);
  EXPECT_EQ(intDefault("denoise", "sparsity"), denoise.sparsity);
  EXPECT_EQ(realDefault("fill-missing", "mu"), MissingVerticesOptions().constraint_weight);
  EXPECT_EQ(realDefault("fill-holes", "mu"), HoleRepairOptions().constraint_weight);
  EXPECT_EQ(realDefault("fill-holes", "fit-scale"), HoleRepairOptions().fit_scale);

  const PatchCodecParameters codec;
  EXPECT_EQ(realDefault("compress", "quad-length"), codec.quad_length);
  EXPECT_EQ(realDefault("compress", "patch-scale"), codec.patch_scale);
  EXPECT_EQ(intDefault("compress", "overlap"), codec.overlap);
  EXPECT_EQ(intDefault("compress", "sparsity"), codec.coefficients);
  EXPECT_EQ(intDefault("compress", "coefficient-bits"), codec.coefficient_bits);
  EXPECT_EQ(intDefault("compress", "position-bits"), codec.position_bits);
  EXPECT_EQ(intDefault("compress", "subdivision"), codec.subdivision);
  EXPECT_EQ(intDefault("compress", "smoothing-iterations"), codec.smoothing_iterations);
  EXPECT_EQ(intDefault("compress", "location-bits"), codec.location_bits);
  EXPECT_EQ(realDefault("compress", "coverage-tolerance"), codec.coverage_tolerance);
  EXPECT_EQ(realDefault("compress", "coverage-budget"), codec.coverage_budget);
  EXPECT_EQ(realDefault("compress", "target-error"), codec.target_error);
  EXPECT_EQ(realDefault("compress", "atom-cost"), codec.atom_cost);
  EXPECT_EQ(static_cast<std::uint64_t>(intDefault("compress", "seed")), codec.seed);

  const PatchLayoutParameters layout;
  EXPECT_EQ(realDefault("quads", "quad-length"), layout.quad_length);
  EXPECT_EQ(intDefault("quads", "overlap"), layout.overlap);
  EXPECT_EQ(intDefault("quads", "smoothing-iterations"), layout.smoothing_iterations);
  EXPECT_EQ(static_cast<std::uint64_t>(intDefault("quads", "seed")), layout.seed);
  EXPECT_EQ(optionOf("quads", "smoothing").text_default, "laplacian");
  EXPECT_EQ(layout.smoothing, CoarseMeshEstimation::Method::Laplacian);

  const DictionaryLearningOptions learning;
  EXPECT_EQ(intDefault("learn", "atoms"), learning.num_atoms);
  EXPECT_EQ(intDefault("learn", "sparsity"), learning.sparsity);
  EXPECT_EQ(intDefault("learn", "batch"), learning.batch_size);
  EXPECT_EQ(static_cast<std::uint64_t>(intDefault("learn", "seed")), learning.seed);
  EXPECT_EQ(optionOf("learn", "iterations").note, "20 (ksvd), 3 (online)");  // computed in cmd_learn.cpp
  EXPECT_EQ(learning.iterations, 20);

  const CloudRepairParameters cloud;
  const CloudCompletionParameters completion;
  const OrganizedFillParameters organized;
  for (const char* command : {"denoise", "fill-holes"}) {
    SCOPED_TRACE(command);
    EXPECT_EQ(intDefault(command, "outlier-neighbours", "cloud"), cloud.outlier_neighbours);
    EXPECT_EQ(realDefault(command, "outlier-std", "cloud"), cloud.outlier_std);
    EXPECT_EQ(realDefault(command, "residual-outliers", "cloud"), cloud.residual_outlier_factor);
    EXPECT_EQ(realDefault(command, "noise", "cloud"), cloud.noise_sigma);
    EXPECT_EQ(realDefault(command, "bandwidth", "cloud"), cloud.bandwidth);
  }
  EXPECT_EQ(realDefault("fill-holes", "rim-width", "cloud"), completion.rim_width);
  EXPECT_EQ(static_cast<std::size_t>(intDefault("fill-holes", "max-hole-pixels", "cloud")), organized.max_hole_pixels);
  EXPECT_EQ(intDefault("fill-holes", "fit-ring", "cloud"), organized.fit_ring);
  EXPECT_FALSE(optionOf("fill-holes", "max-hole-diameter", "cloud").has_default);  // each fill's own
  EXPECT_EQ(completion.max_hole_diameter, 0.0);
}

// The getters return the table's default, check the table's range and words, and refuse (a
// programming error, std::logic_error) an option the command's table lacks, another kind, a
// literal default for an option whose default is the table's, or no value for a computed one.
TEST(CliOptions, GettersReadTheTable)
{
  const Arguments none({"in.ply", "-o", "out.ply"}, commandSpec("denoise"));
  EXPECT_EQ(none.getDouble("noise"), 0.0);
  EXPECT_EQ(none.getDouble("fidelity"), 0.05);
  EXPECT_EQ(none.getInt("base-iterations"), -1);
  EXPECT_EQ(none.getInt("seed"), 0);  // the repair's own, not the common 1
  EXPECT_EQ(none.getInt("grid", 7), 7);  // computed (the dictionary's): the caller's value when not given
  EXPECT_THROW(none.getInt("grid"), std::logic_error);
  EXPECT_THROW(none.getDouble("noise", 0.0), std::logic_error);
  EXPECT_THROW(none.getDouble("sparsity"), std::logic_error);   // an Integer
  EXPECT_THROW(none.getDouble("bandwidth"), std::logic_error);  // the cloud path's
  EXPECT_THROW(none.get("bogus"), std::logic_error);
  EXPECT_FALSE(none.takes("mu"));  // hidden: only refused
  EXPECT_TRUE(none.takes("fidelity"));
  EXPECT_EQ(Arguments({}, commandSpec("demo")).get("output"), "pcl_patchdict_demo");
  EXPECT_EQ(Arguments({"in.ply", "-o", "x.ply"}, commandSpec("fill-holes")).getWord("surface"), "auto");

  const auto usageError = [](const std::vector<std::string>& args, const std::string& command,
                             const std::function<void(const Arguments&)>& read) -> std::string {
    try {
      read(Arguments(args, commandSpec(command)));
    } catch (const UsageError& error) {
      return error.what();
    }
    return "(no error)";
  };
  EXPECT_EQ(usageError({"--grid", "0"}, "denoise", [](const Arguments& a) { a.getInt("grid", 0); }),
            "option --grid: 0 is out of range (2 to 256)");
  EXPECT_EQ(usageError({"--noise", "2"}, "denoise", [](const Arguments& a) { a.getDouble("noise"); }),
            "option --noise: 2 is out of range (0 to 1)");
  EXPECT_EQ(usageError({"--max-hole-diameter", "0"}, "fill-holes",
                       [](const Arguments& a) { a.getDouble("max-hole-diameter", 1.0); }),
            "(no error)");  // the mesh path: 0 fills none
  EXPECT_EQ(usageError({"--surface", "bumpy"}, "fill-holes", [](const Arguments& a) { a.getWord("surface"); }),
            "option --surface: 'bumpy' is not one of auto, smooth, relief");
  EXPECT_EQ(usageError({"--samples", "1e5"}, "eval", [](const Arguments& a) { a.getInt("samples"); }),
            "option --samples: '1e5' is not an integer");
}

// The help shows what the getters use: the default and the range.
TEST(CliOptions, HelpShowsDefaultsAndRanges)
{
  const std::string help = commandHelp("denoise");
  EXPECT_NE(help.find("Taubin iterations (-1 to 10000) [-1 (by the discrepancy principle)]"), std::string::npos)
      << help;
  EXPECT_NE(help.find("--grid N"), std::string::npos) << help;
  EXPECT_NE(help.find("(2 to 256) [the dictionary's (16 self-similar)]"), std::string::npos) << help;
  EXPECT_EQ(help.find("--mu"), std::string::npos) << help;
  EXPECT_EQ(rangeText(optionOf("fill-holes", "max-hole-diameter", "cloud")), "> 0");
  EXPECT_EQ(rangeText(optionOf("eval", "samples")), "1000 to 1e8");
  EXPECT_EQ(rangeText(optionOf("learn", "checkpoint-every")), "1 to 2^40");
  EXPECT_EQ(formatNumber(1e-9), "1e-9");
  EXPECT_EQ(defaultText(optionOf("compress", "subdivision")), "0 (grid / 2)");
}
