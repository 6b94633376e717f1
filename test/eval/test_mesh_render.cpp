// The software renderer and the PNG encoder: known pixel counts, depth order, shading, edges only
// when asked, close-up windows, the error colour map, panels and text, a PNG that zlib inflates
// back to the exact pixels.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict_eval/mesh_render.h>
#include <pcl_patchdict_eval/picture_layout.h>
#include <pcl_patchdict_eval/repair_figure.h>
#include <pcl_patchdict/io/png_writer.h>

#include <gtest/gtest.h>

#include <cmath>

#include <zlib.h>

using namespace pcl::patchdict;

namespace {

std::uint32_t bigEndian(const std::string& s, std::size_t at)
{
  return (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at])) << 24) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 1])) << 16) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 2])) << 8) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 3]));
}

using Polygons = std::vector<std::vector<std::int32_t>>;

RGBColour pixelAt(const std::vector<std::uint8_t>& pixels, int width, int x, int y)
{
  const std::size_t k = 3 * (static_cast<std::size_t>(y) * width + x);
  return {pixels[k], pixels[k + 1], pixels[k + 2]};
}

int brightness(const RGBColour& c) { return c[0] + c[1] + c[2]; }

/** A unit square in the plane z = 0 centred at (cx, cy), tilted by `angle` about the y axis. */
void addSquare(std::vector<Eigen::Vector3d>& vertices, Polygons& faces, double cx, double cy, double angle)
{
  const std::int32_t first = static_cast<std::int32_t>(vertices.size());
  for (const auto& corner : {Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(0.5, -0.5), Eigen::Vector2d(0.5, 0.5),
                             Eigen::Vector2d(-0.5, 0.5)})
    vertices.emplace_back(cx + corner.x() * std::cos(angle), cy + corner.y(), corner.x() * std::sin(angle));
  faces.push_back({first, first + 1, first + 2, first + 3});
}

}  // namespace

TEST(MeshRender, ASquareFacingTheCameraFillsItsShareOfTheImage)
{
  const std::vector<Eigen::Vector3d> vertices{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<std::vector<std::int32_t>> faces{{0, 1, 2, 3}};
  RenderOptions options;
  options.width = options.height = 200;
  options.light = Eigen::Vector3d(0.0, 0.0, 1.0);  // head-on, no highlight: the full shade
  options.specular = 0.0;
  const auto pixels = renderPolygons(vertices, faces, {{{200, 100, 50}}}, options);
  ASSERT_EQ(pixels.size(), 200u * 200u * 3u);
  std::size_t coloured = 0;
  for (std::size_t p = 0; p < pixels.size(); p += 3) {
    if (pixels[p] != 255) {
      ++coloured;
      // Facing the camera and the light: the colour itself.
      EXPECT_EQ(pixels[p], 200);
      EXPECT_EQ(pixels[p + 1], 100);
      EXPECT_EQ(pixels[p + 2], 50);
    }
  }
  // The square is scaled to 90 % of the image: 180 × 180 pixels.
  EXPECT_NEAR(static_cast<double>(coloured), 180.0 * 180.0, 2.0 * 180.0);
}

TEST(MeshRender, TheNearerFaceHidesTheFartherOne)
{
  // Two overlapping squares; the camera looks along −z, so z = 1 is in front.
  const std::vector<Eigen::Vector3d> vertices{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                              {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  RenderOptions options;
  options.width = options.height = 64;
  options.light = Eigen::Vector3d(0.0, 0.0, 1.0);  // head-on: the colours themselves
  options.specular = 0.0;
  for (const bool front_first : {true, false}) {
    const std::vector<std::vector<std::int32_t>> faces =
        front_first ? std::vector<std::vector<std::int32_t>>{{4, 5, 6, 7}, {0, 1, 2, 3}}
                    : std::vector<std::vector<std::int32_t>>{{0, 1, 2, 3}, {4, 5, 6, 7}};
    const std::vector<std::array<std::uint8_t, 3>> colours =
        front_first ? std::vector<std::array<std::uint8_t, 3>>{{0, 255, 0}, {255, 0, 0}}
                    : std::vector<std::array<std::uint8_t, 3>>{{255, 0, 0}, {0, 255, 0}};
    const auto pixels = renderPolygons(vertices, faces, colours, options);
    const std::size_t centre = 3 * (32 * 64 + 32);
    EXPECT_EQ(pixels[centre], 0);  // green (the front square) whatever the drawing order
    EXPECT_EQ(pixels[centre + 1], 255);
  }
  EXPECT_THROW(renderPolygons(vertices, {{0, 1, 9}}, {}, options), Error);
  EXPECT_THROW(renderPolygons(vertices, {{0, 1, 2}}, {{{1, 2, 3}}, {{1, 2, 3}}}, options), Error);
}

TEST(PngWriter, RGBImageInflatesBackToItsPixels)
{
  const int w = 37, h = 11;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < pixels.size(); ++i)
    pixels[i] = static_cast<std::uint8_t>((i * 7919) % 251);
  const std::string png = encodeRGBPNG(w, h, pixels);
  ASSERT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // IHDR: width, height, depth 8, colour type 2.
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(bigEndian(png, 16), static_cast<std::uint32_t>(w));
  EXPECT_EQ(bigEndian(png, 20), static_cast<std::uint32_t>(h));
  EXPECT_EQ(png[24], 8);
  EXPECT_EQ(png[25], 2);
  // IDAT follows IHDR (8 + 25 bytes in); inflate it and compare the scanlines.
  const std::size_t idat = 8 + 25;
  ASSERT_EQ(png.substr(idat + 4, 4), "IDAT");
  const std::uint32_t length = bigEndian(png, idat);
  std::vector<unsigned char> raw(static_cast<std::size_t>(h) * (3 * w + 1));
  uLongf raw_size = static_cast<uLongf>(raw.size());
  ASSERT_EQ(uncompress(raw.data(), &raw_size, reinterpret_cast<const Bytef*>(png.data() + idat + 8), length), Z_OK);
  ASSERT_EQ(raw_size, raw.size());
  for (int y = 0; y < h; ++y) {
    EXPECT_EQ(raw[static_cast<std::size_t>(y) * (3 * w + 1)], 0);  // filter: none
    for (int x = 0; x < 3 * w; ++x)
      EXPECT_EQ(raw[static_cast<std::size_t>(y) * (3 * w + 1) + 1 + x], pixels[static_cast<std::size_t>(y) * 3 * w + x]);
  }
  EXPECT_THROW(encodeRGBPNG(w, h, std::vector<std::uint8_t>(5)), Error);
}

TEST(MeshRender, ShadingDarkensAFaceTiltedAwayFromTheLight)
{
  // Two squares side by side: the left one faces the camera, the right one is tilted by 60°.
  std::vector<Eigen::Vector3d> vertices;
  Polygons faces;
  addSquare(vertices, faces, -0.6, 0.0, 0.0);
  addSquare(vertices, faces, 0.6, 0.0, 1.05);
  RenderOptions options;
  options.width = options.height = 100;
  options.light = Eigen::Vector3d(0.0, 0.0, 1.0);
  options.specular = 0.0;
  auto pixels = renderPolygons(vertices, faces, {}, options);
  const RGBColour facing = pixelAt(pixels, 100, 28, 50), tilted = pixelAt(pixels, 100, 82, 50);
  EXPECT_EQ(brightness(facing), 3 * 215);  // the grey itself, fully lit
  EXPECT_LT(brightness(tilted), brightness(facing) - 100);
  // The default key light comes from the upper left: a face turned to the left is brighter than
  // one turned as much to the right.
  vertices.clear();
  faces.clear();
  addSquare(vertices, faces, -0.6, 0.0, 0.6);   // normal towards −x (the left)
  addSquare(vertices, faces, 0.6, 0.0, -0.6);   // normal towards +x
  pixels = renderPolygons(vertices, faces, {}, RenderOptions{});
  EXPECT_GT(brightness(pixelAt(pixels, 800, 250, 400)), brightness(pixelAt(pixels, 800, 550, 400)) + 60);
}

TEST(MeshRender, SmoothShadingVariesAcrossAFaceAndFlatDoesNot)
{
  // A roof of two faces meeting at a ridge along y: flat shading gives each face one colour, smooth
  // shading blends the normals towards the ridge.
  const std::vector<Eigen::Vector3d> vertices{{-1, -1, 0}, {0, -1, 0.5}, {0, 1, 0.5}, {-1, 1, 0}, {1, -1, 0}, {1, 1, 0}};
  const Polygons faces{{0, 1, 2, 3}, {1, 4, 5, 2}};
  RenderOptions options;
  options.width = options.height = 100;
  options.specular = 0.0;
  options.smooth_shading = false;
  auto pixels = renderPolygons(vertices, faces, {}, options);
  EXPECT_EQ(pixelAt(pixels, 100, 10, 50), pixelAt(pixels, 100, 45, 50));
  options.smooth_shading = true;
  pixels = renderPolygons(vertices, faces, {}, options);
  EXPECT_NE(pixelAt(pixels, 100, 10, 50), pixelAt(pixels, 100, 45, 50));
}

TEST(MeshRender, EdgesAreDrawnOnlyWhenAsked)
{
  // A grid of 4 × 4 squares, flat and head-on lit: without edges every covered pixel has one colour.
  std::vector<Eigen::Vector3d> vertices;
  Polygons faces;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      addSquare(vertices, faces, i, j, 0.0);
  RenderOptions options;
  options.width = options.height = 120;
  options.light = Eigen::Vector3d(0.0, 0.0, 1.0);
  options.specular = 0.0;
  const auto count = [&](const std::vector<std::uint8_t>& pixels, const RGBColour& colour) {
    std::size_t n = 0;
    for (int y = 0; y < 120; ++y)
      for (int x = 0; x < 120; ++x)
        n += pixelAt(pixels, 120, x, y) == colour;
    return n;
  };
  const auto plain = renderPolygons(vertices, faces, {}, options);
  EXPECT_EQ(count(plain, RGBColour{215, 215, 215}) + count(plain, options.background), 120u * 120u);
  options.draw_edges = true;
  const auto edged = renderPolygons(vertices, faces, {}, options);
  EXPECT_GT(count(edged, options.edge_colour), 5u * 100u);  // 5 lines each way across ~108 pixels
}

TEST(MeshRender, ACloseUpWindowMapsItsCentreToTheImageCentre)
{
  // A big square and, far from its centre, a small one of side 0.02 at (3, 4): a window of radius
  // 0.02 around the small square shows it across the middle half of the image.
  std::vector<Eigen::Vector3d> vertices;
  Polygons faces;
  addSquare(vertices, faces, 0.0, 0.0, 0.0);
  const std::int32_t first = static_cast<std::int32_t>(vertices.size());
  for (const auto& corner : {Eigen::Vector2d(-0.01, -0.01), Eigen::Vector2d(0.01, -0.01), Eigen::Vector2d(0.01, 0.01),
                             Eigen::Vector2d(-0.01, 0.01)})
    vertices.emplace_back(3.0 + corner.x(), 4.0 + corner.y(), 0.0);
  faces.push_back({first, first + 1, first + 2, first + 3});
  RenderOptions options;
  options.width = options.height = 200;
  options.window_centre = Eigen::Vector3d(3.0, 4.0, 0.0);
  options.window_radius = 0.02;
  const std::vector<RGBColour> colours{{0, 0, 255}, {255, 0, 0}};
  const auto pixels = renderPolygons(vertices, faces, colours, options);
  EXPECT_GT(pixelAt(pixels, 200, 100, 100)[0], 100);  // red: the small square
  EXPECT_EQ(pixelAt(pixels, 200, 100, 100)[2], pixelAt(pixels, 200, 100, 100)[1]);
  EXPECT_GT(pixelAt(pixels, 200, 55, 145)[0], 100);   // just inside its corner (50 … 150)
  EXPECT_EQ(pixelAt(pixels, 200, 45, 100), options.background);
  EXPECT_EQ(pixelAt(pixels, 200, 100, 155), options.background);
  options.window_radius = -1.0;
  EXPECT_THROW(renderPolygons(vertices, faces, colours, options), Error);
  options.window_radius = 0.02;
  options.per_vertex_colours = true;  // two colours for eight vertices
  EXPECT_THROW(renderPolygons(vertices, faces, colours, options), Error);
}

TEST(MeshRender, ErrorColourMapRunsFromPaleBlueGreyThroughYellowToRed)
{
  const RGBColour low = errorColour(0.0), middle = errorColour(0.5), high = errorColour(1.0);
  EXPECT_EQ(errorColour(-3.0), low);  // clamped
  EXPECT_EQ(errorColour(7.0), high);
  // Low: light and bluish grey, not saturated blue; middle: yellow; high: red.
  EXPECT_GT(low[0], 150);
  EXPECT_GT(low[2], low[0]);
  EXPECT_LT(low[2] - low[0], 60);
  EXPECT_GT(middle[0], 200);
  EXPECT_GT(middle[1], 160);
  EXPECT_LT(middle[2], 100);
  EXPECT_GT(high[0], 180);
  EXPECT_LT(high[1], 80);
  EXPECT_LT(high[2], 80);
  // The map never turns back: each colour is farther from the low end than the one before.
  double previous = -1.0;
  for (int i = 0; i <= 20; ++i) {
    const RGBColour c = errorColour(i / 20.0);
    const double distance = std::hypot(c[0] - low[0], c[1] - low[1], c[2] - low[2]);
    EXPECT_GT(distance, previous) << i;
    previous = distance;
  }
}

TEST(PictureLayout, PanelsSitSideBySideUnderTheirLabels)
{
  RGBImage red = blankImage(40, 30, {255, 0, 0}), blue = blankImage(40, 30, {0, 0, 255});
  const RGBImage grid = panelGrid({red, blue, red}, {"A", "B", "C"}, 2);
  EXPECT_GT(grid.width, 2 * 40);
  EXPECT_LT(grid.width, 2 * 40 + 60);
  EXPECT_GT(grid.height, 2 * 30);
  EXPECT_EQ(grid.pixels.size(), static_cast<std::size_t>(grid.width) * grid.height * 3);
  std::size_t dark = 0, red_pixels = 0, blue_pixels = 0;
  for (std::size_t p = 0; p < grid.pixels.size(); p += 3) {
    const RGBColour c{grid.pixels[p], grid.pixels[p + 1], grid.pixels[p + 2]};
    dark += c == RGBColour{30, 30, 30};
    red_pixels += c == RGBColour{255, 0, 0};
    blue_pixels += c == RGBColour{0, 0, 255};
  }
  EXPECT_EQ(red_pixels, 2u * 40u * 30u);
  EXPECT_EQ(blue_pixels, 40u * 30u);
  EXPECT_GT(dark, 3u * 10u);  // three letters drawn
  EXPECT_EQ(textWidth("AB", 2), 2 * (12 - 1));
  EXPECT_THROW(panelGrid({red, blankImage(10, 10)}, {}, 2), Error);
  EXPECT_THROW(panelGrid({red}, {"A", "B"}, 2), Error);
  const RGBImage barred = withColourBar(red, "error", ">=1");
  EXPECT_EQ(barred.width, red.width);
  EXPECT_GT(barred.height, red.height);
}

TEST(RepairFigure, TheCloseUpFramesTheLargestAddedRegion)
{
  // A 20 × 20 grid of squares as triangles; the "added" faces are one square at (2, 2) and a block
  // of 3 × 3 squares around (12.5, 12.5).
  TriangleMesh mesh;
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i)
      mesh.vertices.emplace_back(i, j, 0.0);
  std::vector<Face> kept, added;
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) {
      const std::int32_t v = j * 21 + i;
      const bool add = (i == 2 && j == 2) || (i >= 11 && i <= 13 && j >= 11 && j <= 13);
      auto& list = add ? added : kept;
      list.push_back({v, v + 1, v + 22});
      list.push_back({v, v + 22, v + 21});
    }
  mesh.faces = kept;
  const std::size_t first_new = mesh.faces.size();
  mesh.faces.insert(mesh.faces.end(), added.begin(), added.end());
  CloseUpWindow window;
  ASSERT_TRUE(windowAroundNewFaces(mesh, first_new, window));
  EXPECT_NEAR(window.centre.x(), 12.5, 1e-9);
  EXPECT_NEAR(window.centre.y(), 12.5, 1e-9);
  EXPECT_NEAR(window.radius, 1.6 * std::sqrt(2.0 * 1.5 * 1.5), 1e-9);  // corner to centre
  EXPECT_NEAR(std::abs(window.view_direction.z()), 1.0, 1e-9);
  EXPECT_FALSE(windowAroundNewFaces(mesh, mesh.faces.size(), window));
  EXPECT_THROW(windowAround(mesh, Eigen::Vector3d::Zero(), 0.0), Error);
}
