// Mesh and heightmap image loading against files whose content is known by construction: the same
// wedge in four formats, and PGM images written byte by byte here.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "temp_dir.hpp"
#include "scene/heightmap_image.hpp"
#include "scene/mesh_loader.hpp"

namespace sear {
namespace {

using sear::test::TempDir;

namespace fs = std::filesystem;

const std::string kMeshes = std::string(SEAR_TEST_DATA) + "/meshes/";

// Sum of the signed volumes of the tetrahedra (origin, a, b, c): the enclosed volume of a closed
// mesh, positive when its triangles wind counter-clockwise seen from outside.
double signed_volume(const TriangleMesh& mesh) {
  double six_v = 0;
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const Eigen::Vector3d a = mesh.vertices[mesh.indices[i]].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[mesh.indices[i + 1]].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[mesh.indices[i + 2]].cast<double>();
    six_v += a.dot(b.cross(c));
  }
  return six_v / 6.0;
}

void expect_box(const TriangleMesh& mesh, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  Eigen::Vector3f got_lo, got_hi;
  mesh_bounds(mesh, got_lo, got_hi);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(got_lo[k], lo[k], 1e-5) << "lower bound, axis " << k;
    EXPECT_NEAR(got_hi[k], hi[k], 1e-5) << "upper bound, axis " << k;
  }
}

// Loads one of the wedge files (x 0..4, y -1..1, z 0..1 rising with x, written Z-up) and checks
// that it arrives unrotated: 8 triangles, its box, and +4 m^3 (a 4 x 1 / 2 triangle times 2 wide).
void check_z_up_wedge(const std::string& file) {
  SCOPED_TRACE(file);
  const MeshLoadResult loaded = load_mesh(kMeshes + file, UpAxis::Z, 1.0);
  ASSERT_TRUE(loaded.error.empty()) << loaded.error;
  ASSERT_EQ(loaded.mesh.indices.size(), 8u * 3u);
  for (const auto index : loaded.mesh.indices) ASSERT_LT(index, loaded.mesh.vertices.size());
  expect_box(loaded.mesh, {0, -1, 0}, {4, 1, 1});
  EXPECT_NEAR(signed_volume(loaded.mesh), 4.0, 1e-5);
}

TEST(MeshLoader, WedgeObj) { check_z_up_wedge("wedge.obj"); }
TEST(MeshLoader, WedgeStl) { check_z_up_wedge("wedge.stl"); }
TEST(MeshLoader, WedgeColladaIgnoresItsOwnUpAxis) { check_z_up_wedge("wedge.dae"); }
TEST(MeshLoader, WedgeOgreXml) { check_z_up_wedge("wedge.mesh.xml"); }

TEST(MeshLoader, YUpFileIsTurnedSoItsYBecomesZ) {
  // Y-up to Z-up is (x, y, z) -> (x, -z, y): the file's x 0..4 stays, its z 0..1 becomes y -1..0,
  // its y -1..1 becomes z -1..1. A proper rotation, so the winding and the volume's sign stay.
  const MeshLoadResult loaded = load_mesh(kMeshes + "wedge.obj", UpAxis::Y, 1.0);
  ASSERT_TRUE(loaded.error.empty()) << loaded.error;
  ASSERT_EQ(loaded.mesh.indices.size(), 8u * 3u);
  expect_box(loaded.mesh, {0, -1, -1}, {4, 0, 1});
  EXPECT_NEAR(signed_volume(loaded.mesh), 4.0, 1e-5);
}

TEST(MeshLoader, ScaleMultipliesEveryLength) {
  const MeshLoadResult loaded = load_mesh(kMeshes + "wedge.obj", UpAxis::Z, 2.0);
  ASSERT_TRUE(loaded.error.empty()) << loaded.error;
  expect_box(loaded.mesh, {0, -2, 0}, {8, 2, 2});
  EXPECT_NEAR(signed_volume(loaded.mesh), 32.0, 1e-4);  // 2^3 times 4 m^3
}

TEST(MeshLoader, BrokenFileGivesAnError) {
  const MeshLoadResult loaded = load_mesh(kMeshes + "broken.obj", UpAxis::Z, 1.0);
  EXPECT_FALSE(loaded.error.empty());
  EXPECT_TRUE(loaded.mesh.indices.empty());
}

TEST(MeshLoader, MissingFileGivesAnError) {
  const MeshLoadResult loaded = load_mesh(kMeshes + "no_such_mesh.obj", UpAxis::Z, 1.0);
  EXPECT_FALSE(loaded.error.empty());
}


TEST(HeightmapImage, EightBitPgmKeepsRowOrderAndLevels) {
  TempDir dir;
  // 3 columns, 2 rows; row 0 is the first row in the file.
  const std::vector<std::uint8_t> bytes = {0, 128, 255, 10, 20, 30};
  const std::string path = dir.write("small.pgm", "P5\n3 2\n255\n" + std::string(bytes.begin(), bytes.end()));
  const HeightmapImage image = load_heightmap_image(path);
  ASSERT_TRUE(image.error.empty()) << image.error;
  EXPECT_EQ(image.columns, 3);
  EXPECT_EQ(image.rows, 2);
  ASSERT_EQ(image.levels.size(), bytes.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) EXPECT_NEAR(image.levels[i], bytes[i] / 255.0, 1e-12) << "sample " << i;
}

TEST(HeightmapImage, SixteenBitPgmIsReadMostSignificantByteFirst) {
  TempDir dir;
  // 2 columns, 2 rows of 16-bit samples; Netpbm stores each most significant byte first.
  const std::vector<unsigned> values = {0, 65535, 1000, 40000};
  std::vector<std::uint8_t> bytes;
  for (const unsigned v : values) {
    bytes.push_back(static_cast<std::uint8_t>(v >> 8));
    bytes.push_back(static_cast<std::uint8_t>(v & 0xffu));
  }
  const std::string path = dir.write("deep.pgm", "P5\n2 2\n65535\n" + std::string(bytes.begin(), bytes.end()));
  const HeightmapImage image = load_heightmap_image(path);
  ASSERT_TRUE(image.error.empty()) << image.error;
  EXPECT_EQ(image.columns, 2);
  EXPECT_EQ(image.rows, 2);
  ASSERT_EQ(image.levels.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    EXPECT_NEAR(image.levels[i], values[i] / 65535.0, 1e-12) << "sample " << i;
}

// Levels are samples over maxval, whatever maxval the file states (Netpbm allows 1..65535):
// a 10-bit map (maxval 1023, a comment in its header) and a 100-level 8-bit one.
TEST(HeightmapImage, PgmLevelsAreScaledByMaxval) {
  TempDir dir;
  const std::vector<unsigned> ten_bit = {0, 1023, 512, 100};
  std::string bytes;
  for (const unsigned v : ten_bit) bytes += {static_cast<char>(v >> 8), static_cast<char>(v & 0xffu)};
  const HeightmapImage deep = load_heightmap_image(dir.write("ten_bit.pgm", "P5\n# from a DEM\n2 2\n1023\n" + bytes));
  ASSERT_TRUE(deep.error.empty()) << deep.error;
  for (std::size_t i = 0; i < ten_bit.size(); ++i) EXPECT_NEAR(deep.levels[i], ten_bit[i] / 1023.0, 1e-12) << i;

  const HeightmapImage shallow =
      load_heightmap_image(dir.write("hundred.pgm", std::string("P5\n2 2\n100\n\x32\x64\x00\x19", 15)));
  ASSERT_TRUE(shallow.error.empty()) << shallow.error;
  ASSERT_EQ(shallow.levels.size(), 4u);
  EXPECT_NEAR(shallow.levels[0], 0.5, 1e-12);
  EXPECT_NEAR(shallow.levels[1], 1.0, 1e-12);
  EXPECT_NEAR(shallow.levels[2], 0.0, 1e-12);
  EXPECT_NEAR(shallow.levels[3], 0.25, 1e-12);
}

// stb 2.27 reads 16-bit colour PPM one byte short per sample and fills a truncated PGM with
// whatever memory held; the loader refuses both rather than make up terrain.
TEST(HeightmapImage, ColourAndTruncatedNetpbmFilesAreRefused) {
  TempDir dir;
  const HeightmapImage colour =
      load_heightmap_image(dir.write("colour.ppm", "P6\n2 2\n65535\n" + std::string(2 * 2 * 3 * 2, '\x10')));
  EXPECT_NE(colour.error.find("only binary greyscale Netpbm images (PGM, P5)"), std::string::npos) << colour.error;
  const HeightmapImage ascii = load_heightmap_image(dir.write("ascii.pgm", "P2\n2 2\n255\n0 1 2 3\n"));
  EXPECT_NE(ascii.error.find("only binary greyscale"), std::string::npos) << ascii.error;
  const HeightmapImage truncated =
      load_heightmap_image(dir.write("short.pgm", "P5\n4 4\n65535\n" + std::string(4 * 4 * 2 - 1, '\x10')));
  EXPECT_NE(truncated.error.find("shorter than its header says"), std::string::npos) << truncated.error;
  const HeightmapImage exact =
      load_heightmap_image(dir.write("exact.pgm", "P5\n4 4\n65535\n" + std::string(4 * 4 * 2, '\x10')));
  EXPECT_TRUE(exact.error.empty()) << exact.error;
  const HeightmapImage garbled = load_heightmap_image(dir.write("garbled.pgm", "P5\n4 four\n255\n"));
  EXPECT_NE(garbled.error.find("malformed PGM header"), std::string::npos) << garbled.error;
}

TEST(HeightmapImage, TooSmallImageIsAnError) {
  TempDir dir;
  const std::string path = dir.write("line.pgm", std::string("P5\n3 1\n255\n\x01\x02\x03", 14));
  const HeightmapImage image = load_heightmap_image(path);
  EXPECT_FALSE(image.error.empty());
}

TEST(HeightmapImage, MissingFileIsAnError) {
  const HeightmapImage image = load_heightmap_image(std::string(SEAR_TEST_DATA) + "/no_such_heightmap.png");
  EXPECT_FALSE(image.error.empty());
}

TEST(HeightmapImage, BundledHillsPngIs129By129) {
  const HeightmapImage image = load_heightmap_image(std::string(SEAR_ASSET_DIR) + "/heightmaps/hills.png");
  ASSERT_TRUE(image.error.empty()) << image.error;
  EXPECT_EQ(image.columns, 129);
  EXPECT_EQ(image.rows, 129);
  ASSERT_EQ(image.levels.size(), 129u * 129u);
  for (const double level : image.levels) {
    ASSERT_GE(level, 0.0);
    ASSERT_LE(level, 1.0);
  }
}

}  // namespace
}  // namespace sear
