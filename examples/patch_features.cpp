// patch_features IN.pcd OUT.pdd — the paper's height-map patches of a scan as PCL features, and a
// dictionary of them: QuadFrameEstimation (seeds and reference frames on field-aligned quads) →
// HeightMapPatchExtractor (a pcl::Histogram<256> per seed: 16 × 16 heights, NaN where the scan
// has no points) → a dictionary learned from the histograms → their coding error → the scan's holes
// completed by SparsePatchInpainter.
#include <pcl_patchdict/cloud/sparse_patch_inpainter.h>
#include <pcl_patchdict/pcl/height_map_patch_extractor.h>
#include <pcl_patchdict/pcl/patch_histograms.h>
#include <pcl_patchdict/pcl/quad_frame_estimation.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>

#include <pcl/common/io.h>  // pcl::copyPointCloud
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>  // std::runtime_error, std::exception
#include <string>
#include <vector>

int main(int argc, char** argv)
{
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s IN.pcd OUT.pdd\n", argv[0]);
    return 2;
  }
  try {
    auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    if (pcl::io::loadPCDFile<pcl::PointXYZ>(argv[1], *cloud) < 0)
      throw std::runtime_error(std::string("cannot read the cloud ") + argv[1]);

    // 0. How fine the patches can be: binned heights need points in their bins. A 16 × 16 patch
    //    of side L = 20 point spacings has about 1.5 points a bin (a dense scan can take the
    //    default L, 0.03 of its largest bounding-box side: setQuadLength(0)).
    pcl::search::KdTree<pcl::PointXYZ> tree;
    tree.setInputCloud(cloud);
    pcl::Indices nearest(2);
    std::vector<float> squared(2);
    double spacing = 0.0;
    for (std::size_t i = 0; i < cloud->size(); ++i) {
      tree.nearestKSearch((*cloud)[i], 2, nearest, squared);  // the point itself, then its neighbour
      spacing += std::sqrt(squared[1]) / static_cast<double>(cloud->size());
    }

    // 1. Where the patches go: the cloud's Poisson surface, field-aligned quads of side L, 1 + 4
    //    seeds per quad, a frame each (Z the surface normal, X along the quads, consistent across
    //    the surface).
    pcl::patchdict::QuadFrameEstimation<pcl::PointXYZ> layout;
    layout.setInputCloud(cloud);
    layout.setQuadLength(20.0 * spacing);
    auto seeds = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
    auto frames = std::make_shared<pcl::PointCloud<pcl::ReferenceFrame>>();
    layout.compute(*seeds, *frames);
    const double quad_length = layout.getReport().quad_length;

    // 2. The patches: the cloud's points around each seed, binned on a 16 × 16 grid of side L in
    //    its frame (radius r = L / √2), as a pcl::Feature with local reference frames.
    auto seed_points = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    pcl::copyPointCloud(*seeds, *seed_points);
    pcl::patchdict::HeightMapPatchExtractor<pcl::PointXYZ, pcl::Histogram<256>> extractor;
    extractor.setInputCloud(seed_points);
    extractor.setInputReferenceFrames(frames);
    extractor.setSearchSurface(cloud);
    extractor.setRadiusSearch(quad_length / std::sqrt(2.0));
    pcl::PointCloud<pcl::Histogram<256>> patches;
    extractor.compute(patches);

    // 3. A dictionary of 64 atoms learned from them (NaN bins are unobserved), saved as .pdd, and
    //    how well 6 atoms a patch describe the bins the scan observed.
    pcl::patchdict::DictionaryLearningOptions options;
    options.num_atoms = 64;
    options.sparsity = 6;
    options.iterations = 10;
    const auto dictionary = pcl::patchdict::learnPatchDictionary(patches, options);
    savePatchDictionary(argv[2], dictionary);
    const auto codes = pcl::patchdict::encodePatches(dictionary, patches, {6, 0.0});
    pcl::PointCloud<pcl::Histogram<256>> decoded;  // every bin, the unobserved ones filled
    pcl::patchdict::decodePatches(dictionary, codes, decoded);
    const double rmse = pcl::patchdict::observedRMSE(decoded, patches);

    // 4. The patches back onto the scan: its holes filled by the geometric repair, then the new
    //    points moved onto patches completed by masked OMP — if, measured on this scan, the
    //    dictionary predicts hidden surface better than a smooth fill (a relief); otherwise the
    //    geometric fill stands, point for point.
    pcl::patchdict::SparsePatchInpainter<pcl::PointXYZ> inpainter;
    inpainter.setInputCloud(cloud);
    inpainter.setMode(pcl::patchdict::SparsePatchInpainter<pcl::PointXYZ>::Mode::Complete);
    pcl::PointCloud<pcl::PointXYZ> repaired;
    inpainter.process(repaired);
    const auto& decision = inpainter.getPatchReport();
    std::printf("hole completion: %zu points added, patches %s%s%s\n", repaired.size() - inpainter.getKeptIndices().size(),
                toString(decision.outcome), decision.reason.empty() ? "" : ": ", decision.reason.c_str());

    std::size_t observed = 0;
    for (const auto& patch : patches)
      for (const float height : patch.histogram)
        observed += std::isfinite(height);
    std::printf("%zu points, %zu seeds (L = %.4g), %zu patches, %.1f %% of their bins observed; "
                "%d atoms -> %s; coding RMSE %.3g (%.2f %% of L)\n",
                cloud->size(), seeds->size(), quad_length, patches.size(),
                100.0 * static_cast<double>(observed) / (256.0 * static_cast<double>(patches.size())),
                options.num_atoms, argv[2], rmse, 100.0 * rmse / quad_length);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "patch_features: %s\n", e.what());
    return 1;
  }
}
