#include "proto/draco_codec.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "body/body_model.h"
#include "core/garment_obj.h"
#include "core/random.h"
#include "core/test_support.h"
#include "draco/compression/expert_encode.h"
#include "draco/mesh/mesh.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace fitbase::proto {
namespace {

using ::fitbase::core::StatusIs;

// A mesh's positions as float32 meters, V x 3 row-major.
std::vector<float> MetersOf(const core::Positions& data_units) {
  std::vector<float> xyz(data_units.size());
  for (Eigen::Index i = 0; i < data_units.size(); ++i) {
    xyz[i] = static_cast<float>(data_units.data()[i] * body::kMetersPerDataUnit);
  }
  return xyz;
}

// A garment whose vertex order is spatially coherent (consecutive vertices ~3 cm apart), as
// the order of the hm08 body is; 3,763 vertices.
std::vector<float> CoherentGarment() {
  auto garment = core::ReadGarmentObj(core::TestDataDir() /
                                      "clothes/male_worksuit01/male_worksuit01.obj");
  EXPECT_TRUE(garment.ok()) << garment.status();
  return garment.ok() ? MetersOf(garment->mesh.positions) : std::vector<float>{};
}

// The hm08 body: the first 13,380 vertices of base.obj.
std::vector<float> Body() {
  auto base = core::ReadGarmentObj(core::TestDataDir() / "base.obj");
  EXPECT_TRUE(base.ok()) << base.status();
  if (!base.ok()) return {};
  return MetersOf(base->mesh.positions.topRows(body::kBodyVertexCount));
}

// `count` points uniform in a 1 m cube, in no spatial order.
std::vector<float> RandomCloud(int count, uint64_t seed) {
  core::Random random(seed, 0);
  std::vector<float> xyz(3 * count);
  for (float& v : xyz) v = static_cast<float>(random.Uniform(-0.5, 0.5));
  return xyz;
}

// The largest |decoded - input| over all coordinates, or infinity on a size mismatch.
double MaxError(const std::vector<float>& decoded, const std::vector<float>& input) {
  if (decoded.size() != input.size()) return std::numeric_limits<double>::infinity();
  double worst = 0;
  for (size_t i = 0; i < input.size(); ++i) {
    worst = std::max(worst, std::abs(static_cast<double>(decoded[i]) - input[i]));
  }
  return worst;
}

// Draco bytes of `xyz` as a point cloud with `method`, or, if `faces` is not empty, as a
// mesh with those triangles: what other encoders may send.
std::string EncodeWithDraco(const std::vector<float>& xyz, int method,
                            const std::vector<int>& faces = {}) {
  const int count = static_cast<int>(xyz.size() / 3);
  std::unique_ptr<draco::PointCloud> geometry;
  if (faces.empty()) {
    geometry = std::make_unique<draco::PointCloud>();
  } else {
    auto mesh = std::make_unique<draco::Mesh>();
    for (size_t f = 0; f < faces.size(); f += 3) {
      mesh->AddFace({draco::PointIndex(faces[f]), draco::PointIndex(faces[f + 1]),
                     draco::PointIndex(faces[f + 2])});
    }
    geometry = std::move(mesh);
  }
  geometry->set_num_points(count);
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false,
                3 * sizeof(float), 0);
  const int id = geometry->AddAttribute(position, true, count);
  geometry->attribute(id)->buffer()->Write(0, xyz.data(), xyz.size() * sizeof(float));
  std::unique_ptr<draco::ExpertEncoder> encoder =
      faces.empty() ? std::make_unique<draco::ExpertEncoder>(*geometry)
                    : std::make_unique<draco::ExpertEncoder>(
                          static_cast<const draco::Mesh&>(*geometry));
  encoder->SetEncodingMethod(method);
  encoder->SetAttributeQuantization(id, 11);
  draco::EncoderBuffer buffer;
  EXPECT_TRUE(encoder->EncodeToBuffer(&buffer).ok());
  return std::string(buffer.data(), buffer.size());
}

v1::EncodedPositions DracoMessage(uint32_t vertex_count, std::string data) {
  v1::EncodedPositions message;
  message.set_vertex_count(vertex_count);
  message.mutable_draco()->set_data(std::move(data));
  return message;
}

TEST(DracoCodecTest, RawRoundTripIsExact) {
  const std::vector<float> xyz = {0.1f, -0.2f, 0.3f, 1.0f / 3.0f, 1e-7f, -1.5f};
  const v1::EncodedPositions message = EncodeRawPositions(xyz);
  EXPECT_EQ(message.vertex_count(), 2u);
  ASSERT_TRUE(message.has_raw());
  auto decoded = DecodePositions(message, 2);
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  EXPECT_EQ(*decoded, xyz);
}

TEST(DracoCodecTest, DracoKeepsEveryPointInVertexOrderWithinTheStatedError) {
  // Spatially incoherent order: a decoder that reordered points would be off by decimeters.
  const std::vector<float> xyz = RandomCloud(5000, 1);
  for (int bits : {8, 11, 14, 20}) {
    auto message = EncodeDracoPositions(xyz, {.quantization_bits = bits});
    ASSERT_TRUE(message.ok()) << message.status();
    EXPECT_EQ(message->vertex_count(), 5000u);
    EXPECT_EQ(message->draco().quantization_bits(), static_cast<uint32_t>(bits));
    // The longest side is just under 1 m: the bound is half a step.
    const double half_step = 0.5 / ((1 << bits) - 1);
    EXPECT_GT(message->draco().max_error_m(), 0.99 * half_step) << bits;
    EXPECT_LT(message->draco().max_error_m(), 1.01 * half_step + 1e-6) << bits;
    auto decoded = DecodePositions(*message, 5000);
    ASSERT_TRUE(decoded.ok()) << decoded.status();
    EXPECT_LE(MaxError(*decoded, xyz), message->draco().max_error_m()) << bits;
  }
}

TEST(DracoCodecTest, DefaultIsFourTimesSmallerThanRawOnCoherentMeshesWithinHalfAMillimeter) {
  for (const std::vector<float>& xyz : {CoherentGarment(), Body()}) {
    ASSERT_FALSE(xyz.empty());
    const int64_t count = static_cast<int64_t>(xyz.size() / 3);
    auto message = EncodeDracoPositions(xyz);
    ASSERT_TRUE(message.ok()) << message.status();
    EXPECT_EQ(message->draco().quantization_bits(), 11u);
    const size_t raw_bytes = EncodeRawPositions(xyz).ByteSizeLong();
    EXPECT_GE(raw_bytes, 12 * count);
    EXPECT_GE(raw_bytes, 4 * message->ByteSizeLong()) << count << " vertices";
    EXPECT_LT(message->draco().max_error_m(), 0.5e-3);
    auto decoded = DecodePositions(*message, count);
    ASSERT_TRUE(decoded.ok()) << decoded.status();
    EXPECT_LE(MaxError(*decoded, xyz), message->draco().max_error_m());
  }
}

TEST(DracoCodecTest, EncodingRefusesBadInput) {
  const std::vector<float> xyz = RandomCloud(10, 2);
  EXPECT_THAT(EncodeDracoPositions(xyz, {.quantization_bits = 0}),
              StatusIs(absl::StatusCode::kInvalidArgument, "quantization_bits is 0"));
  EXPECT_THAT(EncodeDracoPositions(xyz, {.quantization_bits = 31}),
              StatusIs(absl::StatusCode::kInvalidArgument, "quantization_bits is 31"));
  EXPECT_THAT(EncodeDracoPositions(std::span<const float>(xyz).first(29)),
              StatusIs(absl::StatusCode::kInvalidArgument, "not 3 per vertex"));
  EXPECT_THAT(EncodeDracoPositions({}),
              StatusIs(absl::StatusCode::kInvalidArgument, "0 vertices"));
  std::vector<float> bad = xyz;
  bad[3 * 7 + 1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THAT(EncodeDracoPositions(bad),
              StatusIs(absl::StatusCode::kInvalidArgument, "vertex 7 has a non-finite"));
}

TEST(DracoCodecTest, DecodingNamesEachProblem) {
  const std::vector<float> xyz = RandomCloud(10, 3);
  const v1::EncodedPositions raw = EncodeRawPositions(xyz);
  EXPECT_THAT(DecodePositions(raw, 11),
              StatusIs(absl::StatusCode::kInvalidArgument, "vertex_count 10; expected 11"));
  v1::EncodedPositions none;
  none.set_vertex_count(10);
  EXPECT_THAT(DecodePositions(none, 10),
              StatusIs(absl::StatusCode::kInvalidArgument, "neither raw nor draco"));
  v1::EncodedPositions short_raw = raw;
  short_raw.mutable_raw()->mutable_xyz()->RemoveLast();
  EXPECT_THAT(DecodePositions(short_raw, 10),
              StatusIs(absl::StatusCode::kInvalidArgument, "29 values for 10 vertices"));
  v1::EncodedPositions infinite = raw;
  infinite.mutable_raw()->set_xyz(14, std::numeric_limits<float>::infinity());
  EXPECT_THAT(DecodePositions(infinite, 10),
              StatusIs(absl::StatusCode::kInvalidArgument, "raw positions: vertex 4"));

  auto draco = EncodeDracoPositions(xyz);
  ASSERT_TRUE(draco.ok());
  v1::EncodedPositions miscounted = *draco;
  miscounted.set_vertex_count(9);
  EXPECT_THAT(DecodePositions(miscounted, 9),
              StatusIs(absl::StatusCode::kInvalidArgument, "hold 10 points; expected 9"));
  EXPECT_THAT(DecodePositions(DracoMessage(10, "not draco at all"), 10),
              StatusIs(absl::StatusCode::kInvalidArgument, "not a Draco bitstream"));
  EXPECT_THAT(DecodePositions(DracoMessage(10, ""), 10),
              StatusIs(absl::StatusCode::kInvalidArgument, "not a Draco bitstream"));
  EXPECT_THAT(DecodePositions(DracoMessage(10, draco->draco().data().substr(0, 12)), 10),
              StatusIs(absl::StatusCode::kInvalidArgument, "end before their point count"));
  EXPECT_THAT(DecodePositions(DracoMessage(10, draco->draco().data().substr(0, 40)), 10),
              StatusIs(absl::StatusCode::kInvalidArgument, "do not decode"));
}

TEST(DracoCodecTest, DecodingRefusesEncodingsThatReorderPoints) {
  const std::vector<float> xyz = RandomCloud(500, 4);
  EXPECT_THAT(
      DecodePositions(DracoMessage(500, EncodeWithDraco(xyz, draco::POINT_CLOUD_KD_TREE_ENCODING)),
                      500),
      StatusIs(absl::StatusCode::kInvalidArgument, "kd-tree"));
  // A strip of triangles over the points, in both of Draco's mesh encodings.
  std::vector<int> faces;
  for (int v = 0; v + 2 < 500; ++v) faces.insert(faces.end(), {v, v + 1, v + 2});
  for (int method : {draco::MESH_SEQUENTIAL_ENCODING, draco::MESH_EDGEBREAKER_ENCODING}) {
    EXPECT_THAT(DecodePositions(DracoMessage(500, EncodeWithDraco(xyz, method, faces)), 500),
                StatusIs(absl::StatusCode::kInvalidArgument, "are a mesh"));
  }
  // Our own payload is what a partner's sequential encoder produces.
  auto decoded = DecodePositions(
      DracoMessage(500, EncodeWithDraco(xyz, draco::POINT_CLOUD_SEQUENTIAL_ENCODING)), 500);
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  EXPECT_LT(MaxError(*decoded, xyz), 0.5e-3);
}

TEST(DracoCodecTest, AForgedPointCountIsRefusedBeforeDecoding) {
  auto draco = EncodeDracoPositions(RandomCloud(10, 5));
  ASSERT_TRUE(draco.ok());
  // The int32 point count follows the 11-byte header; claim 2^31 - 1 points.
  std::string data = draco->draco().data();
  const int32_t huge = std::numeric_limits<int32_t>::max();
  std::memcpy(data.data() + 11, &huge, sizeof(huge));
  EXPECT_THAT(DecodePositions(DracoMessage(10, data), 10),
              StatusIs(absl::StatusCode::kInvalidArgument, "hold 2147483647 points"));
  // Metadata would hide the count behind a block of its own: flag 0x8000 of the little-endian
  // uint16 at bytes 9..10.
  data = draco->draco().data();
  data[10] = static_cast<char>(data[10] | 0x80);
  EXPECT_THAT(DecodePositions(DracoMessage(10, data), 10),
              StatusIs(absl::StatusCode::kInvalidArgument, "metadata"));
}

// Whatever the bytes, decoding returns an error or exactly the expected count of finite values.
void ExpectSafe(const std::string& data, int64_t count) {
  auto decoded = DecodePositions(DracoMessage(static_cast<uint32_t>(count), data), count);
  if (decoded.ok()) {
    ASSERT_EQ(decoded->size(), static_cast<size_t>(3 * count));
    for (float v : *decoded) ASSERT_TRUE(std::isfinite(v));
  } else {
    ASSERT_EQ(decoded.status().code(), absl::StatusCode::kInvalidArgument) << decoded.status();
  }
}

TEST(DracoCodecTest, CorruptPayloadsNeverCrash) {
  const std::vector<float> xyz = RandomCloud(200, 6);
  auto draco = EncodeDracoPositions(xyz);
  ASSERT_TRUE(draco.ok());
  const std::string& valid = draco->draco().data();
  for (size_t length = 0; length < valid.size(); ++length) {
    ExpectSafe(valid.substr(0, length), 200);
  }
  core::Random random(7, 0);
  auto byte = [&random] { return static_cast<char>(random.Uniform01() * 256); };
  for (int trial = 0; trial < 2000; ++trial) {
    std::string flipped = valid;
    const int flips = 1 + static_cast<int>(random.Uniform01() * 4);
    for (int f = 0; f < flips; ++f) {
      flipped[static_cast<size_t>(random.Uniform01() * flipped.size())] = byte();
    }
    ExpectSafe(flipped, 200);
    // Random bodies behind a valid header and point count reach Draco's attribute decoder.
    std::string noise = valid.substr(0, 15);
    const int length = static_cast<int>(random.Uniform01() * 400);
    for (int i = 0; i < length; ++i) noise.push_back(byte());
    ExpectSafe(noise, 200);
  }
}

}  // namespace
}  // namespace fitbase::proto
